"""The command lines of a pipeline's jobs, and the files a grid reads: the one place where the
pipeline's plain data (:mod:`usvtool.pipeline`) becomes ``usvtool`` arguments, for the batch's
jobs (:mod:`~usvtool.batch.jobs`) and the Make fragment (:mod:`~usvtool.batch.make`) alike.

A file a command reads (an option's :class:`~pathlib.Path`) is given as ``file(path)``: its
path by default, its content for a key, its path relative to the root in the Make fragment.

>>> from usvtool.pipeline import Ends
>>> ends_args(Ends((0.5, 0.5), (19.5, 19.5)))
['--start', '0.5', '0.5', '--goal', '19.5', '19.5']
>>> option_args((("cell-size", 1), ("no-swell", True), ("cutline", Path("/c/cut.geojson"))))
['--cell-size', '1', '--no-swell', '--cutline', '/c/cut.geojson']
"""

from __future__ import annotations

import json
import os
import shlex
from collections.abc import Callable
from pathlib import Path

from usvtool.companions import companions
from usvtool.pipeline import Chart, Ends, FamilyJob, Named, OptionPairs, Program, RouteJob

#: A grid job's output, in its directory (a route reads ``../../grids/<key>/grid.tif``).
GRID = "grid.tif"
#: A family run's scene, in its directory (with the rasters it names beside it).
SCENE = "scenario.yaml"
#: How a file an option names is given (:func:`option_args`).
FileWord = Callable[[Path], str]
#: A program's standard error, in its run's directory (:func:`controller_args`).
CONTROLLER_LOG = "controller.log"


def word(value: object) -> str:
    """A YAML scalar as a command-line word: 10 -> '10', 0.5 -> '0.5' (shortest repr)."""
    return repr(value) if isinstance(value, float) else str(value)


def param_word(value: object) -> str:
    """A controller parameter as ``--param NAME=VALUE`` reads it back: true, false and null as
    JSON, a number as :func:`word` gives it, a word itself.

    >>> [param_word(v) for v in (False, None, 2, 0.5, "calm")]
    ['false', 'null', '2', '0.5', 'calm']
    """
    return json.dumps(value) if value is None or isinstance(value, bool) else word(value)


def family_option_args(options: OptionPairs) -> list[str]:
    """A family's options as ``--family-option NAME=VALUE`` words (the value as
    :func:`word` gives it, which ``usvtool simulate`` reads back as the same number or word).

    >>> family_option_args((("own_speed", 5), ("vessel", "udwa-usv")))
    ['--family-option', 'own_speed=5', '--family-option', 'vessel=udwa-usv']
    """
    return [w for key, value in options for w in ("--family-option", f"{key}={word(value)}")]


def option_args(options: OptionPairs, file: FileWord = str) -> list[str]:
    """``(("cell-size", 1), ("no-swell", True))`` -> ``["--cell-size", "1", "--no-swell"]``;
    a file (a :class:`Path`) as ``file(path)`` gives it."""
    out: list[str] = []
    for key, value in options:
        if value is True:
            out.append(f"--{key}")
        else:
            out += [f"--{key}", file(value) if isinstance(value, Path) else word(value)]
    return out


def ends_args(ends: Ends) -> list[str]:
    """A route's ``--start X Y --goal X Y`` (``--start-lonlat``, ... for ``frame="lonlat"``)."""
    suffix = "-lonlat" if ends.frame == "lonlat" else ""
    return [f"--start{suffix}", *map(word, ends.start), f"--goal{suffix}", *map(word, ends.goal)]


def route_args(route: RouteJob, file: FileWord = str) -> list[str]:
    """The ``usvtool plan`` arguments of a route but its grid (no seed for an exact planner's)."""
    seeded = [] if route.seed is None else ["--seed", str(route.seed), "--attempts",
                                            str(route.attempts)]  # fmt: skip
    return [*ends_args(route.ends), "--algo", route.algorithm, *seeded,
            *option_args(route.options, file)]  # fmt: skip


def preprocess_command(root: Path, chart: Chart) -> tuple[str, ...]:
    """A grid job's ``usvtool preprocess`` command line, in its directory."""
    return ("preprocess", str(root / chart.source), *option_args(chart.options), "-o", GRID,
            "--preview", "preview.png")  # fmt: skip


def plan_command(grid_key: str, route: RouteJob) -> tuple[str, ...]:
    """A route job's ``usvtool plan`` command line, on the grid of the job ``grid_key``. A
    faithful run's colliding route is a result to count (its collision_free is false), not a
    failed job: plan exits 0 for it with --allow-collision, not 3."""
    return ("plan", f"../../grids/{grid_key}/{GRID}", *route_args(route), "--allow-collision",
            "-o", "route.geojson")  # fmt: skip


def controller_args(controller: str, program: Named | None = None) -> list[str]:
    """``--controller NAME``; for a program (:class:`~usvtool.pipeline.Program`), ``--controller
    exec:PROGRAM ARGS...`` (its words quoted as a shell would), its name as the exec controller's
    label, its parameters, and its stderr to :data:`CONTROLLER_LOG`; for a variant
    (:class:`~usvtool.pipeline.Variant`), its registered controller, its parameters and its
    name as the run's ``--label``.

    >>> from usvtool.pipeline import Variant
    >>> controller_args("udwa-calm", Variant("udwa-calm", "udwa", (("weather", False),)))
    ['--controller', 'udwa', '--param', 'weather=false', '--label', 'udwa-calm']

    >>> controller_args("c-client", Program("c-client", (Path("/x/client"), "--course"),
    ...                                     (("deadline", 2),)))  # doctest: +NORMALIZE_WHITESPACE
    ['--controller', 'exec:/x/client --course', '--param', 'label=c-client',
     '--param', 'deadline=2', '--controller-log', 'controller.log']
    """
    if program is None:
        return ["--controller", controller]
    if not isinstance(program, Program):
        params = [w for key, value in program.params
                  for w in ("--param", f"{key}={param_word(value)}")]  # fmt: skip
        return ["--controller", program.controller, *params, "--label", program.name]
    words = shlex.join(str(w) for w in program.command)
    params = [w for key, value in program.params for w in ("--param", f"{key}={word(value)}")]
    return ["--controller", f"exec:{words}", "--param", f"label={program.name}", *params,
            "--controller-log", CONTROLLER_LOG]  # fmt: skip


def simulate_command(scenario: Path, controller: str, seed: int,
                     program: Named | None = None) -> tuple[str, ...]:  # fmt: skip
    """A run job's ``usvtool simulate`` command line (``program``: the controller's, when it
    is one)."""
    return ("simulate", str(scenario), *controller_args(controller, program), "--seed",
            str(seed), "-o", "trace.csv", "--events", "trace.events.json")  # fmt: skip


def family_command(job: FamilyJob) -> tuple[str, ...]:
    """A family run's ``usvtool simulate --family`` command line: it writes the scene to
    :data:`SCENE` in the job's directory and runs it."""
    return ("simulate", "--family", job.family, "--kind", job.kind, "--scene", str(job.scene),
            *family_option_args(job.options), *controller_args(job.controller, job.program),
            "--seed", str(job.seed), "-o", "trace.csv", "--events", "trace.events.json",
            "--scenario-out", SCENE)  # fmt: skip


def functions_command(function: str, algorithm: str, seed: int,
                      sizes: dict[str, int]) -> tuple[str, ...]:  # fmt: skip
    """A function job's ``usvtool functions`` command line: one run; ``sizes`` pop, iters, dim."""
    sized = [w for k, v in sizes.items() for w in (f"--{k}", str(v))]
    return ("functions", "--function", function, "--algo", algorithm, "--runs", "1",
            "--seed", str(seed), *sized)  # fmt: skip


def chart_inputs(root: Path, chart: Chart) -> list[str]:
    """A chart's extra ``inputs``: the files its globs match, relative to ``root``, sorted."""
    return sorted(str(p.relative_to(root)) for pattern in chart.inputs
                  for p in root.glob(pattern) if p.is_file())  # fmt: skip


def option_files(options: OptionPairs) -> list[Path]:
    """The files a command's options name (those the reader made a :class:`Path`)."""
    return [v for _, v in options if isinstance(v, Path)]


def with_companions(path: Path) -> list[Path]:
    """``path`` and the files read with it (:func:`usvtool.companions.companions`)."""
    return [path, *companions(path)]


def chart_files(root: Path, chart: Chart) -> list[Path]:
    """Every file a chart's grid job reads, as its key hashes them: its source, its extra
    inputs and the files its options name, each followed by its companions (GDAL sidecars, an
    S-57 cell's updates); each file once, in that order."""
    read = [root / chart.source, *(root / p for p in chart_inputs(root, chart)),
            *option_files(chart.options)]  # fmt: skip
    files = (Path(os.path.abspath(f)) for p in read for f in with_companions(p))
    return list(dict.fromkeys(files))
