"""A pipeline's jobs: what each runs, and its key.

A job is one ``usvtool`` command (``preprocess`` a chart, ``plan`` a route, ``simulate`` a
scenario, one run of ``functions``) run in its own directory ``DIR/<kind>/<key>/``. Its
arguments name its outputs relative to that directory (``route.geojson``), its grid as
``../../grids/<key>/grid.tif`` and its input files by absolute path. Its key is a short hash of
its whole configuration: the input file's content (and a chart's extra inputs, and the files a
scenario names: its map, route, target tracks and wind field), the options, the algorithm or
controller, the seed, and the code of the stage that runs it (the stage's
package, its command module, the CLI basics and the contract modules), so that a change of any
of them gives new keys and the jobs run again.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

from usvtool.errors import UsvError
from usvtool.pipeline import Names, Pipeline
from usvtool.yamlfile import read_yaml

PACKAGE = Path(__file__).resolve().parent.parent
#: The stage and the command of each kind of job.
STAGES = {"grids": ("chart", "preprocess"), "routes": ("plan", "plan"),
          "runs": ("sim", "simulate"), "functions": ("plan", "functions")}  # fmt: skip
#: The order in which ready jobs start: grids (routes wait for them), then the longest kinds.
PRIORITY = {"grids": 0, "runs": 1, "routes": 2, "functions": 3}
GRID = "grid.tif"


@dataclass(frozen=True)
class Job:
    """One command of a pipeline, in ``DIR/<kind>/<key>/``."""

    kind: str  # grids, routes, runs, functions
    key: str
    case: str  # the chart, the scenario file's stem, the benchmark function
    method: str  # the algorithm, the controller; "preprocess" for a grid
    seed: int | None  # None: deterministic (a grid, an exact planner)
    args: tuple[str, ...]  # the usvtool command line, relative to the job's directory
    needs: str | None = None  # the key of the grid job a route plans on
    info: dict = field(default_factory=dict)  # further job.json fields

    @property
    def label(self) -> str:
        seed = "" if self.seed is None else f" seed {self.seed}"
        return f"{self.kind} {self.case} {self.method}{seed}"

    def record(self) -> dict:
        """The job's ``job.json`` (the worker adds its wall time, and its error if any)."""
        return {"kind": self.kind, "key": self.key, "case": self.case, "method": self.method,
                "seed": self.seed, "args": list(self.args), **self.info}  # fmt: skip


def _file_hash(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def scenario_hashes(path: Path) -> dict[str, str]:
    """The hashes of a scenario file and of every file it names: each string value of its
    YAML, at any depth, that is the path of a file relative to the scenario's folder (the
    scenario schema's map grid, route, target tracks and wind field, read without the
    simulation stage). A file that is not valid YAML names none (the run then fails on it).

    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp())
    >>> _ = (d / "w.tif").write_bytes(b"wind"), (d / "s.yaml").write_text("weather: {field: w.tif}")
    >>> sorted(scenario_hashes(d / "s.yaml"))
    ['s.yaml', 'w.tif']
    """
    hashes = {path.name: _file_hash(path)}
    try:
        data = read_yaml(path)
    except UsvError:
        return hashes
    stack = [data]
    while stack:
        value = stack.pop()
        if isinstance(value, dict):
            stack.extend(value.values())
        elif isinstance(value, list):
            stack.extend(value)
        elif isinstance(value, str) and value and (path.parent / value).is_file():
            hashes[value] = _file_hash(path.parent / value)
    return hashes


@cache
def code_hash(kind: str) -> str:
    """A hash of the code a kind of job runs: its stage, its command, the CLI basics and the
    contract modules (``usvtool/*.py``)."""
    stage, command = STAGES[kind]
    files = sorted((PACKAGE / stage).rglob("*.py")) + sorted(PACKAGE.glob("*.py"))
    files += [PACKAGE / "cli" / name for name in ("__init__.py", "options.py", f"{command}.py")]
    digest = hashlib.sha256()
    for f in files:
        digest.update(f.relative_to(PACKAGE).as_posix().encode() + b"\0" + f.read_bytes())
    return digest.hexdigest()


def _key(config: dict) -> str:
    text = json.dumps({"code": code_hash(config["kind"]), **config}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def expand(pipeline: Pipeline, names: Names) -> list[Job]:
    """Every job of a pipeline: the grids of the charts that have routes, the routes, the runs
    and the function runs. A job named by two matrices is one job; two different jobs of the
    same case, method and seed are refused."""
    root = pipeline.root
    jobs: dict[str, Job] = {}
    grid_keys: dict[str, str] = {}
    for chart in dict.fromkeys(j.chart for j in pipeline.route_jobs()):
        c = pipeline.charts[chart]
        inputs = sorted(str(p.relative_to(root)) for pattern in c.inputs
                        for p in root.glob(pattern) if p.is_file())  # fmt: skip
        key = grid_keys[chart] = _key({
            "kind": "grids", "source": _file_hash(root / c.source),
            "suffix": Path(c.source).suffix.lower(),
            "inputs": {p: _file_hash(root / p) for p in inputs}, "options": c.args(),
        })  # fmt: skip
        args = ("preprocess", str(root / c.source), *c.args(), "-o", GRID,
                "--preview", "preview.png")  # fmt: skip
        jobs.setdefault(key, Job("grids", key, chart, "preprocess", None, args,
                                 info={"source": str(root / c.source)}))  # fmt: skip
    owners: dict[tuple, tuple[str, str]] = {}  # (kind, case, method, seed) -> (key, where)
    for r in pipeline.route_jobs(names):
        grid = grid_keys[r.chart]
        key = _key({"kind": "routes", "grid": grid, "args": r.args()})
        # a faithful run's colliding route is a result to count (its collision_free is false),
        # not a failed job: plan exits 0 for it with --allow-collision, not 3
        args = ("plan", f"../../grids/{grid}/{GRID}", *r.args(), "--allow-collision",
                "-o", "route.geojson")  # fmt: skip
        info = {"matrix": r.matrix, "grid": grid, "frame": r.ends.frame,
                "start": list(r.ends.start), "goal": list(r.ends.goal)}  # fmt: skip
        _claim(pipeline, owners, ("routes", r.chart, r.algorithm, r.seed), key,
               f"routes.{r.matrix}")  # fmt: skip
        jobs.setdefault(key, Job("routes", key, r.chart, r.algorithm, r.seed, args, grid, info))
    for scenario, controller, seed in pipeline.simulation_jobs():
        path = root / scenario
        key = _key({"kind": "runs", "scenario": scenario_hashes(path), "controller": controller,
                    "seed": seed})  # fmt: skip
        args = ("simulate", str(path), "--controller", controller, "--seed", str(seed),
                "-o", "trace.csv", "--events", "trace.events.json")  # fmt: skip
        jobs.setdefault(key, Job("runs", key, Path(scenario).stem, controller, seed, args,
                                 info={"scenario": str(path)}))  # fmt: skip
    f = pipeline.functions
    for function, algorithm, seed in pipeline.function_jobs():
        sizes = {"pop": f.pop, "iters": f.iters, "dim": f.dim}
        key = _key({"kind": "functions", "function": function, "algorithm": algorithm,
                    "seed": seed, **sizes})  # fmt: skip
        args = ("functions", "--function", function, "--algo", algorithm, "--runs", "1",
                "--seed", str(seed), *(w for k, v in sizes.items() for w in (f"--{k}", str(v))))
        jobs.setdefault(key, Job("functions", key, function, algorithm, seed, args, info=sizes))
    return list(jobs.values())


def _claim(pipeline: Pipeline, owners: dict, identity: tuple, key: str, where: str) -> None:
    """Refuse a second job with another configuration for one (kind, case, method, seed)."""
    first = owners.setdefault(identity, (key, where))
    if first[0] != key:
        _, case, method, seed = identity
        seed_text = "" if seed is None else f" seed {seed}"
        raise UsvError(f"{pipeline.path}: {where}: {case} {method}{seed_text} is also in "
                       f"{first[1]} with other options (give one of the charts another "
                       "name)")  # fmt: skip
