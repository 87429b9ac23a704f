"""A pipeline's jobs: what each runs, and its key.

A job is one ``usvtool`` command (``preprocess`` a chart, ``plan`` a route, ``simulate`` a
scenario or a scene of a family, one run of ``functions``) run in its own directory
``DIR/<kind>/<key>/``. Its
arguments (:mod:`~usvtool.batch.commands` builds them) name its outputs relative to that
directory (``route.geojson``), its grid as ``../../grids/<key>/grid.tif`` and its input files by
absolute path. Its key is a short hash of its whole configuration, every byte the job reads
included: the content of its input files (a grid's: a chart's source, extra inputs and the files
its options name, :func:`~usvtool.batch.commands.chart_files`; a run's: a scenario and the files
it names, its map, route, target tracks and wind field), each with its companions (GDAL's
sidecars of a raster, an S-57 cell's update files: :mod:`usvtool.companions`); a family run's
family, kind, scene and options, the content standing for the path of an option that names a
file the family reads (the ``ais`` family's encounters and tracks); the options, the
algorithm or controller, the seed, and the code of the stage that runs it (the stage's
package, its command module, the CLI basics and the contract modules), so that a change of any
of them gives new keys and the jobs run again.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

from usvtool.batch.commands import (
    chart_inputs,
    family_command,
    functions_command,
    option_args,
    plan_command,
    preprocess_command,
    route_args,
    simulate_command,
    with_companions,
)
from usvtool.budget import require
from usvtool.digest import sha256
from usvtool.errors import UsvError
from usvtool.pipeline import Named, Names, Pipeline, Program

PACKAGE = Path(__file__).resolve().parent.parent
#: The stage and the command of each kind of job.
STAGES = {"grids": ("chart", "preprocess"), "routes": ("plan", "plan"),
          "runs": ("sim", "simulate"), "functions": ("plan", "functions")}  # fmt: skip
#: The order in which ready jobs start: grids (routes wait for them), then the longest kinds.
PRIORITY = {"grids": 0, "runs": 1, "routes": 2, "functions": 3}
#: Bytes the batch holds per job: the job, its key's inputs, its command line, its place in the
#: run's queues (docs/batch.md; a function run's job alone measured 1.0 kB, tracemalloc)
JOB_BYTES = 3 << 10


@dataclass(frozen=True)
class Job:
    """One command of a pipeline, in ``DIR/<kind>/<key>/``."""

    kind: str  # grids, routes, runs, functions
    key: str
    case: str  # the chart (or CHART-LABEL), the scenario stem, family/kind/sNNN, the function
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


#: ``scenario_files(path)``: the files the scenario ``path`` names (its map, route, targets'
#: tracks and wind field) as the simulation resolves them; a :class:`UsvError` for a scenario
#: that does not read (``usvtool batch`` gives :func:`usvtool.cli.batch.scenario_files`).
ScenarioFiles = Callable[[Path], list[Path]]


class _Contents:
    """The content of input files for keys, each file read once."""

    def __init__(self) -> None:
        self._known: dict[Path, str] = {}

    def __call__(self, path: Path) -> str:
        """A digest of the bytes of ``path`` and of its companions (their names relative to
        its folder, and their bytes)."""
        path = Path(os.path.abspath(path))
        if path not in self._known:
            _, *others = with_companions(path)
            files = {os.path.relpath(p, path.parent): sha256(p) for p in others}
            text = json.dumps({"sha256": sha256(path), "with": files}, sort_keys=True)
            self._known[path] = hashlib.sha256(text.encode()).hexdigest()
        return self._known[path]


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


def _key(config: dict, names: Names | None = None, *methods: str) -> str:
    """A job's key: its configuration and its stage's code; with the distribution and version
    of each of ``methods`` a plugin gives (``names.plugins``), so that an upgraded plugin's
    jobs run again (a built-in's key holds none: it is as it was before plugins)."""
    plugins = {m: names.plugins[m] for m in methods if names and m in names.plugins}
    text = json.dumps({"code": code_hash(config["kind"]), **config,
                       **({"plugins": plugins} if plugins else {})}, sort_keys=True)  # fmt: skip
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def check_expansion(pipeline: Pipeline, names: Names, budget: int | None = None) -> None:
    """Refuse, before :func:`expand` lists them, jobs that would need more than ``budget``
    bytes (None: the default budget), :data:`JOB_BYTES` each, in one line naming the matrix
    with the most."""
    counts = pipeline.job_counts(names)
    total = sum(n for _, n in counts)
    field, most = max(counts, key=lambda count: count[1], default=("", 0))
    require(total * JOB_BYTES, f"{pipeline.path}: listing {total} jobs ({most} of them in "
            f"{field})", f"lower the seeds, scenes or other lists of {field} (or split the "
            "pipeline)", budget)  # fmt: skip


def expand(pipeline: Pipeline, names: Names,
           scenario_files: ScenarioFiles | None = None) -> list[Job]:  # fmt: skip
    """Every job of a pipeline: the grids of the charts that have routes, the routes, the runs
    (of the scenario files, then of the families' scenes) and the function runs. A job named
    by two matrices is one job; two different jobs of the same case, method and seed are
    refused. ``scenario_files`` tells the files each scenario
    names (None: none); a scenario that does not read is keyed by its own bytes (its run
    fails alone)."""
    root = pipeline.root
    content = _Contents()
    jobs: dict[str, Job] = {}
    grid_keys: dict[str, str] = {}
    for chart in dict.fromkeys(j.chart for j in pipeline.route_jobs()):
        c = pipeline.charts[chart]
        key = grid_keys[chart] = _key({
            "kind": "grids", "source": content(root / c.source),
            "suffix": Path(c.source).suffix.lower(),
            "inputs": {p: content(root / p) for p in chart_inputs(root, c)},
            "options": option_args(c.options, content),
        })  # fmt: skip
        jobs.setdefault(key, Job("grids", key, chart, "preprocess", None,
                                 preprocess_command(root, c),
                                 info={"source": str(root / c.source)}))  # fmt: skip
    owners: dict[tuple, tuple[str, str]] = {}  # (kind, case, method, seed) -> (key, where)
    file_sha256 = cache(sha256)  # a family's files, hashed once for all its jobs
    for r in pipeline.route_jobs(names):
        grid = grid_keys[r.chart]
        key = _key({"kind": "routes", "grid": grid, "args": route_args(r, content)}, names,
                   r.algorithm.split("+")[0])  # fmt: skip
        info = {"matrix": r.matrix, "grid": grid, "frame": r.ends.frame,
                "start": list(r.ends.start), "goal": list(r.ends.goal)}  # fmt: skip
        _claim(pipeline, owners, ("routes", r.case, r.algorithm, r.seed), key,
               f"routes.{r.matrix}")  # fmt: skip
        jobs.setdefault(key, Job("routes", key, r.case, r.algorithm, r.seed,
                                 plan_command(grid, r), grid, info))  # fmt: skip
    scenarios: dict[str, dict] = {}
    for scenario, controller, seed in pipeline.simulation_jobs():
        path = root / scenario
        if scenario not in scenarios:
            scenarios[scenario] = _scenario_content(path, scenario_files, content)
        program = pipeline.program(controller)
        key = _key({"kind": "runs", "scenario": scenarios[scenario], "controller": controller,
                    "seed": seed, **_program_key(program, content)}, names, controller,
                   *_registered(program))  # fmt: skip
        jobs.setdefault(key, Job("runs", key, Path(scenario).stem, controller, seed,
                                 simulate_command(path, controller, seed, program),
                                 info={"scenario": str(path), **_program_info(program)}))
    for j in pipeline.family_jobs():
        scene = {"family": j.family, "kind": j.kind, "scene": j.scene,
                 "options": {k: str(v) if isinstance(v, Path) else v for k, v in j.options}}
        read = {k: content(v) if isinstance(v, Path) else v for k, v in j.options}
        key = _key({"kind": "runs", "scene": {**scene, "options": read},
                    "controller": j.controller, "seed": j.seed,
                    **_program_key(j.program, content)}, names, j.controller,
                   j.family, *_registered(j.program))  # fmt: skip
        _claim(pipeline, owners, ("runs", j.case, j.controller, j.seed), key,
               f"families.{j.entry}")  # fmt: skip
        # the files' own SHA-256 in job.json, for a reader to check it reads what the run did
        digests = {k: file_sha256(v) for k, v in j.options if isinstance(v, Path)}
        info = {"scene": {**scene, "sha256": digests} if digests else scene,
                **_program_info(j.program)}
        jobs.setdefault(key, Job("runs", key, j.case, j.controller, j.seed, family_command(j),
                                 info=info))  # fmt: skip
    f = pipeline.functions
    for function, algorithm, seed in pipeline.function_jobs():
        sizes = {"pop": f.pop, "iters": f.iters, "dim": f.dim}
        key = _key({"kind": "functions", "function": function, "algorithm": algorithm,
                    "seed": seed, **sizes}, names, algorithm)  # fmt: skip
        jobs.setdefault(key, Job("functions", key, function, algorithm, seed,
                                 functions_command(function, algorithm, seed, sizes),
                                 info=sizes))  # fmt: skip
    return list(jobs.values())


def _registered(program: Named | None) -> tuple[str, ...]:
    """The registered controller a variant runs, whose plugin origin its key holds."""
    return () if program is None or isinstance(program, Program) else (program.controller,)


def _program_key(program: Named | None, content) -> dict:
    """What a run's key holds of its controller's program (nothing for a registered controller,
    whose keys are as they were): its command with the content of every file in it, that of the
    program found on ``PATH`` for a bare name (``python3``), and its parameters; so a rebuilt
    program, or an edited script it runs, runs its jobs again. A variant's: its registered
    controller and its parameters."""
    if program is None:
        return {}
    if not isinstance(program, Program):
        return {"variant": {"controller": program.controller, "params": dict(program.params)}}
    command = [{"file": content(w)} if isinstance(w, Path) else w for w in program.command]
    found = None
    if not isinstance(program.command[0], Path):
        where = shutil.which(program.command[0])
        found = content(Path(where)) if where else None
    return {"program": {"command": command, "found": found, "params": dict(program.params)}}


def _program_info(program: Named | None) -> dict:
    """A run's ``job.json`` fields of its program: its command and parameters (a variant's:
    its registered controller and parameters)."""
    if program is None:
        return {}
    if not isinstance(program, Program):
        return {"variant": {"controller": program.controller, "params": dict(program.params)}}
    return {"program": {"command": [str(w) for w in program.command],
                        "params": dict(program.params)}}  # fmt: skip


def _scenario_content(path: Path, scenario_files: ScenarioFiles | None, content) -> dict:
    """The content of a scenario file and of the files it names (by their names relative to
    its folder); only its own for a scenario that does not read."""
    try:
        named = scenario_files(path) if scenario_files is not None else []
    except UsvError:
        named = []
    files = {os.path.relpath(p, path.parent): content(p) for p in named}
    return {"file": content(path), "names": files}


def _claim(pipeline: Pipeline, owners: dict, identity: tuple, key: str, where: str) -> None:
    """Refuse a second job with another configuration for one (kind, case, method, seed)."""
    first = owners.setdefault(identity, (key, where))
    if first[0] != key:
        _, case, method, seed = identity
        seed_text = "" if seed is None else f" seed {seed}"
        raise UsvError(f"{pipeline.path}: {where}: {case} {method}{seed_text} is also in "
                       f"{first[1]} with other options (give one of the charts another "
                       "name)")  # fmt: skip
