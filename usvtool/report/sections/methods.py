"""The report's methods section: what produced the results and how a stranger produces them
again from a fresh clone.

How to rerun it all (``make report``) and one example command per stage, run from the
repository's root: the command of a real job of the batch (its ``job.json``), with its own
seed, its inputs as paths relative to the repository and its outputs in ``rerun/`` (a route's
grid is the example grid's, written there first). Then the versions of Python, usvtool (the git
commit) and its libraries, the machine, and the parameter tables, each read from the jobs'
files, never from another stage: the optimizers' (a route's ``summary.json`` ``parameters``, a
function job's ``job.json``), the controllers' parameters and weights (the events' ``run``
``parameters``), the vessels (the events' ``run.vessel_preset``, ``run.own_length`` and
``run.vessel``) and the scene families' geometry and seeds (each scene's ``job.json`` ``scene``,
its trace's first step and its events' ``run.goal``). No scenario YAML is read: a run's facts
are its events' (:mod:`usvtool.report.runs`). The command line of every job is listed in the
HTML only. Nothing here depends on the time of day, so the same results give the same page.
"""

from __future__ import annotations

import json
import math
import os
import platform
import shlex
import subprocess
from collections import defaultdict
from functools import cache
from importlib import metadata
from pathlib import Path

from usvtool import __version__
from usvtool.report.data import JobResults, Results, seed_text
from usvtool.report.document import APPENDIX, HTML, Cell, Section, Table
from usvtool.report.runs import job_facts
from usvtool.report.runs import start as first_states
from usvtool.results import file_name
from usvtool.trace import OWN

#: The repository this report's source lives in: paths inside it are shown relative to it.
ROOT = Path(__file__).resolve().parents[3]
#: The directory the example commands write into (relative to the repository).
RERUN_DIR = "rerun"
LIBRARIES = ("numpy", "scipy", "numba", "matplotlib", "weasyprint", "rasterio", "pyogrio",
             "shapely", "pyproj", "opencv-python-headless", "scikit-fuzzy", "jinja2", "click",
             "pyyaml")  # fmt: skip
MAKE = ("make report", "usvtool batch pipelines/full.yaml -j 2 -o build/batch",
        "usvtool report build/batch/metrics.csv -o build/report")  # fmt: skip

def git_commit() -> str:
    """The commit of the source tree (``+changes`` when it has uncommitted ones), or
    ``unknown`` outside a git work tree."""
    where = Path(__file__).resolve().parent
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=where, capture_output=True,
                              text=True, timeout=10)  # fmt: skip
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               cwd=where, capture_output=True, text=True, timeout=10)  # fmt: skip
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    if head.returncode != 0:
        return "unknown"
    if dirty.returncode != 0:  # the tree's state unknown (e.g. the index locked meanwhile)
        return head.stdout.strip() + " (uncommitted changes unknown)"
    return head.stdout.strip() + (" +changes" if dirty.stdout.strip() else "")


def _version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "not installed"


def _memory_gib() -> str:
    try:
        pages, size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return "unknown"
    return f"{pages * size / 2**30:.0f} GiB"


def shown_path(path: Path) -> str:
    """``path`` relative to the repository when inside it, else as it is."""
    try:
        return str(path.resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def slug(job: JobResults) -> str:
    """A job's name in ``rerun/``: its case (``/`` as ``-``), method and seed."""
    case = job.case.replace("/", "-")
    if job.kind == "grids":
        return case
    return f"{case}-{job.method}" + ("" if job.seed is None else f"-s{job.seed}")


def rerun(name: str) -> str:
    """The path of an example's output ``name`` in ``rerun/``, as a
    :func:`usvtool.results.file_name` (a case's ``../`` stays in ``rerun/``)."""
    return f"{RERUN_DIR}/{file_name(name)}"


@cache
def _grid_case(grid_dir: Path) -> str:
    """The case (chart) of a grid job's directory, from its ``job.json``."""
    try:
        return str(json.loads((grid_dir / "job.json").read_text(encoding="utf-8"))["case"])
    except (OSError, ValueError, KeyError):
        return grid_dir.name


def command(job: JobResults) -> str:
    """The job's command line as one runs it from the repository's root: its own outputs
    (the files its ``job.json`` lists) as ``rerun/<slug>-<file>``, a grid job's output read
    by a route as ``rerun/<chart>-<file>``, any other path relative to the repository."""
    outputs = set(job.config.get("files") or ()) | {"grid.tif", "preview.png"}
    words = []
    for arg in map(str, job.config.get("args") or ()):
        if arg in outputs:
            words.append(rerun(f"{slug(job)}-{arg}"))
        elif arg.startswith("../") or os.path.isabs(arg):
            path = (job.dir / arg).resolve()
            if path.parent.parent.name == "grids" and (path.parent / "job.json").is_file():
                words.append(rerun(f"{_grid_case(path.parent)}-{path.name}"))
            else:
                words.append(shown_path(path))
        else:
            words.append(arg)
    return shlex.join(["usvtool", *words]) if words else "-"


def grid_jobs(results: Results) -> list[JobResults]:
    """The grid jobs of the routes (a grid has no metrics, so no row in the results table):
    each route's grid job directory with its ``job.json``."""
    dirs = {d for d in (j.grid_dir() for j in results.select("routes")) if d is not None}
    jobs = []
    for d in sorted(dirs):
        config = _json(d / "job.json")
        if config:
            jobs.append(JobResults(d.name, "grids", str(config.get("case", d.name)),
                                   str(config.get("method", "preprocess")), None, d,
                                   config=config))  # fmt: skip
    return jobs


def _first(jobs: list[JobResults]) -> JobResults | None:
    return min(jobs, key=lambda j: (j.case, j.method, j.seed is None, j.seed), default=None)


def examples(results: Results) -> list[list[Cell]]:
    """One job per stage: the first grid, a route planned on that grid, the first function
    job, a bundled scenario's run and a family scene's run."""
    grid = _first(grid_jobs(results))
    routes = results.select("routes")
    on_grid = [j for j in routes if grid and j.config.get("grid") == grid.key]
    runs = results.select("runs")
    chosen = (("preprocess a chart", grid), ("plan a route on it", _first(on_grid or routes)),
              ("an optimizer on a benchmark function", _first(results.select("functions"))),
              ("simulate a bundled scenario", _first([j for j in runs if "scene" not in j.config])),
              ("simulate a scene of a family", _first([j for j in runs if "scene" in j.config])))
    rows = [[Cell("setup"), Cell(f"mkdir -p {RERUN_DIR}", "mono")]]
    for stage, job in chosen:
        if job is not None and job.config.get("args"):
            seed = "" if job.seed is None else f", seed {job.seed}"
            rows.append([Cell(f"{stage} ({job.case}, {job.method}{seed})"),
                         Cell(command(job), "mono")])  # fmt: skip
    return rows


def _value(v) -> str:
    if isinstance(v, float):
        return f"{v:g}"
    return json.dumps(v) if isinstance(v, list | dict) else str(v)


def _values(seen: set[str]) -> str:
    return " / ".join(sorted(seen)) if seen else "-"


@cache
def _json(path: Path) -> dict:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}


def _events_run(job: JobResults, keys: tuple[str, ...] = ()) -> dict:
    """The run's events' ``run`` object ({} without events; refused without ``keys``)."""
    return job_facts(job, keys) or {}


def optimizers(results: Results) -> Table | None:
    """Each optimizer's parameters: a route's ``summary.json`` ``parameters`` (every value
    seen, per matrix of the pipeline), the functions' population, iterations and dimension."""
    seen: dict[tuple[str, str], dict[str, set[str]]] = defaultdict(lambda: defaultdict(set))
    for j in results.select("routes"):
        params = _json(j.dir / "summary.json").get("parameters") or {}
        where = f"routes: {j.config.get('matrix', j.case)}"
        for k, v in params.items():
            seen[(j.method, where)][k].add(_value(v))
    for j in results.select("functions"):
        for k in ("pop", "iters", "dim"):
            if k in j.config:
                seen[(j.method, "functions")][k].add(_value(j.config[k]))
    if not seen:
        return None
    rows = [[Cell(m), Cell(where), Cell(", ".join(f"{k} {_values(v)}" for k, v in p.items()))]
            for (m, where), p in sorted(seen.items())]  # fmt: skip
    return Table("methods-optimizers", "Optimizers' parameters",
                 "As each run recorded them (route summary.json's parameters; the functions' "
                 "job.json); values that differ between runs are separated by /.",
                 ["algorithm", "where", "parameters"], rows, APPENDIX)  # fmt: skip


def controllers(results: Results) -> Table | None:
    """Each controller's parameters and weights, as the runs' events record them
    (``run.parameters``): one row per parameter, one column per controller."""
    seen: dict[str, dict[str, set[str]]] = defaultdict(lambda: defaultdict(set))
    for j in results.select("runs"):
        for k, v in (_events_run(j).get("parameters") or {}).items():
            seen[j.method][k].add(_value(v))
    if not seen:
        return None
    names = results.methods("runs")
    names = [c for c in names if c in seen]
    params = sorted({k for p in seen.values() for k in p})
    rows = [[Cell(k), *(Cell(_values(seen[c].get(k, set())), "num") for c in names)]
            for k in params]  # fmt: skip
    return Table("methods-controllers", "Controllers' parameters and weights",
                 "As the runs' events record them (run.parameters); - : the controller has "
                 "no such parameter; values that differ between runs are separated by /.",
                 ["parameter", *names], rows, APPENDIX)  # fmt: skip


#: The keys of the events' ``run`` object the vessels table reads (docs/simulate.md).
VESSEL_FACTS = ("vessel_preset", "own_length", "vessel")


def vessels(results: Results) -> Table | None:
    """The own ships' vessels: the preset each run's scenario names, the length the runs used
    and the motion limits as the runs resolved them (a scenario's inline overrides
    included), from the events' ``run`` (:data:`VESSEL_FACTS`)."""
    seen: dict[str, dict[str, set[str]]] = defaultdict(lambda: defaultdict(set))
    for j in results.select("runs"):
        run = _events_run(j, VESSEL_FACTS)
        if not run:
            continue
        name = str(run["vessel_preset"])
        seen[name]["scenarios"].add(j.case.rsplit("/", 1)[0])  # a family's scenes: its kind
        seen[name]["length (m)"].add(_value(run["own_length"]))
        for k, v in (run["vessel"] or {}).items():
            seen[name][k].add(_value(v))
    if not seen:
        return None
    rows = []
    for name, facts in sorted(seen.items()):
        limits = ", ".join(f"{k} {_values(v)}" for k, v in facts.items()
                           if k not in ("scenarios", "length (m)"))  # fmt: skip
        rows.append([Cell(name), Cell(_values(facts["length (m)"]), "num"), Cell(limits or "-"),
                     Cell(f"{len(facts['scenarios'])}: " + ", ".join(sorted(facts["scenarios"])[:6])
                          + (" ..." if len(facts["scenarios"]) > 6 else ""))])  # fmt: skip
    return Table("methods-vessels", "Vessels of the own ship",
                 "The preset each run's scenario names (run.vessel_preset), the length the runs "
                 "used (run.own_length) and the motion limits as the runs resolved them, a "
                 "scenario's inline overrides included (run.vessel); values that differ between "
                 "runs are separated by /.",
                 ["vessel", "length (m)", "limits", "scenarios"], rows,
                 APPENDIX)  # fmt: skip


def _span(values: list[float], digits: int = 0) -> str:
    if not values:
        return "-"
    lo, hi = min(values), max(values)
    return f"{lo:.{digits}f}" if lo == hi else f"{lo:.{digits}f}-{hi:.{digits}f}"


def families(results: Results) -> Table | None:
    """Per scene family and kind (the runs' ``job.json`` ``scene``): the scenes, seeds and
    controllers, and the geometry of the scenes as the runs started them (the trace's first
    step, the events' ``run.goal``): the own ship's run from start to goal and speed, the
    targets, their distance from the own start and their speed."""
    groups: dict[str, list[JobResults]] = defaultdict(list)
    for j in results.select("runs"):
        scene = j.config.get("scene")
        if isinstance(scene, dict):
            groups[f"{scene.get('family')}/{scene.get('kind')}"].append(j)
    if not groups:
        return None
    order = results.methods("runs")
    rows = []
    for name, jobs in sorted(groups.items()):
        scenes = sorted({int(j.config["scene"].get("scene", -1)) for j in jobs})
        seeds = sorted({j.seed for j in jobs if j.seed is not None})
        run, speed, targets, distance, target_speed = [], [], [], [], []
        for j in {j.case: j for j in jobs}.values():  # one run per scene: the same scene
            states, facts = first_states(j), _events_run(j, ("goal",))
            if states is None or not facts:
                continue
            own = states[OWN]
            run.append(math.dist((own.x, own.y), facts["goal"]))
            speed.append(own.speed)
            ts = [t for name, t in states.items() if name != OWN]
            targets.append(len(ts))
            distance += [math.dist((own.x, own.y), (t.x, t.y)) for t in ts]
            target_speed += [t.speed for t in ts]
        options = sorted({_value(j.config["scene"].get("options") or {}) for j in jobs})
        rows.append([Cell(name), Cell(seed_text(scenes)), Cell(seed_text(seeds)),
                     Cell(", ".join(sorted({j.method for j in jobs}, key=order.index))),
                     Cell(_span(run), "num"), Cell(_span(speed, 1), "num"),
                     Cell(_span(targets), "num"), Cell(_span(distance), "num"),
                     Cell(_span(target_speed, 1), "num"), Cell(" / ".join(options))])  # fmt: skip
    return Table("methods-families", "Scene families: geometry and seeds",
                 "Per family and kind (docs/families.md): the scenes drawn and the seeds of "
                 "the runs, the controllers, and over the scenes (as the runs started them): the "
                 "own ship's start-goal distance (m) and speed (m/s), the number of targets, "
                 "their distance from the own start (m) and speed (m/s); min-max.",
                 ["family/kind", "scenes", "seeds", "controllers", "own run (m)",
                  "own speed", "targets", "target distance (m)", "target speed", "options"],
                 rows, APPENDIX)  # fmt: skip


def jobs_table(results: Results) -> Table:
    """Every job with its own seed and command line (HTML only: it is long)."""
    jobs = sorted([*grid_jobs(results), *results.jobs],
                  key=lambda j: (j.kind, j.case, j.method, j.seed is None, j.seed))  # fmt: skip
    rows = [[Cell(j.kind), Cell(j.case), Cell(j.method),
             Cell("-" if j.seed is None else str(j.seed), "num"), Cell(command(j), "mono")]
            for j in jobs]  # fmt: skip
    return Table("methods-jobs", f"Every job's command line ({len(rows)} jobs)",
                 "Each job with its own seed, as run from the repository's root (outputs in "
                 f"{RERUN_DIR}/, a route's grid the one its chart's preprocess line writes).",
                 ["kind", "case", "method", "seed", "command"], rows, HTML)  # fmt: skip


def section(results: Results) -> Section:
    s = Section("methods", "Methods")
    tables = ", ".join(shown_path(Path(t)) for t in results.tables)
    s.paragraphs.append(
        f"Every figure of this report comes from the results tables {tables} and the job files "
        "beside them; the same tables give the same page. Timings are those of the machine "
        "described here. To run it all again from a fresh clone: "
        f"{MAKE[0]} (= {MAKE[1]}, then {MAKE[2]}).")
    s.paragraphs.append(
        "One job of each stage as it ran, with its own seed, to be run from the repository's "
        f"root (outputs in {RERUN_DIR}/); the parameter tables are in the appendix, every "
        "job's command line in the HTML report.")
    s.blocks.append(Table("methods-rerun", "One example per stage", "",
                          ["stage", "command"], examples(results)))  # fmt: skip
    versions = [("Python", platform.python_version()), ("usvtool", __version__),
                *((name, _version(name)) for name in LIBRARIES)]  # fmt: skip
    half = (len(versions) + 1) // 2  # two pairs of columns: half the rows
    versions += [("", "")] * (2 * half - len(versions))
    software = [[Cell(a), Cell(b), Cell(c), Cell(d)]
                for (a, b), (c, d) in zip(versions[:half], versions[half:], strict=True)]
    machine = (f"{platform.system()} {platform.machine()}, "
               f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
               f"{_memory_gib()}")  # fmt: skip
    s.blocks.append(Table("methods-software", "Software and machine",
                          f"usvtool's git commit: {git_commit()}. Machine: {machine}.",
                          ["package", "version", "package", "version"], software))  # fmt: skip
    s.blocks += [t for t in (optimizers(results), controllers(results), vessels(results),
                             families(results)) if t is not None]  # fmt: skip
    s.blocks.append(jobs_table(results))
    if results.missing:
        s.paragraphs.append(missing_paragraph(results))
        s.blocks.append(missing_table(results))
    return s


def missing_paragraph(results: Results) -> str:
    """What a report made with ``--allow-missing`` is without."""
    return (f"{len(results.missing)} job folders were missing (usvtool report --allow-missing, "
            "listed in the appendix): the figures, maps, parameters and command lines drawn "
            "from their files are left out, while their rows of the results tables count in "
            "the tables and statistics.")


def missing_table(results: Results) -> Table:
    """Every job folder the report went without."""
    rows = [[Cell(shown_path(d), "mono")] for d in results.missing]
    return Table("methods-missing", f"Job folders missing ({len(rows)})",
                 "The folders of jobs of the results tables (and of their routes' grids) that "
                 "were not there: no file of theirs is in this report.", ["folder"], rows,
                 APPENDIX)  # fmt: skip
