"""The batch engine of ``usvtool batch``: a pipeline's jobs in a local pool, resumable.

Each job (a chart to preprocess, a route to plan, a scenario to simulate) runs as a subprocess
of the ``usvtool`` command line, so the batch talks to the stages through their files only and
a crash stays in its job. A job's key is a short hash of its whole configuration (the input
file's content, the options, the algorithm or controller, the seed, the package version); its
result is the directory ``DIR/<kind>/<key>/``, renamed into place complete, so that a rerun
skips the jobs already done and a killed batch leaves no half result.
"""

from __future__ import annotations

import hashlib
import json
import os
import secrets
import shutil
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

from usvtool import __version__
from usvtool.errors import UsvError

USV = [sys.executable, "-m", "usvtool.cli"]


def _file_hash(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _key(config: dict) -> str:
    text = json.dumps({"version": __version__, **config}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass
class Job:
    kind: str  # grids, routes, runs
    key: str
    label: str
    args: list[str]  # usvtool arguments; OUT_DIR/... outputs are relative to the job directory
    needs: str | None = None  # the key of the grid job it needs
    error: str | None = field(default=None)


def expand(pipeline) -> list[Job]:
    """The grid, route and simulation jobs of a pipeline (grids first)."""
    root = pipeline.root
    jobs: list[Job] = []
    grid_keys: dict[str, str] = {}
    for chart in dict.fromkeys(j.chart for j in pipeline.route_jobs()):
        c = pipeline.charts[chart]
        inputs = sorted(
            str(p.relative_to(root))
            for pattern in c.inputs
            for p in root.glob(pattern)
            if p.is_file()
        )
        config = {
            "kind": "grids",
            "source": _file_hash(root / c.source),
            "suffix": Path(c.source).suffix.lower(),
            "inputs": {p: _file_hash(root / p) for p in inputs},
            "options": c.args(),
        }
        key = grid_keys[chart] = _key(config)
        args = ["preprocess", str(root / c.source), *c.args(), "-o", "grid.tif",
                "--summary", "summary.json"]  # fmt: skip
        jobs.append(Job("grids", key, f"grid {chart}", args))
    for r in pipeline.route_jobs():
        config = {"kind": "routes", "grid": grid_keys[r.chart], "args": r.args()}
        args = ["plan", "GRID", *r.args(), "--no-timing", "-o", "route.geojson",
                "--summary", "summary.json"]  # fmt: skip
        jobs.append(Job("routes", _key(config), f"route {r.chart} {r.algorithm}", args,
                        needs=grid_keys[r.chart]))  # fmt: skip
    for scenario, controller, seed in pipeline.simulation_jobs():
        path = root / scenario
        config = {"kind": "runs", "scenario": _file_hash(path), "controller": controller,
                  "seed": seed}  # fmt: skip
        args = ["simulate", str(path), "--controller", controller, "--seed", str(seed),
                "-o", "trace.csv", "--events", "trace.events.json",
                "--summary", "summary.json"]  # fmt: skip
        jobs.append(Job("runs", _key(config), f"run {scenario} {controller}", args))
    return jobs


def _one_line(text: str) -> str:
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1] if lines else "failed"


def run_job(job: Job, out: Path) -> str | None:
    """Run one job into ``out/<kind>/<key>/``; its one-line error, or None."""
    final = out / job.kind / job.key
    tmp = out / job.kind / f".tmp-{job.key}-{secrets.token_hex(4)}"
    tmp.mkdir(parents=True)
    try:
        args = [str(out / "grids" / job.needs / "grid.tif") if a == "GRID" else a
                for a in job.args]  # fmt: skip
        proc = subprocess.run([*USV, *args], cwd=tmp, capture_output=True, text=True)
        error = None if proc.returncode == 0 else _one_line(proc.stderr)
        if error is not None:
            for p in tmp.iterdir():
                p.unlink()
            (tmp / "error.txt").write_text(error + "\n", encoding="utf-8")
        try:
            os.rename(tmp, final)  # the result appears complete, or not at all
        except OSError:
            if not final.is_dir():
                raise
        return error
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _done(job: Job, out: Path) -> bool | None:
    """True when the job's result is present, False when it failed before, None when absent."""
    d = out / job.kind / job.key
    if not d.is_dir():
        return None
    return not (d / "error.txt").is_file()


def _result_files(job: Job) -> list[str]:
    if job.kind == "routes":
        return [f"routes/{job.key}/route.geojson"]
    if job.kind == "runs":
        return [f"runs/{job.key}/trace.csv"]
    return []


def long_table(wide_csv: str, jobs: list[Job]) -> str:
    """``usvtool metrics``' table in long format: key, kind, job, metric, value (one row per
    metric a job has), sorted by key, then the metric's column."""
    import csv
    import io

    labels = {j.key: (j.kind, j.label) for j in jobs}
    rows = []
    for row in csv.DictReader(io.StringIO(wide_csv)):
        key = Path(row["run"]).parent.name if row.get("run") else row["chart"]
        kind, label = labels[key]
        for metric, value in row.items():
            if value != "" and metric not in ("chart", "run"):
                rows.append((key, kind, label, metric, value))
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(["key", "kind", "job", "metric", "value"])
    writer.writerows(sorted(rows, key=lambda r: r[0]))  # stable: the metrics' column order
    return text.getvalue()


@dataclass(frozen=True)
class BatchOptions:
    """``workers``: jobs run at once (None: the number of cores); ``out``: the results'
    directory."""

    workers: int | None = None
    out: str = "build/batch"


@dataclass
class BatchResult:
    """What a batch did: its summary figures and the failed jobs."""

    figures: dict
    failed: list = field(default_factory=list)

    def summary(self) -> dict:
        return dict(self.figures)


def run_batch(pipeline_path, options: BatchOptions | None = None, log=lambda text: None):
    """Run every job of the pipeline (grids, then routes and runs), skipping those already
    done; ``log`` receives one progress line per job. Raises :class:`UsvError` when the final
    table cannot be made."""
    from usvtool.atomic import atomic_path
    from usvtool.pipeline import load

    opts = options or BatchOptions()
    started = time.monotonic()
    workers = opts.workers or os.cpu_count() or 1
    out = Path(opts.out).resolve()
    jobs = expand(load(pipeline_path))
    for kind in ("grids", "routes", "runs"):  # temporaries of a killed batch
        for stale in (out / kind).glob(".tmp-*") if (out / kind).is_dir() else ():
            shutil.rmtree(stale, ignore_errors=True)
    # a failed job is tried again on a rerun; a finished one is skipped
    for job in jobs:
        if _done(job, out) is False:
            shutil.rmtree(out / job.kind / job.key)
    skipped = [j for j in jobs if _done(j, out)]
    todo = [j for j in jobs if not _done(j, out)]
    total, count = len(jobs), len(skipped)
    failed: list[Job] = []
    log(f"batch: {total} jobs, {len(skipped)} already done, {workers} at once")

    def finish(job: Job, error: str | None) -> None:
        nonlocal count
        count += 1
        if error is not None:
            job.error = error
            failed.append(job)
        state = "ok" if error is None else f"FAILED: {error}"
        log(f"[{count}/{total}] {job.kind}/{job.key} {job.label}: {state}")

    grid_ok = {j.key for j in skipped if j.kind == "grids"}
    with ThreadPoolExecutor(max_workers=workers) as pool:
        for phase in (("grids",), ("routes", "runs")):
            futures = {}
            for job in (j for j in todo if j.kind in phase):
                if job.needs is not None and job.needs not in grid_ok:
                    finish(job, f"its grid {job.needs} failed")
                    continue
                futures[pool.submit(run_job, job, out)] = job
            for future in as_completed(futures):
                job = futures[future]
                error = future.result()
                if error is None and job.kind == "grids":
                    grid_ok.add(job.key)
                finish(job, error)

    ok = sorted((j for j in jobs if _done(j, out)), key=lambda j: (j.key, j.kind))
    inputs = [f for j in ok for f in _result_files(j)]
    if inputs:
        proc = subprocess.run([*USV, "metrics", *inputs], cwd=out, capture_output=True, text=True)
        if proc.returncode != 0:
            raise UsvError(f"metrics: {_one_line(proc.stderr)}")
        with atomic_path(out / "metrics.csv") as tmp:
            Path(tmp).write_text(long_table(proc.stdout, ok), encoding="utf-8")
    figures = {
        "output": str(out),
        "metrics": str(out / "metrics.csv") if inputs else None,
        "jobs": total,
        "done": total - len(skipped) - len(failed),
        "skipped": len(skipped),
        "failed": len(failed),
        "failures": [
            {"kind": j.kind, "key": j.key, "job": j.label, "error": j.error} for j in failed
        ],  # fmt: skip
        "wall_time_s": round(time.monotonic() - started, 3),
    }
    return BatchResult(figures, failed)
