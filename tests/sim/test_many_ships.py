"""Many ships (issue 24 item 4): a scene of 300 replayed tracks runs, its memory is bounded by
the guard's estimate, and a trace past the budget is refused in one line. The scenes are
benchmarks/bench_simulate.py's (``tracks_scene``: AIS-like fixes every 10 s, straight courses
through a 3 km square around the own ship's route); the benchmark measures the peak against
ships x steps (docs/simulate.md, "Many ships")."""

import numpy as np
import pytest

from usvtool.sim import memory
from usvtool.sim.controllers import make_controller
from usvtool.sim.run import SimOptions, simulate
from usvtool.sim.scenario import read_scenario


def test_300_replayed_tracks_run(tmp_path, benchmark):
    """Two seconds among 300 tracks: every ship in the trace, each target where linear
    interpolation of her fixes puts her."""
    path = benchmark("bench_simulate").tracks_scene(tmp_path, 300, 2.0)
    result = simulate(read_scenario(path), SimOptions())
    trace = result.trace
    assert len(trace.ships) == 301 and len(trace.t) == 21
    for j in (0, 150, 299):
        fixes = np.loadtxt(tmp_path / f"t{j}.csv", delimiter=",", skiprows=1)
        np.testing.assert_allclose(trace.x[:, 1 + j], np.interp(trace.t, fixes[:, 0], fixes[:, 1]))
        np.testing.assert_allclose(trace.y[:, 1 + j], np.interp(trace.t, fixes[:, 0], fixes[:, 2]))
    assert result.summary()["collision"] is None


@pytest.mark.slow  # a subprocess measured
def test_the_estimate_bounds_the_peak_of_300_tracks(tmp_path, benchmark):
    """The peak resident size of ``usvtool simulate`` on 300 tracks for 60 s lies below the
    guard's estimate (measured 282 MiB; the estimate was 232 before numba's process and the
    tracks' 684 bytes per ship and step were counted, now 373)."""
    path = benchmark("bench_simulate").tracks_scene(tmp_path, 300, 60.0)
    used, _ = benchmark("bench_memory").measure("simulate", path, "-o", tmp_path / "t.csv")
    need = memory.run_need(memory.run_parts(make_controller("udwa"), 600, 301))
    assert used < need < 1.6 * used, (used / 2**20, need / 2**20)


def test_a_trace_past_the_budget_is_refused_in_one_line(tmp_path, benchmark, usv):
    """An hour among 300 tracks at 0.1 s under a budget of 1 GiB: refused before a track is
    read, naming the trace's steps and ships and what lowers them; nothing written."""
    path = benchmark("bench_simulate").tracks_scene(tmp_path, 300, 3600.0)
    out = tmp_path / "t.csv"
    result = usv("simulate", path, "-o", out, "--max-memory", "1G")
    assert result.exit_code == 1
    (line,) = result.stderr.strip().splitlines()
    assert "its trace: 36000 steps x 301 ships" in line and "--max-memory" in line
    # short beside the file's name (whose temporary directory's length varies)
    assert "shorten sim.duration" in line and len(line.replace(str(path), "")) < 220
    assert not out.exists()
