"""The memory estimates against measured peaks (issue 22 item 6): each bounds what a real job
uses, and not by far (docs/preprocess.md, planning.md, simulate.md have the full tables).

Planning and preprocessing are measured as the peak resident size of a ``usvtool`` subprocess
(``VmHWM``: benchmarks/bench_memory.py's ``measure``); the rollouts as the peak of NumPy's
allocations during one control step (``tracemalloc``).
"""

import tracemalloc

import cv2
import numpy as np
import pytest
import rasterio
from affine import Affine

from usvtool.chart import memory as chart_memory
from usvtool.clearance import Clearance
from usvtool.grid import Grid, read_grid, write_grid
from usvtool.plan import memory as plan_memory
from usvtool.sim import memory as sim_memory
from usvtool.sim import vessel
from usvtool.sim.controllers import Own, Targets, World, make_controller


def test_planning_on_a_million_cells(charts, tmp_path, benchmark):
    env1 = read_grid(charts / "env1.tif")  # 500 x 500 cells of 1 m, scaled to 1000 x 1000
    cells = env1.cells.repeat(2, 0).repeat(2, 1)
    write_grid(tmp_path / "g.tif", Grid(cells, env1.transform @ Affine.scale(0.5), env1.crs))
    used, _ = benchmark("bench_memory").measure("plan", tmp_path / "g.tif", "--start", 10, 10,
                                                "--goal", 490, 490, "--algo", "anyangle", "-o",
                                                tmp_path / "r.geojson")  # fmt: skip
    need = plan_memory.grid_need(1000, 1000)  # 348 MiB; measured 306-326 MiB (docs/planning.md)
    assert used < need < 1.5 * used, (used, need)


def test_preprocessing_a_four_megapixel_chart(tmp_path, benchmark):
    rgb = np.empty((2000, 2000, 3), np.uint8)
    rgb[:] = (212, 234, 238)  # S-52 deep water
    cv2.circle(rgb, (1000, 1000), 600, (201, 185, 122), -1)  # an island of land
    cv2.putText(rgb, "12", (300, 300), cv2.FONT_HERSHEY_SIMPLEX, 3, (0, 0, 0), 4)  # soundings
    with rasterio.open(tmp_path / "c.tif", "w", driver="GTiff", width=2000, height=2000, count=3,
                       dtype="uint8", crs="EPSG:32619",
                       transform=Affine(1, 0, 330_000, 0, -1, 4_690_000)) as ds:  # fmt: skip
        ds.write(np.moveaxis(rgb, -1, 0))
    used, _ = benchmark("bench_memory").measure("preprocess", tmp_path / "c.tif", "-o",
                                                tmp_path / "g.tif")  # fmt: skip
    grid = 534  # cells a side: 2000 m in cells of 3.75 m
    need = max(chart_memory.pixels_need(2000, 2000, 3, 1),
               chart_memory.cells_need(grid, grid, 2000 * 2000, False))  # fmt: skip
    assert used < need < 1.6 * used, (used, need)


@pytest.mark.parametrize("name, params", [
    ("gdwa", {}),  # the default: the domain checked at every other rollout point
    ("udwa+", {"step": 0.5}),  # steps of 0.5 s: at every point, the most per point
])  # fmt: skip
def test_one_control_step_of_many_samples(charts, name, params):
    controller = make_controller(name, v_samples=101, omega_samples=101, **params)
    clearance = Clearance(read_grid(charts / "env1.tif"))
    world = World(vessel.preset("udwa-usv"), np.array([260.0, 380.0]), clearance, period=0.1,
                  goal_tolerance=5.0)  # fmt: skip
    controller.reset(world)
    own = Own(260.0, 30.0, np.pi / 2, 5.0, 0.0)  # targets close by: every check runs
    targets = Targets(np.array([[260.0, 60.0], [280.0, 40.0]]),
                      np.array([[0.0, -3.0], [-3.0, 0.0]]), np.array([15.0, 15.0]))  # fmt: skip
    controller.decide(own, targets)  # numpy's first-use allocations out of the way
    tracemalloc.start()
    try:
        controller.decide(own, targets)
        used = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    rollouts = sim_memory.run_parts(controller, 0, 1)[0][0]  # 102 x 103 samples x horizon
    # measured: 16 bytes per point and 131-136 per sample; the estimate: 16 and 320
    assert used < rollouts < 1.6 * used, (used, rollouts)
