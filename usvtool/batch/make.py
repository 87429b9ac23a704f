"""The Make fragment of a pipeline (``usvtool batch PIPELINE.yaml --make-fragment FILE``):
the Make variables that ``pipelines/charts.mk`` includes and ``pipelines/routes.mk`` uses.

Its words come from the batch's own builders (:mod:`~usvtool.batch.commands`): a chart's
``usvtool preprocess`` options, a route's ends and plan options; a grid's dependencies
(``CHART_INPUTS_<chart>``) are the files its batch key hashes
(:func:`~usvtool.batch.commands.chart_files`: the source's companions, the extra inputs, the
files its options name and theirs), so Make and the batch agree on what a grid depends on.
Paths are relative to the pipeline's root, where Make runs.
"""

from __future__ import annotations

import glob
import os
import shlex
from pathlib import Path

from usvtool.batch.commands import chart_files, ends_args, option_args
from usvtool.errors import UsvError
from usvtool.pipeline import Chart, Pipeline

#: Where the Make rules put the routes (relative to the project root).
PATHS_DIR = "build/paths"


def _words(args: list[str]) -> str:
    return " ".join(shlex.quote(a) for a in args)


def fragment(p: Pipeline) -> str:
    """The Make variables of a pipeline of one route matrix with one seed."""
    if len(p.routes) != 1:
        raise UsvError(f"{p.path}: routes: the Make fragment needs exactly one route matrix, "
                       f"not {len(p.routes)}")  # fmt: skip
    (r,) = p.routes.values()
    if r.label is not None:
        raise UsvError(f"{p.path}: routes.{r.name}.label: the Make fragment writes "
                       f"{PATHS_DIR}/CHART/ALGO.geojson, one route per chart: no label")
    try:
        seed = r.seed
    except UsvError as exc:
        raise UsvError(f"{p.path}: {exc} (the Make fragment's SEED)") from None

    def rel(path: Path) -> str:
        return os.path.relpath(path, p.root)

    lines = [
        f"# Generated from {p.path.name} by `usvtool batch --make-fragment`: do not edit.",
        f"GRIDS := {' '.join(p.charts)}",
    ]
    folders: set[str] = set()
    for c in p.charts.values():
        source, *inputs = chart_files(p.root, c)
        folders |= {rel(f.parent) for f in (source, *inputs)} | _glob_folders(p.root, c)
        lines.append(f"CHART_SOURCE_{c.name} := {c.source}")
        lines.append(f"CHART_INPUTS_{c.name} := {' '.join(map(rel, inputs))}".rstrip())
        lines.append(f"PREPROCESS_{c.name} := {_words(option_args(c.options, rel))}".rstrip())
    lines += [
        f"ROUTE_GRIDS := {' '.join(r.charts)}",
        f"ALGOS := {' '.join(r.algorithms)}",
        f"SEED ?= {seed}",
        f"ATTEMPTS ?= {r.attempts}",
        f"PLAN_OPTIONS := {_words(option_args(r.options, rel))}".rstrip(),
    ]
    lines += [f"ENDS_{chart} := {_words(ends_args(e))}" for chart, e in r.ends.items()]
    routes = [f"{PATHS_DIR}/{j.chart}/{j.algorithm}.geojson" for j in p.route_jobs()]
    lines.append("ROUTES := " + " \\\n\t".join(routes))
    if p.simulation is not None:
        lines.append(f"SCENARIOS := {' '.join(p.simulation.scenarios)}")
        lines.append(f"CONTROLLERS := {' '.join(p.simulation.controllers)}")
    # a file that appears in one of these folders or leaves it may change a chart's files
    lines.append(f"CHART_FOLDERS := {' '.join(sorted(folders))}")
    return "\n".join(lines) + "\n"


def _glob_folders(root: Path, chart: Chart) -> set[str]:
    """The folders the globs of a chart's inputs look in (their parts before the first magic)."""
    folders = set()
    for pattern in chart.inputs:
        parts = Path(pattern).parts
        fixed = next((i for i, part in enumerate(parts) if glob.has_magic(part)), None)
        if fixed is not None:
            folders.add(os.path.relpath(root.joinpath(*parts[:fixed]), root))
    return folders
