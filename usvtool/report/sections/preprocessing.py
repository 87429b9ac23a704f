"""The report's preprocessing section: a table of the grids' figures (their ``summary.json``)
and, in the appendix, each chart's preview (the chart with its obstacle and margin cells,
legend and scale, as ``usvtool preprocess --preview`` draws it) beside its navigation grid."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from usvtool.grid import read_grid
from usvtool.report import figures
from usvtool.report.data import Results
from usvtool.report.document import APPENDIX, Cell, Figure, Section, Table, number
from usvtool.report.sections.methods import shown_path


def _chart(where: Path, case: str) -> str:
    """The chart of a grid job's directory (its ``job.json``'s case); ``case``, a route's on
    it, when that does not read."""
    try:
        return str(json.loads((where / "job.json").read_text(encoding="utf-8"))["case"])
    except (OSError, ValueError, KeyError, TypeError):
        return case


def section(results: Results) -> Section | None:
    grids = {}  # chart -> its grid job's directory, once for the routes of several matrices
    for case in results.cases("routes"):
        where = next((d for d in (j.grid_dir() for j in results.select("routes", case)) if d),
                     None)  # fmt: skip
        if where is not None and (where / "grid.tif").is_file() and where not in grids.values():
            grids[_chart(where, case)] = where
    if not grids:
        return None
    s = Section("preprocessing", "Charts and their navigation grids")
    s.paragraphs.append(
        "Each chart as usvtool preprocess turns it into a grid: obstacle cells (land, shallows, "
        "hazards) and the safety margin around them (docs/preprocess.md gives the method); "
        "each chart beside its grid is in the appendix.")
    rows = []
    for chart, where in grids.items():
        grid = read_grid(where / "grid.tif")
        summary = where / "summary.json"
        info = json.loads(summary.read_text(encoding="utf-8")) if summary.is_file() else {}
        obstacle = float(np.mean(grid.cells == 1))
        margin = float(np.mean(grid.cells == 2))
        source = info.get("source")
        rows.append([Cell(chart), Cell(shown_path(Path(source)) if source else "-"),
                     number(grid.cell_size, 2), Cell(f"{grid.width} x {grid.height}", "num"),
                     number(100 * obstacle, 2), number(100 * margin, 2),
                     Cell(str(grid.crs) if grid.crs else "local metres")])  # fmt: skip
        if grid.crs is None:
            continue  # a synthetic map: its routes figure shows it
        plot = figures.preprocessing(figures.preview_chart(where / "preview.png", grid), grid,
                                     chart)
        s.blocks.append(Figure(f"chart-{chart}", f"Chart {chart}",
                               "Left: the chart with its obstacle (red) and margin (yellow) "
                               "cells; right: the navigation grid (obstacle dark, margin grey, "
                               "outside the chart hatched).", plot.png, plot.data,
                               APPENDIX))  # fmt: skip
    s.blocks.append(Table("charts-table", "Navigation grids",
                          "Cell size, size, and the share of obstacle and margin cells.",
                          ["chart", "source", "cell (m)", "cells", "obstacle (%)", "margin (%)",
                           "CRS"], rows))  # fmt: skip
    return s
