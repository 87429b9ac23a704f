"""Experiment matrices in YAML (``pipelines/*.yaml``): the one source of Make, benchmarks, tests.

A pipeline names its charts (a source file, ``usvtool preprocess`` options, extra inputs), a
route matrix (start and goal per chart, algorithms, seed, attempts, ``usvtool plan`` options)
and a simulation matrix (scenario files x controllers). :func:`load` reads and validates one;
a bad file raises :class:`usvtool.errors.UsvError` in one line naming the file and the field.
The schema is in docs/pipelines.md. This is a contract module: it imports no stage.

``python -m usvtool.pipeline make PIPELINE.yaml [-o build/pipeline.mk]`` writes the Make
fragment that ``pipelines/charts.mk`` includes (its variables feed ``pipelines/routes.mk``).

>>> p = load()
>>> len(p.route_jobs()) == len(p.routes.ends) * len(p.routes.algorithms)
True
>>> p.routes.ends["grid20"].args()
['--start', '0.5', '0.5', '--goal', '19.5', '19.5']
"""

from __future__ import annotations

import argparse
import glob
import math
import re
import shlex
import sys
from dataclasses import dataclass
from pathlib import Path

import yaml

from usvtool.errors import UsvError

#: The pipeline of ``make report``.
BUNDLED = Path(__file__).resolve().parent.parent / "pipelines" / "report.yaml"
#: Where the Make fragment puts the grids and routes (relative to the project root).
GRIDS_DIR = "build/grids"
PATHS_DIR = "build/paths"

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$")
_OPTION = re.compile(r"^[a-z][a-z0-9-]*$")
Options = tuple[tuple[str, object], ...]


def _arg(value: object) -> str:
    """A YAML scalar as a command-line word: 10 -> '10', 0.5 -> '0.5' (shortest repr)."""
    return repr(value) if isinstance(value, float) else str(value)


def option_args(options: Options) -> list[str]:
    """``(("cell-size", 1), ("no-swell", True))`` -> ``["--cell-size", "1", "--no-swell"]``."""
    out: list[str] = []
    for key, value in options:
        out += [f"--{key}"] if value is True else [f"--{key}", _arg(value)]
    return out


@dataclass(frozen=True)
class Chart:
    """A chart to preprocess into ``build/grids/NAME.tif``."""

    name: str
    source: str  # relative to the pipeline's root, as written
    inputs: tuple[str, ...] = ()  # globs of further files the grid depends on
    options: Options = ()  # usvtool preprocess options

    def args(self) -> list[str]:
        return option_args(self.options)


@dataclass(frozen=True)
class Ends:
    """A route's start and goal: map metres (``frame="map"``) or (lon, lat) (``"lonlat"``)."""

    start: tuple[float, float]
    goal: tuple[float, float]
    frame: str = "map"

    def args(self) -> list[str]:
        suffix = "-lonlat" if self.frame == "lonlat" else ""
        return [
            f"--start{suffix}",
            *map(_arg, self.start),
            f"--goal{suffix}",
            *map(_arg, self.goal),
        ]


@dataclass(frozen=True)
class RouteMatrix:
    """Every chart of ``ends`` with every algorithm, at one seed and attempt count."""

    algorithms: tuple[str, ...]
    seed: int
    attempts: int
    options: Options  # further usvtool plan options
    ends: dict[str, Ends]


@dataclass(frozen=True)
class RouteJob:
    """One route to plan: ``usvtool plan build/grids/CHART.tif *args()``."""

    chart: str
    algorithm: str
    start: tuple[float, float]
    goal: tuple[float, float]
    frame: str
    options: Options  # seed, attempts and the matrix's plan options

    def args(self) -> list[str]:
        ends = Ends(self.start, self.goal, self.frame).args()
        return [*ends, "--algo", self.algorithm, *option_args(self.options)]


@dataclass(frozen=True)
class SimulationMatrix:
    """Every scenario file with every controller."""

    scenarios: tuple[str, ...]  # files, relative to the root, sorted
    controllers: tuple[str, ...]
    seed: int


@dataclass(frozen=True)
class Pipeline:
    path: Path
    root: Path
    charts: dict[str, Chart]
    routes: RouteMatrix
    simulation: SimulationMatrix | None = None

    def route_jobs(self) -> list[RouteJob]:
        """The route matrix expanded: charts (in file order) x algorithms."""
        r = self.routes
        opts = (("seed", r.seed), ("attempts", r.attempts), *r.options)
        return [
            RouteJob(chart, algo, e.start, e.goal, e.frame, opts)
            for chart, e in r.ends.items()
            for algo in r.algorithms
        ]

    def simulation_jobs(self) -> list[tuple[str, str, int]]:
        """(scenario file, controller, seed) for every pair of the simulation matrix."""
        s = self.simulation
        if s is None:
            return []
        return [(f, c, s.seed) for f in s.scenarios for c in s.controllers]


class _Reader:
    """Field checks that raise ``FILE: FIELD: problem``."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, field: str, problem: str):
        raise UsvError(f"{self.path}: {field}: {problem}")

    def mapping(self, value, field: str, allowed: set[str], required: set[str] = frozenset()):
        if not isinstance(value, dict):
            self.fail(field, f"expected a mapping, got {_show(value)}")
        for key in value:
            if key not in allowed:
                self.fail(f"{field}.{key}" if field else key, f"unknown field (allowed: "
                          f"{', '.join(sorted(allowed))})")  # fmt: skip
        for key in sorted(required - set(value)):
            self.fail(f"{field}.{key}" if field else key, "missing")
        return value

    def names(self, value, field: str, what: str = "name") -> tuple[str, ...]:
        if isinstance(value, str) or not isinstance(value, list) or not value:
            self.fail(field, f"expected a non-empty list, got {_show(value)}")
        for i, v in enumerate(value):
            if not isinstance(v, str) or not _NAME.match(v):
                self.fail(f"{field}[{i}]", f"not a valid {what}: {_show(v)}")
        dup = sorted({v for v in value if value.count(v) > 1})
        if dup:
            self.fail(field, f"named twice: {', '.join(dup)}")
        return tuple(value)

    def integer(self, value, field: str, least: int) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or value < least:
            self.fail(field, f"expected an integer >= {least}, got {_show(value)}")
        return value

    def options(self, value, field: str) -> Options:
        if value is None:
            return ()
        if not isinstance(value, dict):
            self.fail(field, f"expected a mapping of option: value, got {_show(value)}")
        for key, v in value.items():
            if not isinstance(key, str) or not _OPTION.match(key):
                self.fail(f"{field}.{key}", "not an option name (lower case, e.g. cell-size)")
            if v is False or v is None or isinstance(v, (list, dict)):
                self.fail(f"{field}.{key}", f"expected a number, a word or true, got {_show(v)}")
        return tuple(value.items())

    def point(self, value, field: str, frame: str) -> tuple[float, float]:
        ok = isinstance(value, list) and len(value) == 2
        ok = ok and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
        if not ok or not all(math.isfinite(v) for v in value):
            self.fail(field, f"expected two numbers [x, y], got {_show(value)}")
        if frame == "lonlat" and not (-180 <= value[0] <= 180 and -90 <= value[1] <= 90):
            self.fail(field, f"not a (lon, lat) in degrees: {_show(value)}")
        return (value[0], value[1])

    def files(self, root: Path, value, field: str, glob_ok: bool) -> list[str]:
        """Each entry relative to ``root``; a glob must match a file, a plain path must exist."""
        found: list[str] = []
        for i, pattern in enumerate(value):
            where = f"{field}[{i}]" if len(value) > 1 or glob_ok else field
            if not isinstance(pattern, str) or not pattern:
                self.fail(where, f"expected a path, got {_show(pattern)}")
            if glob_ok and glob.has_magic(pattern):
                hits = sorted(glob.glob(pattern, root_dir=root))
                if not hits:
                    self.fail(where, f"{pattern}: matches no file")
                found += hits
            elif not (root / pattern).is_file():
                self.fail(where, f"{pattern}: no such file")
            else:
                found.append(pattern)
        return found


def _show(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def load(path: str | Path = BUNDLED) -> Pipeline:
    """Read and validate a pipeline file (the bundled one by default)."""
    path = Path(path)
    r = _Reader(path)
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UsvError(f"{path}: no such file") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = f" (line {mark.line + 1})" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise UsvError(f"{path}: not valid YAML{line}: {problem}") from None
    r.mapping(data, "", {"root", "charts", "routes", "simulation"}, {"charts", "routes"})
    root_field = data.get("root", ".")
    if not isinstance(root_field, str):
        r.fail("root", f"expected a directory, got {_show(root_field)}")
    root = (path.parent / root_field).resolve()
    if not root.is_dir():
        r.fail("root", f"{root_field}: no such directory")

    charts: dict[str, Chart] = {}
    if not isinstance(data["charts"], dict) or not data["charts"]:
        r.fail("charts", f"expected a mapping of chart names, got {_show(data['charts'])}")
    for name, entry in data["charts"].items():
        field = f"charts.{name}"
        if not isinstance(name, str) or not _NAME.match(name):
            r.fail(field, "not a valid chart name (letters, digits, _ . + -)")
        r.mapping(entry, field, {"source", "inputs", "options"}, {"source"})
        source = r.files(root, [entry["source"]], f"{field}.source", glob_ok=False)[0]
        inputs = entry.get("inputs", [])
        if not isinstance(inputs, list):
            r.fail(f"{field}.inputs", f"expected a list of paths or globs, got {_show(inputs)}")
        r.files(root, inputs, f"{field}.inputs", glob_ok=True)
        options = r.options(entry.get("options"), f"{field}.options")
        charts[name] = Chart(name, source, tuple(inputs), options)

    rt = r.mapping(data["routes"], "routes", {"algorithms", "seed", "attempts", "options", "ends"},
                   {"algorithms", "seed", "ends"})  # fmt: skip
    algorithms = r.names(rt["algorithms"], "routes.algorithms", "algorithm name")
    seed = r.integer(rt["seed"], "routes.seed", 0)
    attempts = r.integer(rt.get("attempts", 1), "routes.attempts", 1)
    plan_options = r.options(rt.get("options"), "routes.options")
    for key, _ in plan_options:
        if key in {"seed", "attempts", "algo", "start", "goal", "start-lonlat", "goal-lonlat"}:
            r.fail(f"routes.options.{key}", "set by the matrix itself, not an option")
    if not isinstance(rt["ends"], dict) or not rt["ends"]:
        r.fail(
            "routes.ends", f"expected a mapping of chart: start and goal, got {_show(rt['ends'])}"
        )
    ends: dict[str, Ends] = {}
    for chart, entry in rt["ends"].items():
        field = f"routes.ends.{chart}"
        if chart not in charts:
            r.fail(field, f"unknown chart (not under charts: {', '.join(charts)})")
        r.mapping(entry, field, {"start", "goal", "frame"}, {"start", "goal"})
        frame = entry.get("frame", "map")
        if frame not in ("map", "lonlat"):
            r.fail(f"{field}.frame", f"expected map or lonlat, got {_show(frame)}")
        start = r.point(entry["start"], f"{field}.start", frame)
        goal = r.point(entry["goal"], f"{field}.goal", frame)
        ends[chart] = Ends(start, goal, frame)
    routes = RouteMatrix(algorithms, seed, attempts, plan_options, ends)

    simulation = None
    if data.get("simulation") is not None:
        sm = r.mapping(data["simulation"], "simulation", {"scenarios", "controllers", "seed"},
                       {"scenarios", "controllers"})  # fmt: skip
        patterns = sm["scenarios"]
        if isinstance(patterns, str) or not isinstance(patterns, list) or not patterns:
            r.fail(
                "simulation.scenarios", f"expected a list of files or globs, got {_show(patterns)}"
            )
        files = r.files(root, patterns, "simulation.scenarios", glob_ok=True)
        controllers = r.names(sm["controllers"], "simulation.controllers", "controller name")
        sim_seed = r.integer(sm.get("seed", seed), "simulation.seed", 0)
        simulation = SimulationMatrix(tuple(dict.fromkeys(files)), controllers, sim_seed)
    return Pipeline(path, root, charts, routes, simulation)


def _words(args: list[str]) -> str:
    return " ".join(shlex.quote(a) for a in args)


def make_fragment(p: Pipeline) -> str:
    """The Make variables of a pipeline (paths relative to its root, where Make runs)."""
    r = p.routes
    lines = [
        f"# Generated from {p.path.name} by `python -m usvtool.pipeline make`: do not edit.",
        f"GRIDS := {' '.join(p.charts)}",
    ]
    for c in p.charts.values():
        lines.append(f"CHART_SOURCE_{c.name} := {c.source}")
        inputs = " ".join(f"$(wildcard {g})" if glob.has_magic(g) else g for g in c.inputs)
        lines.append(f"CHART_INPUTS_{c.name} := {inputs}".rstrip())
        lines.append(f"PREPROCESS_{c.name} := {_words(c.args())}".rstrip())
    lines += [
        f"ROUTE_GRIDS := {' '.join(r.ends)}",
        f"ALGOS := {' '.join(r.algorithms)}",
        f"SEED ?= {r.seed}",
        f"ATTEMPTS ?= {r.attempts}",
        f"PLAN_OPTIONS := {_words(option_args(r.options))}".rstrip(),
    ]
    lines += [f"ENDS_{chart} := {_words(e.args())}" for chart, e in r.ends.items()]
    routes = [f"{PATHS_DIR}/{j.chart}/{j.algorithm}.geojson" for j in p.route_jobs()]
    lines.append("ROUTES := " + " \\\n\t".join(routes))
    if p.simulation is not None:
        lines.append(f"SCENARIOS := {' '.join(p.simulation.scenarios)}")
        lines.append(f"CONTROLLERS := {' '.join(p.simulation.controllers)}")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m usvtool.pipeline", description=__doc__.split("\n")[0]
    )
    sub = ap.add_subparsers(dest="command", required=True)
    mk = sub.add_parser("make", help="write the Make fragment of a pipeline")
    mk.add_argument("pipeline", nargs="?", default=str(BUNDLED))
    mk.add_argument("-o", "--output", help="file to write (atomically; default stdout)")
    args = ap.parse_args(argv)
    try:
        text = make_fragment(load(args.pipeline))
        if args.output is None:
            sys.stdout.write(text)
        else:
            from usvtool.atomic import atomic_path

            with atomic_path(args.output) as tmp:
                Path(tmp).write_text(text, encoding="utf-8")
    except UsvError as exc:
        print(f"usvtool.pipeline: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
