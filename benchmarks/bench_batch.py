"""The batch engine's own cost (docs/batch.md, issue 12 item 6): per-job overhead of the local
pool and of Dask beside the job time of a real plan, the speed-up of -j 2 over -j 1 on 100 real
plans, and the parent's memory with 10 000 queued jobs.

- Overhead: batches of N1 and N2 minimal real jobs (one run of ``usvtool functions`` on F1 with
  2 agents x 1 iteration in 1-D, well under a millisecond of work) with one worker;
  (T2 - T1) / (N2 - N1) is the time per job with the fixed costs (start, table) cancelled, and
  the jobs' own median wall time (timings.csv) is the command's part of it. The same on a Dask
  ``LocalCluster`` of one worker process (skipped without dask), and, for comparison, a new
  ``python -m usvtool.cli`` process per job (the engine's first version).
- A real plan: IWSO 50 x 300 on env1 (the pipelines' setting): its wall time in a batch.
- Speed-up: 100 IWSO plans on env1 (seeds 0-99), -j 1 and -j 2, the grid done beforehand, and
  how many jobs ran at once on average (their wall times summed over the batch's): a speed-up
  short of it means the cores were not free.
- Memory: the peak RSS (VmHWM) of the ``usvtool batch`` process running 10 000 minimal jobs
  with -j 2, and its throughput.

Usage: python benchmarks/bench_batch.py [--quick]   (--quick: smaller batches, for a check)
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
USV = [sys.executable, "-m", "usvtool.cli"]


def minimal_jobs(count: int) -> str:
    """A pipeline of ``count`` minimal function runs (10 per seed: F1-F10 x pso)."""
    seeds = max(1, count // 10)
    return (f"root: {ROOT}\nfunctions:\n  functions: [F1, F2, F3, F4, F5, F6, F7, F8, F9, F10]\n"
            f"  algorithms: [pso]\n  seeds: {{first: 0, count: {seeds}}}\n"
            "  pop: 2\n  iters: 1\n  dim: 1\n")  # fmt: skip


def plans(count: int) -> str:
    return (f"root: {ROOT}\ninclude: {ROOT / 'pipelines' / 'report.yaml'}\nroutes:\n"
            f"  iwso:\n    charts: [env1]\n    algorithms: [iwso]\n"
            f"    seeds: {{first: 0, count: {count}}}\n")  # fmt: skip


def run_batch(tmp: Path, name: str, pipeline: str, *args: str, out: Path | None = None):
    """Run ``usvtool batch`` on ``pipeline`` (YAML text): (wall time, summary, peak RSS kB)."""
    path = tmp / f"{name}.yaml"
    path.write_text(pipeline)
    out = out or tmp / name
    started = time.perf_counter()
    cmd = [*USV, "batch", str(path), "-o", str(out), *args]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                            text=True)  # fmt: skip
    peak = 0
    status = Path(f"/proc/{proc.pid}/status")
    while proc.poll() is None:
        try:
            line = next(x for x in status.read_text().splitlines() if x.startswith("VmHWM:"))
            peak = max(peak, int(line.split()[1]))
        except (OSError, StopIteration):
            pass
        time.sleep(0.1)
    stdout = proc.stdout.read()
    wall = time.perf_counter() - started
    if proc.returncode != 0:
        sys.exit(f"bench_batch: the batch {name} failed (exit {proc.returncode})")
    return wall, json.loads(stdout), peak


def job_walls(out: Path) -> list[float]:
    from usvtool.results import read_results

    return [r.number for r in read_results(out / "timings.csv") if r.metric == "wall_time_s"]


def overhead(tmp: Path, label: str, n1: int, n2: int, *args: str) -> tuple[float, float]:
    """(seconds per job, the jobs' own median seconds) for one executor."""
    t1, _, _ = run_batch(tmp, f"{label}-{n1}", minimal_jobs(n1), *args)
    t2, _, _ = run_batch(tmp, f"{label}-{n2}", minimal_jobs(n2), *args)
    per_job = (t2 - t1) / (n2 - n1)
    own = statistics.median(job_walls(tmp / f"{label}-{n2}"))
    print(f"  {label:<22} {per_job * 1e3:8.2f} ms per job ({own * 1e3:.2f} ms in the command "
          f"itself; {n1} jobs {t1:.1f} s, {n2} jobs {t2:.1f} s)")  # fmt: skip
    return per_job, own


def one_process_per_job(runs: int = 5) -> float:
    cmd = [*USV, "functions", "--function", "F1", "--algo", "pso", "--runs", "1", "--pop", "2",
           "--iters", "1", "--dim", "1"]  # fmt: skip
    times = []
    for _ in range(runs):
        started = time.perf_counter()
        subprocess.run(cmd, cwd=ROOT, capture_output=True, check=True)
        times.append(time.perf_counter() - started)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small batches, for a check")
    args = ap.parse_args()
    n1, n2 = (20, 60) if args.quick else (50, 250)
    n_plans = 10 if args.quick else 100
    n_queued = 1000 if args.quick else 10_000
    print(f"bench_batch: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f} at start")
    with tempfile.TemporaryDirectory(prefix="bench-batch-") as name:
        tmp = Path(name)
        print("\nPer-job overhead (one worker), a minimal real job:")
        overhead(tmp, "local pool, -j 1", n1, n2, "-j", "1")
        try:
            from distributed import LocalCluster
        except ImportError:
            print("  dask: not installed (pip install 'usvtool[dask]'), skipped")
        else:
            with LocalCluster(n_workers=1, processes=True, threads_per_worker=1,
                              dashboard_address=None) as cluster:  # fmt: skip
                overhead(tmp, "dask, 1 worker", n1, n2, "--scheduler", cluster.scheduler_address)
        print(f"  {'new process per job':<22} {one_process_per_job() * 1e3:8.2f} ms per job "
              "(python -m usvtool.cli functions ...)")

        print(f"\nA real plan (IWSO 50 x 300 on env1), and {n_plans} of them:")
        warm, _, _ = run_batch(tmp, "grid", plans(1), "-j", "1")
        wall = job_walls(tmp / "grid")[0]
        print(f"  one plan: {wall:.3f} s in its worker (the whole batch with the grid: "
              f"{warm:.1f} s)")  # fmt: skip
        times = {}
        for j in (1, 2):
            out = tmp / f"plans-j{j}"
            shutil.copytree(tmp / "grid" / "grids", out / "grids")  # the grid is done
            times[j], summary, _ = run_batch(tmp, f"plans-j{j}", plans(n_plans), "-j", str(j),
                                             out=out)  # fmt: skip
            walls = job_walls(out)
            print(f"  -j {j}: {times[j]:6.1f} s for {summary['done']} plans (median plan "
                  f"{statistics.median(walls):.3f} s; {sum(walls) / times[j]:.2f} jobs running "
                  "on average)")  # fmt: skip
        print(f"  speed-up of -j 2 over -j 1: {times[1] / times[2]:.2f}")

        print(f"\nThe parent with {n_queued} queued jobs (minimal, -j 2):")
        wall, summary, peak = run_batch(tmp, "queued", minimal_jobs(n_queued), "-j", "2")
        print(f"  peak RSS of the usvtool batch process: {peak / 1024:.0f} MiB; {summary['jobs']}"
              f" jobs in {wall:.1f} s ({wall / summary['jobs'] * 1e3:.2f} ms a job, the table "
              f"{summary['stage_time_s']['table']:.1f} s)")  # fmt: skip
    print(f"\nload average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
