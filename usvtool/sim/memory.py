"""The memory ``simulate`` needs, estimated before the run allocates (:mod:`usvtool.budget`).

:data:`PROCESS` plus three parts:

- the controller's rollouts: (v_samples + 1) x (omega_samples + 2) samples (the window's grid,
  the current speed and yaw rate and straight on), each :data:`POINT_BYTES` per horizon step
  (its positions: the compiled checks keep no other (horizon, samples) array,
  :mod:`usvtool.sim.rollout_kernels`) and :data:`SAMPLE_BYTES` (its speed, yaw rate, contact
  time, clearance, the critics' rewards, the kernels' per-sample tables); the number of targets
  does not count;
- the run, per step :data:`STEP_BYTES` and per ship and step :data:`SHIP_STEP_BYTES`: the
  targets' predicted tracks, the own ship's states, the trace's columns and their CSV text, the
  COLREGs evaluation's tables, for a run that lasts its whole ``sim.duration``;
- the map, :data:`MAP_CELL_BYTES` per cell: the grid and its clearance field.

Measured (tracemalloc of one step, NumPy's allocations: 51^2-201^2 samples, horizons of 20-100
steps, every controller): 16 bytes per rollout point and 112-165 per sample, to which the
kernels add about 100 per sample. Peaks of whole runs (``VmHWM``; benchmarks/bench_memory.py,
benchmarks/bench_simulate.py ``--ships``; docs/simulate.md): a process of 160-170 MB with
numba's kernels (47 MB before them; 190-230 MB with a map, a wind field or lon/lat points: the
bundled rudee-inlet-channel 229 MiB, estimated 248), 520-590 bytes per target and step on
courses, 684 with replayed tracks (30-300 tracks of 600-2400 steps: linear in ships x steps,
within 4 MiB), 21-22 per map cell. Every estimate lies above its measured peak, by 1.08-1.5
times (the process's 240 MiB are counted for an open-water run's 165 MB).
"""

from __future__ import annotations

from usvtool.budget import MiB, require

PROCESS = 240 * MiB  # Python, NumPy, numba's kernels (and with a map GDAL, OpenCV, PROJ)
POINT_BYTES = 16
SAMPLE_BYTES = 320
STEP_BYTES = 450
SHIP_STEP_BYTES = 768
MAP_CELL_BYTES = 24


def run_parts(controller, steps: int, ships: int, map_size: tuple[int, int] | None = None):
    """(bytes, what, remedy) of each part of a run of ``steps`` steps of ``ships`` ships (the own
    ship and the targets) under ``controller``, on a map of ``map_size`` (width, height) cells
    or none (:func:`run_need` adds them up)."""
    params = controller.params
    n_v, n_omega = int(params["v_samples"]) + 1, int(params["omega_samples"]) + 2
    horizon = controller.times.size
    parts = [
        (n_v * n_omega * (horizon * POINT_BYTES + SAMPLE_BYTES),
         f"its rollouts: {n_v} x {n_omega} samples x {horizon} horizon steps",
         "lower v_samples and omega_samples (--param) or the horizon"),
        (steps * (STEP_BYTES + ships * SHIP_STEP_BYTES),
         f"its trace: {steps} steps x {ships} ships", "shorten sim.duration or lengthen sim.dt"),
    ]  # fmt: skip
    if map_size is not None:
        width, height = map_size
        parts.append((width * height * MAP_CELL_BYTES, f"its map: {width} x {height} cells",
                      "give a map of larger cells (usvtool preprocess --cell-size)"))  # fmt: skip
    return parts


def run_need(parts) -> int:
    """Bytes a run of these :func:`run_parts` needs."""
    return PROCESS + sum(part[0] for part in parts)


def check_run(path, controller, steps: int, ships: int, budget: int | None = None,
              map_size: tuple[int, int] | None = None) -> None:  # fmt: skip
    """Refuse a run (:func:`run_parts`) that would need more than ``budget`` bytes (None: the
    default budget), in a line naming the scenario's ``path`` (None: nothing, for a caller that
    names it), the largest part and what lowers it."""
    parts = run_parts(controller, steps, ships, map_size)
    _, what, remedy = max(parts, key=lambda part: part[0])
    prefix = f"{path}: " if path is not None else ""
    require(run_need(parts), f"{prefix}the run ({what})", remedy, budget)
