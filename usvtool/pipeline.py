"""Experiment matrices in YAML (``pipelines/*.yaml``): the one source of Make, benchmarks, tests.

A pipeline names its charts (a source file, ``usvtool preprocess`` options, extra inputs, the
start and goal of its routes), named route matrices (charts x algorithms x seeds, with attempts
and ``usvtool plan`` options), a simulation matrix (scenario files x controllers x seeds), scene
families (family x kinds x scenes x controllers x seeds: docs/families.md), a
benchmark-function matrix (functions x optimizers x seeds), and the user's claims about its
methods (``claims:``, :class:`ClaimSpec`: judged by ``usvtool report`` as the papers' are, from
the ``claims.json`` the batch writes beside its results table, :func:`claims_path`).
:func:`load` reads and validates one; a bad file raises :class:`usvtool.errors.UsvError` in
one line naming the file and the field. The schema is in docs/pipelines.md. This is a contract
module: it imports no stage, so the names of algorithms, controllers, scene families and
functions are checked against a :class:`Names` that the caller takes from the stages
(``usvtool batch`` does), and a claim's methods against the pipeline's own. It holds plain
data: the command lines of the jobs, and the Make fragment, are the batch's
(:mod:`usvtool.batch.commands`, :mod:`usvtool.batch.make`).

>>> p = load()
>>> m = p.routes["report"]
>>> len(p.route_jobs()) == len(m.charts) * len(m.algorithms) * len(m.seeds)
True
>>> m.ends["grid20"]
Ends(start=(0.5, 0.5), goal=(19.5, 19.5), frame='map')
"""

from __future__ import annotations

import glob
import json
import math
import os
import re
import shutil
from collections.abc import Callable, Collection, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path

from usvtool.budget import require
from usvtool.errors import UsvError
from usvtool.yamlfile import read_yaml
from usvtool.yamlfile import show as _show

#: Memory of one seed of a ``{first, count}`` list, which is listed when the pipeline is read:
#: a tuple's slot and an int (8 + 28 bytes; CPython's ``sys.getsizeof(10**6)``).
SEED_BYTES = 36

#: The pipeline of ``make report``.
BUNDLED = Path(__file__).resolve().parent.parent / "pipelines" / "report.yaml"
#: ``usvtool plan`` options a route matrix sets itself (or the batch does). Options naming an
#: output file are refused for every command (:class:`FileOptions`).
RESERVED_PLAN_OPTIONS = {"seed", "attempts", "algo", "start", "goal", "start-lonlat",
                         "goal-lonlat", "timing", "no-timing"}  # fmt: skip

#: The metrics a claim may judge, per kind of job: the results table's (``usvtool metrics``'
#: columns that are numbers or True/False, ``collision`` and ``controller_failed`` as events:
#: 1 when the run hit something or its controller failed, else 0; a function's
#: ``final_cost``) and the timings (docs/metrics.md).
CLAIM_METRICS: dict[str, tuple[str, ...]] = {
    "routes": ("length_m", "length_ratio", "turns", "mot", "fitness", "collision_free",
               "attempt", "planning_time_s", "wall_time_s"),
    "runs": ("arrived", "collision", "controller_failed", "length_m", "turns", "mot",
             "arrival_time_s", "closest_distance_m", "average_distance_m", "domain_intrusion_s",
             "encounters", "judged", "compliant", "compliant_excused", "noncompliant",
             "not_judged", "closest_distance_rate", "average_distance_rate", "wall_time_s"),
    "functions": ("final_cost", "wall_time_s"),
}  # fmt: skip
#: The statistics a relative claim may be stated by (judged by where the runs lie; a variance
#: or standard deviation by the runs' deviations from their median: docs/statistics.md), the
#: first the default; an absolute claim's (``every``: each run meets the target).
RELATIVE_STATISTICS = ("median", "mean", "min", "max", "variance", "std")
ABSOLUTE_STATISTICS = ("every",)
#: The file of a batch's claims, beside its results table (:func:`claims_path`).
CLAIMS_FILE = "claims.json"
CLAIM_FIELDS = {"id", "method", "rivals", "metric", "better", "statistic", "cases", "kind",
                "target", "share"}  # fmt: skip

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$")
#: The controller that runs a program (usvtool.sim.controllers.process): a list of controllers
#: names the program instead (:class:`Program`).
EXEC = "exec"
_OPTION = re.compile(r"^[a-z][a-z0-9-]*$")
_FAMILY_OPTION = re.compile(r"^[a-z][a-z0-9_]*$")
#: Options as (name, value) pairs: a command's as written, a family's sorted.
OptionPairs = tuple[tuple[str, object], ...]


@dataclass(frozen=True)
class Ends:
    """A route's start and goal: map metres (``frame="map"``) or (lon, lat) (``"lonlat"``)."""

    start: tuple[float, float]
    goal: tuple[float, float]
    frame: str = "map"


@dataclass(frozen=True)
class Chart:
    """A chart to preprocess into a grid, with the start and goal of its routes (if any)."""

    name: str
    source: str  # relative to the pipeline's root, as written
    inputs: tuple[str, ...] = ()  # globs of further files the grid depends on
    options: OptionPairs = ()  # usvtool preprocess options; a file it reads: its absolute Path
    ends: Ends | None = None


@dataclass(frozen=True)
class FileOptions:
    """The options of one command that name files (long names without ``--``): the files it
    reads and those it writes."""

    reads: frozenset[str] = frozenset()
    writes: frozenset[str] = frozenset()


@dataclass(frozen=True)
class FamilySpec:
    """What the simulation tells the reader of a scene family: its kinds, whether its scenes
    are seeded (else each kind is one scene, 0), ``check(options, where)``, which returns
    the options checked (every one, defaults filled in) or raises a :class:`UsvError` naming
    the option as ``where(name)`` does, and ``files``, its options that name a file it reads
    (the reader makes each an absolute :class:`Path`, relative to the root as written)."""

    kinds: tuple[str, ...]
    seeded: bool = True
    check: Callable[[Mapping, Callable[[str], str]], dict] | None = None
    files: frozenset[str] = frozenset()


@dataclass(frozen=True)
class Names:
    """The names the stages know, for :func:`load` to check a pipeline's entries against:
    optimizers, exact planners (deterministic: their routes take no seed), controllers and
    benchmark functions; ``files``, the file options of the commands a pipeline gives
    options to (``preprocess``, ``plan``), as the commands declare them; ``families``, the
    scene families by name; ``plugins``, the distribution and version (``"usvplug 1.2"``) of
    each method an installed plugin gives (usvtool.registry), which the batch's keys hold;
    ``variants``, the suffixes each exact planner takes (an optimizer takes ``+s`` and ``+g``;
    an exact planner not listed, ``+s``); ``controller_params``, each controller's check of
    its parameters, ``check(params, where)``, which returns them checked or raises a
    :class:`UsvError` naming the parameter as ``where(name)`` does (a :class:`Variant`'s)."""

    optimizers: Collection[str]
    exact: Collection[str]
    controllers: Collection[str]
    functions: Collection[str]
    files: Mapping[str, FileOptions] = field(default_factory=dict)
    families: Mapping[str, FamilySpec] = field(default_factory=dict)
    plugins: Mapping[str, str] = field(default_factory=dict)
    variants: Mapping[str, Collection[str]] = field(default_factory=dict)
    controller_params: Mapping[str, Callable[[Mapping, Callable[[str], str]], dict]] = field(
        default_factory=dict)

    def is_exact(self, algorithm: str) -> bool:
        """``anyangle``, ``astar+s``: an exact planner, with or without shortening."""
        return algorithm.removesuffix("+s") in self.exact


@dataclass(frozen=True)
class RouteMatrix:
    """Every chart of ``charts`` with every algorithm at every seed."""

    name: str
    charts: tuple[str, ...]
    algorithms: tuple[str, ...]
    seeds: tuple[int, ...]
    attempts: int
    options: OptionPairs  # further usvtool plan options
    ends: dict[str, Ends]  # the charts' start and goal
    label: str | None = None  # the routes' case is CHART-LABEL (None: the chart)

    @property
    def seed(self) -> int:
        """The matrix's one seed (a matrix of several has none)."""
        if len(self.seeds) != 1:
            raise UsvError(f"routes.{self.name}: {len(self.seeds)} seeds, not one")
        return self.seeds[0]


@dataclass(frozen=True)
class RouteJob:
    """One route to plan (a cell of a route matrix); ``seed`` None for an exact planner."""

    matrix: str
    chart: str
    algorithm: str
    ends: Ends
    seed: int | None
    attempts: int
    options: OptionPairs  # the matrix's plan options
    label: str | None = None  # the matrix's label

    @property
    def case(self) -> str:
        """The results table's ``case`` of the route: its chart, or ``CHART-LABEL`` for a
        matrix with a label (:func:`route_case`)."""
        return route_case(self.chart, self.label)


def route_case(chart: str, label: str | None) -> str:
    """The ``case`` of a route on ``chart`` planned by a matrix of ``label``.

    >>> route_case("env1", None), route_case("env1", "w11")
    ('env1', 'env1-w11')
    """
    return chart if label is None else f"{chart}-{label}"


@dataclass(frozen=True)
class Program:
    """A controller that is a program run as a process (``exec``, docs/protocol.md), given in a
    list of controllers as ``{name: NAME, exec: [PROGRAM, ARGS...], params: {...}}``: ``name``,
    its runs' method (the exec controller's label); ``command``, the program and its arguments,
    a word naming a file relative to the root as that file's absolute :class:`Path` (the
    program must be one when it holds a ``/``, else a name found on ``PATH``); ``params``, the
    exec controller's further parameters (``deadline``, ...), sorted. A job's key holds the
    content of every file of the command (a rebuilt program runs its jobs again:
    docs/pipelines.md)."""

    name: str
    command: tuple[str | Path, ...]
    params: OptionPairs = ()


@dataclass(frozen=True)
class Variant:
    """A registered controller with parameters under a name of its own, given in a list of
    controllers as ``{name: NAME, controller: REGISTERED, params: {...}}`` (a study compares a
    controller with a variant of itself): ``name``, its runs' method (``usvtool simulate
    --label``); ``controller``, the registered controller that runs; ``params``, its
    parameters as given, sorted. A job's key holds the controller, its parameters and its
    plugin origin."""

    name: str
    controller: str
    params: OptionPairs = ()


#: A controller of a list given a name of its own: a program or a variant.
Named = Program | Variant


@dataclass(frozen=True)
class SimulationMatrix:
    """Every scenario file with every controller at every seed."""

    scenarios: tuple[str, ...]  # files, relative to the root, sorted
    controllers: tuple[str, ...]
    seeds: tuple[int, ...]
    reference_controller: str | None = None  # the optimisation rates' reference
    programs: tuple[Named, ...] = ()  # the controllers that are programs or variants


@dataclass(frozen=True)
class FamilyEntry:
    """Every kind of a scene family x every scene x every controller x every seed; ``name``
    (the family's by default) heads the runs' case (:func:`family_case`)."""

    name: str
    family: str
    kinds: tuple[str, ...]  # () when not given and read without the stages' names: all
    scenes: tuple[int, ...]
    controllers: tuple[str, ...]
    seeds: tuple[int, ...]
    options: tuple[tuple[str, object], ...] = ()  # the family's options as given, sorted; a
    # file it reads: its absolute Path
    programs: tuple[Named, ...] = ()  # the controllers that are programs or variants


@dataclass(frozen=True)
class FamilyJob:
    """One run of a scene of a family: ``usvtool simulate --family ...``; ``program`` when its
    controller is a program or a variant (:class:`Program`, :class:`Variant`)."""

    entry: str
    family: str
    kind: str
    scene: int
    controller: str
    seed: int
    options: tuple[tuple[str, object], ...]
    program: Named | None = None

    @property
    def case(self) -> str:
        return family_case(self.entry, self.kind, self.scene)


def family_case(entry: str, kind: str, scene: int) -> str:
    """The results table's ``case`` of a family's run: ``ENTRY/KIND/sSCENE``, the scene's
    number three digits or more, so that runs group by family and kind and pair by scene.

    >>> family_case("emergency", "head-on", 7)
    'emergency/head-on/s007'
    """
    return f"{entry}/{kind}/s{scene:03d}"


def split_family_case(case: str) -> tuple[str, str, int] | None:
    """``(entry, kind, scene)`` of a family run's case; None for any other case (a scenario
    file's stem, a chart, a function: none holds a ``/``).

    >>> split_family_case("imazu/07/s000"), split_family_case("emergency-head-on")
    (('imazu', '07', 0), None)
    """
    parts = case.split("/")
    if len(parts) != 3 or not re.fullmatch(r"s\d{3,}", parts[2]):
        return None
    return parts[0], parts[1], int(parts[2][1:])


@dataclass(frozen=True)
class FunctionMatrix:
    """Every benchmark function with every optimizer, one run per seed."""

    functions: tuple[str, ...]
    algorithms: tuple[str, ...]
    seeds: tuple[int, ...]
    pop: int = 50
    iters: int = 300
    dim: int = 30


@dataclass(frozen=True)
class ClaimSpec:
    """A user's claim about a method of the pipeline (docs/pipelines.md, "Claims"): the
    ``method`` beats each of ``rivals`` on ``metric`` (``better``: lower or higher), stated by
    ``statistic``, in every case of ``cases`` (results cases of ``kind``: a chart, a route
    matrix's ``CHART-LABEL``, a scenario's stem, a function, a family entry ``ENTRY``, its kind
    ``ENTRY/KIND`` or one scene ``ENTRY/KIND/sNNN``); without rivals an **absolute** claim:
    every run's metric at least as good as ``target`` (a number, or another metric of the same
    run), or with ``share`` < 1 that share of the runs."""

    id: str
    kind: str
    method: str
    rivals: tuple[str, ...]
    metric: str
    better: str
    statistic: str
    cases: tuple[str, ...]
    target: float | str | None = None
    share: float = 1.0

    def to_json(self) -> dict:
        """The claim as ``claims.json`` holds it: every field, but an absolute claim's target
        and share for a relative one (it has none)."""
        out = {"id": self.id, "kind": self.kind, "method": self.method,
               "rivals": list(self.rivals), "metric": self.metric, "better": self.better,
               "statistic": self.statistic, "cases": list(self.cases)}  # fmt: skip
        return out if self.rivals else {**out, "target": self.target, "share": self.share}


def claims_path(table: str | Path) -> Path:
    """The claims of a batch, beside its results table (``metrics.csv``)."""
    return Path(table).with_name(CLAIMS_FILE)


def claims_text(claims: tuple[ClaimSpec, ...] | list[ClaimSpec]) -> str:
    """``claims.json``'s text: ``{"claims": [...]}``, keys sorted, indent 2, a final newline."""
    return json.dumps({"claims": [c.to_json() for c in claims]}, indent=2, sort_keys=True) + "\n"


def read_claims(path: str | Path) -> tuple[ClaimSpec, ...]:
    """The claims of a ``claims.json`` (:func:`claims_text`), each field checked as a
    pipeline's are but the methods and cases, which only the pipeline knows (one line naming
    the file and the field, ``claims.json: claims[0].better: ...``)."""
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as e:
        raise UsvError(f"{path}: cannot read ({e})") from None
    except ValueError as e:
        raise UsvError(f"{path}: not JSON ({e})") from None
    r = _Reader(path)
    r.mapping(data, "", {"claims"}, {"claims"})
    if not isinstance(data["claims"], list):
        r.fail("claims", f"expected a list of claims, got {_show(data['claims'])}")
    return _claims(r, data["claims"], None) if data["claims"] else ()


@dataclass(frozen=True)
class Pipeline:
    path: Path
    root: Path
    charts: dict[str, Chart]
    routes: dict[str, RouteMatrix]
    simulation: SimulationMatrix | None = None
    functions: FunctionMatrix | None = None
    families: tuple[FamilyEntry, ...] = ()
    claims: tuple[ClaimSpec, ...] = ()

    def cases(self) -> dict[str, dict[str, frozenset[str]]]:
        """Every case a claim may name, with the kinds of job it is a case of and the methods
        the pipeline runs there: ``{case: {kind: methods}}``; a family entry gives its name,
        its kinds and its scenes (``ENTRY``, ``ENTRY/KIND``, ``ENTRY/KIND/sNNN``; when its kinds
        are not known, neither read with the stages' names nor given, ``ENTRY/*`` stands for
        any)."""
        found: dict[str, dict[str, set[str]]] = {}

        def add(case: str, kind: str, methods) -> None:
            found.setdefault(case, {}).setdefault(kind, set()).update(methods)

        for m in self.routes.values():
            for chart in m.charts:
                add(route_case(chart, m.label), "routes", m.algorithms)
        if self.simulation is not None:
            for f in self.simulation.scenarios:
                add(Path(f).stem, "runs", self.simulation.controllers)
        for e in self.families:
            add(e.name, "runs", e.controllers)
            if not e.kinds:  # read without the stages' names: any kind of the entry
                add(f"{e.name}/*", "runs", e.controllers)
            for kind in e.kinds:
                add(f"{e.name}/{kind}", "runs", e.controllers)
                for scene in e.scenes:
                    add(family_case(e.name, kind, scene), "runs", e.controllers)
        if self.functions is not None:
            for fn in self.functions.functions:
                add(fn, "functions", self.functions.algorithms)
        return {c: {k: frozenset(m) for k, m in kinds.items()} for c, kinds in found.items()}

    def job_counts(self, exact: Names | None = None) -> list[tuple[str, int]]:
        """(field, jobs) of each matrix, counted without expanding it (the matrices' products;
        with ``exact``, an exact planner's route once): what :meth:`route_jobs`,
        :meth:`simulation_jobs`, :meth:`family_jobs` and :meth:`function_jobs` would list."""
        counts = [(f"routes.{m.name}", len(m.charts) * sum(
            1 if exact is not None and exact.is_exact(a) else len(m.seeds) for a in m.algorithms
        )) for m in self.routes.values()]  # fmt: skip
        if self.simulation is not None:
            s = self.simulation
            counts.append(("simulation", len(s.scenarios) * len(s.controllers) * len(s.seeds)))
        counts += [(f"families[{i}]", len(e.kinds) * len(e.scenes) * len(e.controllers)
                    * len(e.seeds)) for i, e in enumerate(self.families)]  # fmt: skip
        if self.functions is not None:
            f = self.functions
            counts.append(("functions", len(f.functions) * len(f.algorithms) * len(f.seeds)))
        return counts

    def route_jobs(self, exact: Names | None = None) -> list[RouteJob]:
        """The route matrices expanded, in file order: charts x algorithms x seeds. With
        ``exact``, an exact planner's route is one job without a seed."""
        jobs = []
        for m in self.routes.values():
            for chart in m.charts:
                for algo in m.algorithms:
                    once = exact is not None and exact.is_exact(algo)
                    for seed in (None,) if once else m.seeds:
                        jobs.append(RouteJob(m.name, chart, algo, m.ends[chart], seed,
                                             m.attempts, m.options, m.label))  # fmt: skip
        return jobs

    def simulation_jobs(self) -> list[tuple[str, str, int]]:
        """(scenario file, controller, seed) for every cell of the simulation matrix."""
        s = self.simulation
        if s is None:
            return []
        return [(f, c, seed) for f in s.scenarios for c in s.controllers for seed in s.seeds]

    def family_jobs(self) -> list[FamilyJob]:
        """The family entries expanded, in file order: kinds x scenes x controllers x seeds
        (an entry's kinds must be known: read with the stages' names, or given)."""
        jobs = []
        for e in self.families:
            if not e.kinds:
                raise UsvError(f"{self.path}: families.{e.name}: its kinds are not known (read "
                               "the pipeline with the stages' names)")  # fmt: skip
            programs = {p.name: p for p in e.programs}
            jobs += [FamilyJob(e.name, e.family, kind, scene, c, seed, e.options,
                               programs.get(c))
                     for kind in e.kinds for scene in e.scenes for c in e.controllers
                     for seed in e.seeds]  # fmt: skip
        return jobs

    def program(self, controller: str) -> Named | None:
        """The program or variant a controller of the simulation matrix is (None: a registered
        one)."""
        s = self.simulation
        return next((p for p in (s.programs if s else ()) if p.name == controller), None)

    def function_jobs(self) -> list[tuple[str, str, int]]:
        """(function, algorithm, seed) for every cell of the function matrix."""
        f = self.functions
        if f is None:
            return []
        return [(fn, a, seed) for fn in f.functions for a in f.algorithms for seed in f.seeds]


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

    def names(self, value, field: str, what: str = "name", known=None) -> tuple[str, ...]:
        """A non-empty list of distinct names; each in ``known`` (a predicate) when given."""
        if isinstance(value, str) or not isinstance(value, list) or not value:
            self.fail(field, f"expected a non-empty list, got {_show(value)}")
        for i, v in enumerate(value):
            if not isinstance(v, str) or not _NAME.match(v):
                self.fail(f"{field}[{i}]", f"not a valid {what}: {_show(v)}")
            if known is not None and not known[0](v):
                self.fail(f"{field}[{i}]", f"unknown {what} {v!r} (known: {known[1]})")
        dup = sorted({v for v in value if value.count(v) > 1})
        if dup:
            self.fail(field, f"named twice: {', '.join(dup)}")
        return tuple(value)

    def integer(self, value, field: str, least: int) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or value < least:
            self.fail(field, f"expected an integer >= {least}, got {_show(value)}")
        return value

    def seeds(self, value, field: str) -> tuple[int, ...]:
        """A list of distinct integers >= 0, or ``{first: F, count: N}`` (F, F+1, ..., F+N-1)."""
        if isinstance(value, dict):
            self.mapping(value, field, {"first", "count"}, {"first", "count"})
            first = self.integer(value["first"], f"{field}.first", 0)
            count = self.integer(value["count"], f"{field}.count", 1)
            require(count * SEED_BYTES, f"{self.path}: {field}.count: listing {count} seeds",
                    f"give a smaller {field}.count")  # fmt: skip
            return tuple(range(first, first + count))
        if not isinstance(value, list) or not value:
            self.fail(field, f"expected a list of seeds or {{first: F, count: N}}, got "
                      f"{_show(value)}")  # fmt: skip
        for i, v in enumerate(value):
            self.integer(v, f"{field}[{i}]", 0)
        dup = sorted({v for v in value if value.count(v) > 1})
        if dup:
            self.fail(field, f"named twice: {', '.join(map(str, dup))}")
        return tuple(value)

    def options(self, value, field: str, root: Path, files: FileOptions) -> OptionPairs:
        """A command's options; one naming a file it reads must name a file (relative to
        ``root``) and becomes its absolute :class:`Path`; one naming a file it writes is
        refused (``usvtool batch`` names a job's outputs, in the job's directory)."""
        if value is None:
            return ()
        if not isinstance(value, dict):
            self.fail(field, f"expected a mapping of option: value, got {_show(value)}")
        options: list[tuple[str, object]] = []
        for key, v in value.items():
            where = f"{field}.{key}"
            if not isinstance(key, str) or not _OPTION.match(key):
                self.fail(where, "not an option name (lower case, e.g. cell-size)")
            if v is False or v is None or isinstance(v, (list, dict)):
                self.fail(where, f"expected a number, a word or true, got {_show(v)}")
            if key in files.writes:
                self.fail(where, "names an output file: usvtool batch writes every output of a "
                          "job in the job's directory under -o DIR")  # fmt: skip
            if key in files.reads:
                v = root / self.files(root, [v], where, glob_ok=False)[0]
            options.append((key, v))
        return tuple(options)

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


def load(path: str | Path = BUNDLED, names: Names | None = None) -> Pipeline:
    """Read and validate a pipeline file (the bundled one by default); with ``names``, also
    refuse an algorithm, controller or function the stages do not know."""
    return _load(Path(path), names, ())


def _load(path: Path, names: Names | None, including: tuple[Path, ...]) -> Pipeline:
    r = _Reader(path)
    data = read_yaml(path)
    r.mapping(data, "", {"root", "include", "charts", "routes", "simulation", "families",
                         "functions", "claims"})  # fmt: skip
    root_field = data.get("root", ".")
    if not isinstance(root_field, str):
        r.fail("root", f"expected a directory, got {_show(root_field)}")
    root = (path.parent / root_field).resolve()
    if not root.is_dir():
        r.fail("root", f"{root_field}: no such directory")

    charts: dict[str, Chart] = {}
    if data.get("include") is not None:
        charts.update(_included_charts(r, data["include"], root, names, (*including, path)))
    if data.get("charts") is not None:
        if not isinstance(data["charts"], dict) or not data["charts"]:
            r.fail("charts", f"expected a mapping of chart names, got {_show(data['charts'])}")
        for name, entry in data["charts"].items():
            if name in charts:
                r.fail(f"charts.{name}", f"named twice (also in {data['include']})")
            charts[name] = _chart(r, root, name, entry, names)

    routes: dict[str, RouteMatrix] = {}
    if data.get("routes") is not None:
        if not isinstance(data["routes"], dict) or not data["routes"]:
            r.fail("routes", f"expected a mapping of route matrix names, got "
                   f"{_show(data['routes'])}")  # fmt: skip
        for name, entry in data["routes"].items():
            routes[name] = _route_matrix(r, root, name, entry, charts, names)
    simulation = None
    if data.get("simulation") is not None:
        simulation = _simulation(r, root, data["simulation"], names)
    functions = None
    if data.get("functions") is not None:
        functions = _functions(r, data["functions"], names)
    families = () if data.get("families") is None else _families(r, root, data["families"],
                                                                  names)  # fmt: skip
    if not including and not (routes or simulation or functions or families):
        r.fail("routes", "missing: a pipeline needs routes, simulation, families or functions")
    programs = {}  # one program a name, through the whole pipeline
    for where, entry in [("simulation", simulation)] * bool(simulation) + [
            (f"families[{i}]", e) for i, e in enumerate(families)]:  # fmt: skip
        for program in entry.programs:
            if programs.setdefault(program.name, program) != program:
                what = "program" if isinstance(program, Program) else "variant"
                r.fail(f"{where}.controllers", f"{program.name!r} names another {what} "
                       "elsewhere in the pipeline (give it a name of its own)")  # fmt: skip
    pipeline = Pipeline(path, root, charts, routes, simulation, functions, families)
    if data.get("claims") is None:
        return pipeline
    if not isinstance(data["claims"], list) or not data["claims"]:
        r.fail("claims", f"expected a list of claims, got {_show(data['claims'])}")
    return replace(pipeline, claims=_claims(r, data["claims"], pipeline.cases()))


def _included_charts(r: _Reader, value, root: Path, names, including) -> dict[str, Chart]:
    """The charts of the pipeline ``include`` names (relative to this file), of the same root."""
    if not isinstance(value, str) or not value:
        r.fail("include", f"expected a pipeline file, got {_show(value)}")
    other = (r.path.parent / value).resolve()
    if other in {p.resolve() for p in including}:
        r.fail("include", f"{value}: includes itself (through {including[0]})")
    if not other.is_file():
        r.fail("include", f"{value}: no such file")
    included = _load(other, names, including)
    if included.root != root:
        r.fail("include", f"{value}: its root {included.root} is not this file's {root}")
    return included.charts


def _files(names: Names | None, command: str) -> FileOptions:
    """The file options of ``command`` (none known without the stages' names)."""
    return FileOptions() if names is None else names.files.get(command, FileOptions())


def _chart(r: _Reader, root: Path, name, entry, names: Names | None) -> Chart:
    field = f"charts.{name}"
    if not isinstance(name, str) or not _NAME.match(name):
        r.fail(field, "not a valid chart name (letters, digits, _ . + -)")
    r.mapping(entry, field, {"source", "inputs", "options", "start", "goal", "frame"}, {"source"})
    source = r.files(root, [entry["source"]], f"{field}.source", glob_ok=False)[0]
    inputs = entry.get("inputs", [])
    if not isinstance(inputs, list):
        r.fail(f"{field}.inputs", f"expected a list of paths or globs, got {_show(inputs)}")
    r.files(root, inputs, f"{field}.inputs", glob_ok=True)
    options = r.options(entry.get("options"), f"{field}.options", root, _files(names, "preprocess"))
    ends = None
    if "start" in entry or "goal" in entry or "frame" in entry:
        for key in ("start", "goal"):
            if key not in entry:
                r.fail(f"{field}.{key}", "missing (a chart with a route has a start and a goal)")
        frame = entry.get("frame", "map")
        if frame not in ("map", "lonlat"):
            r.fail(f"{field}.frame", f"expected map or lonlat, got {_show(frame)}")
        start = r.point(entry["start"], f"{field}.start", frame)
        goal = r.point(entry["goal"], f"{field}.goal", frame)
        ends = Ends(start, goal, frame)
    return Chart(name, source, tuple(inputs), options, ends)


def _known(names: Names | None, kind: str):
    """The predicate and the list :meth:`_Reader.names` checks ``kind`` names against."""
    if names is None:
        return None
    if kind == "route":
        known = sorted({*names.optimizers, *names.exact})

        def accepted(a: str) -> bool:  # +s and +g for the optimizers, the exact's own
            base, plus, suffix = a.partition("+")
            if base in names.optimizers:
                return suffix in ("", "s", "g")
            return base in names.exact and (not plus or f"+{suffix}" in
                                            names.variants.get(base, ("+s",)))  # fmt: skip

        return (accepted, ", ".join(known) + "; +s for shortening, +g (optimizers) route-guided")
    pool = {"optimizer": names.optimizers, "controller": names.controllers,
            "function": names.functions}[kind]  # fmt: skip
    return (lambda a: a in pool, ", ".join(pool))


def _route_matrix(r: _Reader, root: Path, name, entry, charts: dict[str, Chart],
                  names) -> RouteMatrix:  # fmt: skip
    field = f"routes.{name}"
    if not isinstance(name, str) or not _NAME.match(name):
        r.fail(field, "not a valid matrix name (letters, digits, _ . + -)")
    r.mapping(entry, field, {"charts", "algorithms", "seeds", "attempts", "options", "label"},
              {"charts", "algorithms", "seeds"})  # fmt: skip
    matrix_charts = r.names(entry["charts"], f"{field}.charts", "chart name")
    ends = {}
    for i, chart in enumerate(matrix_charts):
        if chart not in charts:
            r.fail(f"{field}.charts[{i}]", f"unknown chart {chart!r} (not under charts: "
                   f"{', '.join(charts) or 'none'})")  # fmt: skip
        if charts[chart].ends is None:
            r.fail(f"{field}.charts[{i}]", f"chart {chart!r} has no start and goal")
        ends[chart] = charts[chart].ends
    algorithms = r.names(entry["algorithms"], f"{field}.algorithms", "algorithm",
                         _known(names, "route"))  # fmt: skip
    matrix_seeds = r.seeds(entry["seeds"], f"{field}.seeds")
    attempts = r.integer(entry.get("attempts", 1), f"{field}.attempts", 1)
    plan_options = r.options(entry.get("options"), f"{field}.options", root, _files(names, "plan"))
    for key, _ in plan_options:
        if key in RESERVED_PLAN_OPTIONS:
            r.fail(f"{field}.options.{key}", "set by the matrix itself, not an option")
    label = entry.get("label")
    if label is not None:
        if not isinstance(label, str) or not _NAME.match(label):
            r.fail(f"{field}.label", f"not a valid label (letters, digits, _ . + -), got "
                   f"{_show(label)}")  # fmt: skip
        for chart in matrix_charts:
            if route_case(chart, label) in charts:
                r.fail(f"{field}.label", f"its case {route_case(chart, label)!r} is a chart's "
                       "name")  # fmt: skip
    return RouteMatrix(name, matrix_charts, algorithms, matrix_seeds, attempts, plan_options,
                       ends, label)  # fmt: skip


def _simulation(r: _Reader, root: Path, entry, names) -> SimulationMatrix:
    sm = r.mapping(entry, "simulation", {"scenarios", "controllers", "seeds",
                                         "reference_controller"},
                   {"scenarios", "controllers", "seeds"})  # fmt: skip
    patterns = sm["scenarios"]
    if isinstance(patterns, str) or not isinstance(patterns, list) or not patterns:
        r.fail("simulation.scenarios", f"expected a list of files or globs, got {_show(patterns)}")
    files = tuple(dict.fromkeys(r.files(root, patterns, "simulation.scenarios", glob_ok=True)))
    stems: dict[str, str] = {}
    for f in files:  # a run's case is its scenario file's stem
        stem = Path(f).stem
        if stem in stems:
            r.fail("simulation.scenarios", f"{f} and {stems[stem]} share the name {stem!r}")
        stems[stem] = f
    controllers, programs = _controllers(r, sm["controllers"], "simulation.controllers", root,
                                         names)  # fmt: skip
    reference = sm.get("reference_controller")
    if reference is not None and reference not in controllers:
        r.fail("simulation.reference_controller", f"{_show(reference)} is not one of the "
               f"controllers ({', '.join(controllers)})")  # fmt: skip
    sim_seeds = r.seeds(sm["seeds"], "simulation.seeds")
    return SimulationMatrix(files, controllers, sim_seeds, reference, programs)


def _functions(r: _Reader, entry, names) -> FunctionMatrix:
    fm = r.mapping(entry, "functions", {"functions", "algorithms", "seeds", "pop", "iters", "dim"},
                   {"functions", "algorithms", "seeds"})  # fmt: skip
    return FunctionMatrix(
        r.names(fm["functions"], "functions.functions", "function", _known(names, "function")),
        r.names(fm["algorithms"], "functions.algorithms", "optimizer",
                _known(names, "optimizer")),  # fmt: skip
        r.seeds(fm["seeds"], "functions.seeds"),
        r.integer(fm.get("pop", 50), "functions.pop", 2),
        r.integer(fm.get("iters", 300), "functions.iters", 1),
        r.integer(fm.get("dim", 30), "functions.dim", 1),
    )


def _families(r: _Reader, root: Path, value,
              names: Names | None) -> tuple[FamilyEntry, ...]:  # fmt: skip
    if not isinstance(value, list) or not value:
        r.fail("families", f"expected a list of family entries, got {_show(value)}")
    entries: dict[str, FamilyEntry] = {}
    for i, item in enumerate(value):
        where = f"families[{i}]"
        e = r.mapping(item, where, {"family", "name", "kinds", "scenes", "controllers", "seeds",
                                    "options"}, {"family", "controllers", "seeds"})  # fmt: skip
        family = e["family"]
        known = names.families if names is not None else None
        if not isinstance(family, str) or not _NAME.match(family):
            r.fail(f"{where}.family", f"not a valid family name: {_show(family)}")
        if known is not None and family not in known:
            r.fail(f"{where}.family", f"unknown scene family {family!r} (known: "
                   f"{', '.join(known)})")  # fmt: skip
        spec = known[family] if known is not None else None
        name = e.get("name", family)
        if not isinstance(name, str) or not _NAME.match(name):
            r.fail(f"{where}.name", "not a valid entry name (letters, digits, _ . + -)")
        if name in entries:
            r.fail(f"{where}.name", f"{name!r} names two entries (give one another name)")
        kinds = () if spec is None else spec.kinds
        if "kinds" in e:
            known_kinds = None if spec is None else (kinds.__contains__, ", ".join(kinds))
            kinds = r.names(e["kinds"], f"{where}.kinds", "kind", known_kinds)
        if spec is not None and not spec.seeded:
            if "scenes" in e:
                r.fail(f"{where}.scenes", f"family {family} is not seeded (each kind is one "
                       "scene): give no scenes")  # fmt: skip
            scenes: tuple[int, ...] = (0,)
        elif "scenes" in e:
            scenes = r.seeds(e["scenes"], f"{where}.scenes")
        elif spec is not None:
            r.fail(f"{where}.scenes", "missing (the scenes' seeds: a list or {first: F, count: N})")
        else:
            scenes = (0,)
        controllers, programs = _controllers(r, e["controllers"], f"{where}.controllers", root,
                                             names)  # fmt: skip
        seeds = r.seeds(e["seeds"], f"{where}.seeds")
        options = _family_options(r, e.get("options"), f"{where}.options", spec, root)
        entries[name] = FamilyEntry(name, family, kinds, scenes, controllers, seeds, options,
                                    programs)  # fmt: skip
    return tuple(entries.values())


def _controllers(r: _Reader, value, field: str, root: Path,
                 names: Names | None) -> tuple[tuple[str, ...], tuple[Named, ...]]:  # fmt: skip
    """A list of controllers: registered names, programs (:class:`Program`) and variants
    (:class:`Variant`), a mapping each, whose names join the others'; ``exec`` itself is no
    method."""
    if isinstance(value, str) or not isinstance(value, list) or not value:
        r.fail(field, f"expected a non-empty list, got {_show(value)}")
    words: list = []
    programs: list[Named] = []
    for i, item in enumerate(value):
        if isinstance(item, dict) and "controller" in item:
            programs.append(_variant(r, item, f"{field}[{i}]", names))
            item = programs[-1].name
        elif isinstance(item, dict):
            programs.append(_program(r, item, f"{field}[{i}]", root, names))
            item = programs[-1].name
        elif item == EXEC:
            r.fail(f"{field}[{i}]", "exec runs a program: give it as {name: NAME, exec: [PROGRAM, "
                   "ARGS...]} (docs/pipelines.md)")  # fmt: skip
        words.append(item)
    known = _known(names, "controller")
    if known is not None:
        mine = {p.name for p in programs}
        known = (lambda a, check=known[0]: a in mine or check(a), known[1])
    return r.names(words, field, "controller", known), tuple(programs)


def _variant(r: _Reader, item: dict, where: str, names: Names | None) -> Variant:
    """A registered controller with parameters under a name of its own: ``{name, controller,
    params}`` (:class:`Variant`); its parameters checked by the controller's own check."""
    e = r.mapping(item, where, {"name", "controller", "params"}, {"name", "controller"})
    name = e["name"]
    if not isinstance(name, str) or not _NAME.match(name):
        r.fail(f"{where}.name", f"not a valid name (letters, digits, _ . + -): {_show(name)}")
    if name == EXEC or names is not None and name in names.controllers:
        r.fail(f"{where}.name", f"{name!r} is a controller's name: a variant's runs need a "
               "name of their own")  # fmt: skip
    controller = e["controller"]
    if not isinstance(controller, str) or not _NAME.match(controller):
        r.fail(f"{where}.controller", f"not a controller's name: {_show(controller)}")
    if controller == EXEC:
        r.fail(f"{where}.controller", "exec runs a program: give it as {name: NAME, exec: "
               "[PROGRAM, ARGS...]} (docs/pipelines.md)")  # fmt: skip
    if names is not None and controller not in names.controllers:
        r.fail(f"{where}.controller", f"unknown controller {controller!r} (known: "
               f"{', '.join(names.controllers)})")  # fmt: skip
    params = e.get("params") or {}
    if not isinstance(params, dict):
        r.fail(f"{where}.params", f"expected a mapping of parameter: value, got {_show(params)}")
    for key, v in params.items():
        if not isinstance(key, str) or not key:
            r.fail(f"{where}.params", f"not a parameter's name: {_show(key)}")
        if v is not None and not isinstance(v, bool | int | float | str):
            r.fail(f"{where}.params.{key}", f"expected a number, true, false, null or a word, "
                   f"got {_show(v)}")  # fmt: skip
    check = names.controller_params.get(controller) if names is not None else None
    if check is not None:
        try:
            check(dict(params), lambda key: f"{where}.params.{key}")
        except UsvError as exc:
            raise UsvError(f"{r.path}: {exc}") from None
    return Variant(name, controller, tuple(sorted(params.items())))


def _program(r: _Reader, item: dict, where: str, root: Path, names: Names | None) -> Program:
    """A controller that is a program: ``{name, exec, params}`` (:class:`Program`)."""
    e = r.mapping(item, where, {"name", "exec", "params"}, {"name", "exec"})
    name = e["name"]
    if not isinstance(name, str) or not _NAME.match(name):
        r.fail(f"{where}.name", f"not a valid name (letters, digits, _ . + -): {_show(name)}")
    if name == EXEC or names is not None and name in names.controllers:
        r.fail(f"{where}.name", f"{name!r} is a controller's name: a program's runs need a "
               "name of their own")  # fmt: skip
    words = e["exec"]
    if (isinstance(words, str) or not isinstance(words, list) or not words
            or not all(isinstance(w, str) and w for w in words)):  # fmt: skip
        r.fail(f"{where}.exec", f"expected the program and its arguments, a list of words, got "
               f"{_show(words)}")  # fmt: skip
    program, *args = words
    if "/" in program:
        found = r.files(root, [program], f"{where}.exec[0]", glob_ok=False)[0]
        command: list[str | Path] = [Path(os.path.abspath(root / found))]
    elif shutil.which(program) is None:
        r.fail(f"{where}.exec[0]", f"{program}: not found on PATH")
    else:
        command = [program]
    command += [Path(os.path.abspath(root / w)) if (root / w).is_file() else w for w in args]
    params = e.get("params") or {}
    if not isinstance(params, dict):
        r.fail(f"{where}.params", f"expected a mapping of parameter: value, got {_show(params)}")
    for key, v in params.items():
        if key in ("command", "label"):
            given = "exec" if key == "command" else "name"
            r.fail(f"{where}.params.{key}", f"given by the entry's {given}")
        if isinstance(v, bool) or not isinstance(v, int | float | str) or not str(v):
            r.fail(f"{where}.params.{key}", f"expected a number or a word, got {_show(v)}")
    return Program(name, tuple(command), tuple(sorted(params.items())))


def _family_options(r: _Reader, value, field: str, spec: FamilySpec | None, root: Path):
    """A family's options (name: number or word), checked by the family when it is known; an
    option naming a file it reads must name a file (relative to ``root``) and becomes its
    absolute :class:`Path`."""
    value = {} if value is None else value
    if not isinstance(value, dict):
        r.fail(field, f"expected a mapping of option: value, got {_show(value)}")
    options: dict[str, object] = {}
    for key, v in value.items():
        if not isinstance(key, str) or not _FAMILY_OPTION.match(key):
            r.fail(f"{field}.{key}", "not a family option name (lower case, e.g. own_speed)")
        if isinstance(v, bool) or not isinstance(v, int | float | str):
            r.fail(f"{field}.{key}", f"expected a number or a word, got {_show(v)}")
        if spec is not None and key in spec.files:
            v = root / r.files(root, [v], f"{field}.{key}", glob_ok=False)[0]
        options[key] = v
    if spec is not None and spec.check is not None:
        try:
            spec.check({k: str(v) if isinstance(v, Path) else v for k, v in options.items()},
                       lambda key: f"{field}.{key}")  # fmt: skip
        except UsvError as exc:
            raise UsvError(f"{r.path}: {exc}") from None
    return tuple(sorted(options.items()))


def _claims(r: _Reader, value: list, cases: dict | None) -> tuple[ClaimSpec, ...]:
    """The claims of a pipeline (``cases``: :meth:`Pipeline.cases`, against which each claim's
    cases and methods are checked) or of a ``claims.json`` (``cases`` None: each claim must
    give its kind; its cases and methods cannot be checked)."""
    claims: dict[str, ClaimSpec] = {}
    for i, item in enumerate(value):
        claim = _claim(r, item, f"claims[{i}]", cases)
        if claim.id in claims:
            r.fail(f"claims[{i}].id", f"{claim.id!r} names two claims")
        claims[claim.id] = claim
    return tuple(claims.values())


def _claim(r: _Reader, item, where: str, cases: dict | None) -> ClaimSpec:
    required = {"id", "method", "metric", "better", "cases"}
    if cases is None:
        required.add("kind")
    e = r.mapping(item, where, CLAIM_FIELDS, required)
    for key in ("id", "method"):
        if not isinstance(e[key], str) or not _NAME.match(e[key]):
            r.fail(f"{where}.{key}", f"not a valid name (letters, digits, _ . + -): "
                   f"{_show(e[key])}")  # fmt: skip
    rivals = e.get("rivals") or []
    if not isinstance(rivals, list):
        r.fail(f"{where}.rivals", f"expected a list of methods, got {_show(rivals)}")
    rivals = r.names(rivals, f"{where}.rivals", "method") if rivals else ()
    if e["method"] in rivals:
        r.fail(f"{where}.rivals[{rivals.index(e['method'])}]", f"{e['method']!r} is the "
               "claim's method")  # fmt: skip
    kind = e.get("kind")
    if kind is not None and kind not in CLAIM_METRICS:
        r.fail(f"{where}.kind", f"must be {', '.join(CLAIM_METRICS)}, not {_show(kind)}")
    named = e["cases"]
    if isinstance(named, str) or not isinstance(named, list) or not named:
        r.fail(f"{where}.cases", f"expected a non-empty list of cases, got {_show(named)}")
    for j, case in enumerate(named):
        if not isinstance(case, str) or not case or any(
                not _NAME.match(part) for part in case.split("/")):  # fmt: skip
            r.fail(f"{where}.cases[{j}]", f"not a case (a chart, a scenario, a function, "
                   f"ENTRY, ENTRY/KIND or ENTRY/KIND/sNNN): {_show(case)}")  # fmt: skip
    dup = sorted({c for c in named if named.count(c) > 1})
    if dup:
        r.fail(f"{where}.cases", f"named twice: {', '.join(dup)}")
    if cases is not None:
        kind = _claim_kind(r, where, named, kind, cases)
        for field_, method in [("method", e["method"]),
                               *((f"rivals[{k}]", m) for k, m in enumerate(rivals))]:  # fmt: skip
            for case in named:
                run = cases[case][kind]
                if method not in run:
                    r.fail(f"{where}.{field_}", f"{method!r} is not run in case {case!r} (the "
                           f"pipeline runs {', '.join(sorted(run))} there)")  # fmt: skip
    metric = e["metric"]
    if metric not in CLAIM_METRICS[kind]:
        r.fail(f"{where}.metric", f"{_show(metric)} is not a metric of {kind} (known: "
               f"{', '.join(CLAIM_METRICS[kind])})")  # fmt: skip
    if e["better"] not in ("lower", "higher"):
        r.fail(f"{where}.better", f"must be lower or higher, not {_show(e['better'])}")
    allowed = RELATIVE_STATISTICS if rivals else ABSOLUTE_STATISTICS
    statistic = e.get("statistic", allowed[0])
    if statistic not in allowed:
        what = "a relative claim's (with rivals)" if rivals else "an absolute claim's (no rivals)"
        r.fail(f"{where}.statistic", f"must be {what}: {', '.join(allowed)}, not "
               f"{_show(statistic)}")  # fmt: skip
    target, share = e.get("target"), e.get("share", 1.0)
    if rivals:
        for key in ("target", "share"):
            if key in e:
                r.fail(f"{where}.{key}", "a claim with rivals has none (an absolute claim has "
                       "no rivals)")  # fmt: skip
    else:
        if "target" not in e:
            r.fail(f"{where}.target", "missing (an absolute claim, without rivals, needs a "
                   "target: a number, or a metric of the same run)")  # fmt: skip
        if isinstance(target, str):
            if target not in CLAIM_METRICS[kind]:
                r.fail(f"{where}.target", f"{_show(target)} is not a metric of {kind} (known: "
                       f"{', '.join(CLAIM_METRICS[kind])})")  # fmt: skip
        elif (isinstance(target, bool) or not isinstance(target, int | float)
              or not math.isfinite(target)):  # fmt: skip
            r.fail(f"{where}.target", f"expected a number or a metric, got {_show(target)}")
        else:
            target = float(target)
        if (isinstance(share, bool) or not isinstance(share, int | float)
                or not 0 < share <= 1):  # fmt: skip
            r.fail(f"{where}.share", f"expected a number in (0, 1], got {_show(share)}")
    return ClaimSpec(e["id"], kind, e["method"], tuple(rivals), metric, e["better"], statistic,
                     tuple(named), target, float(share))  # fmt: skip


def _claim_kind(r: _Reader, where: str, named: list, kind: str | None, cases: dict) -> str:
    """The kind of job a claim's cases are cases of: ``kind`` when given, else the one their
    cases share."""
    for j, case in enumerate(named):
        if case not in cases and case.count("/") in (1, 2):
            any_kind = cases.get(case.split("/")[0] + "/*")
            if any_kind is not None:
                cases[case] = any_kind
        if case not in cases:
            r.fail(f"{where}.cases[{j}]", f"{case!r} is no case of the pipeline (a chart of a "
                   "route matrix, CHART-LABEL, a scenario's stem, a function, a family entry "
                   "ENTRY, ENTRY/KIND or ENTRY/KIND/sNNN)")  # fmt: skip
        if kind is not None and kind not in cases[case]:
            r.fail(f"{where}.cases[{j}]", f"{case!r} is no case of {kind} (it is of "
                   f"{', '.join(sorted(cases[case]))})")  # fmt: skip
    if kind is not None:
        return kind
    shared = set.intersection(*(set(cases[c]) for c in named))
    if len(shared) == 1:
        return shared.pop()
    if shared:
        r.fail(f"{where}.kind", f"missing: the cases are of {', '.join(sorted(shared))}; give "
               "one")  # fmt: skip
    r.fail(f"{where}.cases", "cases of different kinds of job (" + "; ".join(
        f"{c}: {', '.join(sorted(cases[c]))}" for c in named) + "): one claim, one kind")
