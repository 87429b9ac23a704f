"""The report's preprocessing section (usvtool/report/sections/preprocessing.py) on hand-made
batch directories: one row per grid job, named by its chart, however many route cases plan on
it."""

from __future__ import annotations

import json

import numpy as np
from affine import Affine

from usvtool.grid import Grid, write_grid
from usvtool.report.data import load
from usvtool.report.sections import preprocessing
from usvtool.results import Row, write_results


def test_a_grid_planned_on_by_two_matrices_is_one_row_named_by_its_chart(tmp_path):
    cells = np.zeros((4, 5), np.uint8)
    cells[1, 1:3] = 1  # 2 obstacle cells of 20
    cells[2, 1] = 2  # 1 margin cell
    grid_dir = tmp_path / "grids" / "g1"
    grid_dir.mkdir(parents=True)
    write_grid(grid_dir / "grid.tif", Grid(cells, Affine(2, 0, 0, 0, -2, 8)))
    (grid_dir / "job.json").write_text(json.dumps({"kind": "grids", "case": "env1"}))
    rows = []
    for key, case in (("r1", "env1"), ("r2", "env1-w11")):  # a labelled matrix's case
        (tmp_path / "routes" / key).mkdir(parents=True)
        (tmp_path / "routes" / key / "job.json").write_text(json.dumps({"grid": "g1"}))
        rows.append(Row(key, "routes", case, "iwso", 0, "length_m", "700"))
    write_results(tmp_path / "metrics.csv", rows)
    s = preprocessing.section(load([tmp_path / "metrics.csv"]))
    (table,) = s.tables()
    assert [[c.text for c in r] for r in table.rows] == [
        ["env1", "-", "2.00", "5 x 4", "10.00", "5.00", "local metres"]]
