"""The AIS stage at scale (issue 26 item 6): `usvtool ais read` of 1 M MarineCadastre rows and
`usvtool ais encounters` over the bundled 99 999-row extract, each a process of its own measured
by /usr/bin/time -v (wall clock, CPU time and peak resident memory; the fastest of --repeat
runs, as other processes share the machine).

The 1 M-row file is the bundled extract repeated ten times, copy k a day later than the extract
(BaseDateTime's date 2022-01-03 + k days, everything else unchanged), so that it holds ten days
of the same traffic rather than duplicates; it is written once into --work (plain CSV, some
100 MB). Targets: read <= 10 s and <= 1.5 GB; encounters <= 10 s.

Usage: python benchmarks/bench_ais.py [--work build/bench-ais] [--copies 10] [--repeat 3]
"""

from __future__ import annotations

import argparse
import gzip
import json
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXTRACT = ROOT / "charts" / "ais" / "AIS_2022_01_03_first99999.csv.gz"
USVTOOL = Path(sys.executable).with_name("usvtool")


def synthesise(path: Path, copies: int) -> int:
    """Write the extract repeated ``copies`` times, copy k shifted by k days; its data rows."""
    lines = gzip.decompress(EXTRACT.read_bytes()).decode().splitlines()
    header, rows = lines[0], lines[1:]
    with open(path, "w", encoding="utf-8") as f:
        f.write(header + "\n")
        for k in range(copies):
            day = f"2022-01-{3 + k:02d}T"
            f.write("\n".join(r.replace("2022-01-03T", day, 1) for r in rows) + "\n")
    return len(rows) * copies


def timed(args: list[str]) -> tuple[float, float, float, dict]:
    """(wall s, CPU s (user + system), peak RSS MiB, summary JSON) of one usvtool command run
    under /usr/bin/time -v."""
    done = subprocess.run(["/usr/bin/time", "-v", str(USVTOOL), *args], capture_output=True,
                          text=True, check=True)  # fmt: skip
    wall = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", done.stderr)
    hours, minutes, seconds = (float(g) if g else 0.0 for g in wall.groups())
    cpu = sum(float(re.search(rf"{kind} time \(seconds\): ([\d.]+)", done.stderr)[1])
              for kind in ("User", "System"))  # fmt: skip
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr)[1])
    return hours * 3600 + minutes * 60 + seconds, cpu, rss / 1024, json.loads(done.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--work", type=Path, default=ROOT / "build" / "bench-ais")
    ap.add_argument("--copies", type=int, default=10)
    ap.add_argument("--repeat", type=int, default=3, help="runs of each case; the fastest shown")
    args = ap.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    big = args.work / f"AIS_x{args.copies}.csv"
    if not big.exists():
        print(f"writing {big}: {synthesise(big, args.copies):,} rows", flush=True)
    cases = [("read 99 999 rows (gzip)", ["ais", "read", str(EXTRACT), "-o",
                                          str(args.work / "extract.parquet")]),
             (f"read {args.copies} x 99 999 rows", ["ais", "read", str(big), "-o",
                                                    str(args.work / "big.parquet")]),
             ("encounters over the 99 999 rows", ["ais", "encounters",
                                                  str(args.work / "extract.parquet"), "-o",
                                                  str(args.work / "encounters.csv")])]  # fmt: skip
    print(f"{'case':36s} {'wall':>8s} {'CPU':>8s} {'peak':>11s}  (fastest of {args.repeat}; "
          f"load {os.getloadavg()[0]:.1f})")  # fmt: skip
    for label, command in cases:
        wall, cpu, rss, summary = min(timed(command) for _ in range(args.repeat))
        figures = {k: summary[k] for k in ("fixes", "tracks", "encounters", "candidate_pairs",
                                           "samples") if k in summary}  # fmt: skip
        print(f"{label:36s} {wall:6.2f} s {cpu:6.2f} s {rss:7.1f} MiB  {figures}", flush=True)


if __name__ == "__main__":
    main()
