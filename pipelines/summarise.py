"""Tabulate the route summaries under a directory (CHART/ALGO.json) as CSV on stdout.

Columns: chart, algorithm, length_m, ratio to the chart's any-angle optimum, turns, mot,
fitness, planning_time_s (all runs), collision_free, attempt (the optimizer run that gave the
route; empty for the exact planners).
"""

import csv
import json
import sys
from pathlib import Path

FIELDS = ["chart", "algorithm", "length_m", "length_ratio", "turns", "mot", "fitness",
          "planning_time_s", "collision_free", "attempt"]  # fmt: skip


def main(root: str) -> None:
    rows = []
    for path in sorted(Path(root).glob("*/*.json")):
        summary = json.loads(path.read_text())
        rows.append(
            {"chart": path.parent.name, **{k: summary[k] for k in FIELDS[1:] if k in summary}}
        )
    best = {r["chart"]: r["length_m"] for r in rows if r["algorithm"] == "anyangle"}
    writer = csv.DictWriter(sys.stdout, FIELDS, lineterminator="\n")
    writer.writeheader()
    for r in rows:
        r["length_ratio"] = round(r["length_m"] / best[r["chart"]], 4) if r["chart"] in best else ""
        r["length_m"] = round(r["length_m"], 2)
        r["mot"], r["fitness"] = round(r["mot"], 4), round(r["fitness"], 2)
        if r.get("planning_time_s") is not None:  # null with --no-timing
            r["planning_time_s"] = round(r["planning_time_s"], 3)
        writer.writerow(r)


if __name__ == "__main__":
    main(sys.argv[1])
