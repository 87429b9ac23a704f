"""The memory ``simulate`` needs, estimated before the run allocates (:mod:`usvtool.budget`).

:data:`PROCESS` plus three parts:

- a DWA controller's rollouts (its ``memory_parts``; a controller of another make states its
  own, none by default): (v_samples + 1) x (omega_samples + 2) samples (the window's grid, the
  current speed and yaw rate and straight on), each :data:`POINT_BYTES` per horizon step
  (its positions: the compiled checks keep no other (horizon, samples) array,
  :mod:`usvtool.sim.rollout_kernels`) and :data:`SAMPLE_BYTES` (its speed, yaw rate, contact
  time, clearance, the critics' rewards, the kernels' per-sample tables); the number of targets
  does not count;
- the run, per step :data:`STEP_BYTES` and per ship and step :data:`SHIP_STEP_BYTES`: the
  targets' predicted tracks, the own ship's states, the trace's columns and their CSV text, the
  COLREGs evaluation's tables, for a run that lasts its whole ``sim.duration``;
- the map, :data:`MAP_CELL_BYTES` per cell: the grid and its clearance field;
- the targets' track files, read whole: :data:`TRACK_ROW_BYTES` per row (the CSV reader's lists
  of strings, then of floats) and :data:`TRACK_BYTE` per byte (:func:`track_sizes` counts them
  before any row is parsed).

Measured (tracemalloc of one step, NumPy's allocations: 51^2-201^2 samples, horizons of 20-100
steps, every controller): 16 bytes per rollout point and 112-165 per sample, to which the
kernels add about 100 per sample. Peaks of whole runs (``VmHWM``; benchmarks/bench_memory.py,
benchmarks/bench_simulate.py ``--ships``; docs/simulate.md): a process of 160-170 MB with
numba's kernels (47 MB before them; 190-230 MB with a map, a wind field or lon/lat points: the
bundled rudee-inlet-channel 229 MiB, estimated 248), 520-590 bytes per target and step on
courses, 684 with replayed tracks (30-300 tracks of 600-2400 steps: linear in ships x steps,
within 4 MiB), 21-22 per map cell. Every estimate lies above its measured peak, by 1.08-1.5
times (the process's 240 MiB are counted for an open-water run's 165 MB). A track CSV read
took 479-528 bytes per row for rows of 15-63 characters (tracemalloc; 300 000 rows), a file of
one line of 100 MB 6.1 bytes per byte (the reader's line as 4-byte characters).

:func:`check_run` returns the guard (:func:`usvtool.budget.allocating`) the run is wrapped in.
"""

from __future__ import annotations

import os
from contextlib import AbstractContextManager

from usvtool.budget import MiB, allocating, require, size_text

PROCESS = 240 * MiB  # Python, NumPy, numba's kernels (and with a map GDAL, OpenCV, PROJ)
POINT_BYTES = 16
SAMPLE_BYTES = 320
STEP_BYTES = 450
SHIP_STEP_BYTES = 768
MAP_CELL_BYTES = 24
TRACK_ROW_BYTES = 460  # per row of a track CSV
TRACK_BYTE = 7  # per byte of a track CSV
CHUNK = 1 << 24  # bytes read at a time to count a track's rows


def track_sizes(paths) -> tuple[int, int]:
    """(rows, bytes) of the track files at ``paths`` that exist (a missing one is named by its
    reader), counted in chunks without parsing."""
    rows = size = 0
    for path in paths:
        if not os.path.isfile(path):
            continue
        with open(path, "rb") as f:
            while chunk := f.read(CHUNK):
                rows += chunk.count(b"\n")
                size += len(chunk)
    return rows, size


def run_parts(controller, steps: int, ships: int, map_size: tuple[int, int] | None = None,
              tracks: tuple[int, int] = (0, 0)):  # fmt: skip
    """(bytes, what, remedy) of each part of a run of ``steps`` steps of ``ships`` ships (the own
    ship and the targets) under ``controller``, on a map of ``map_size`` (width, height) cells
    or none, replaying ``tracks`` (rows, bytes: :func:`track_sizes`) (:func:`run_need` adds them
    up)."""
    parts = [
        *controller.memory_parts(),
        (steps * (STEP_BYTES + ships * SHIP_STEP_BYTES),
         f"its trace: {steps} steps x {ships} ships", "shorten sim.duration or lengthen sim.dt"),
    ]  # fmt: skip
    if map_size is not None:
        width, height = map_size
        parts.append((width * height * MAP_CELL_BYTES, f"its map: {width} x {height} cells",
                      "give a map of larger cells (usvtool preprocess --cell-size)"))  # fmt: skip
    rows, size = tracks
    if size:
        parts.append((rows * TRACK_ROW_BYTES + size * TRACK_BYTE,
                      f"its targets' tracks: {rows} rows, {size_text(size)}",
                      "give shorter track files (targets[].track)"))  # fmt: skip
    return parts


def run_need(parts) -> int:
    """Bytes a run of these :func:`run_parts` needs."""
    return PROCESS + sum(part[0] for part in parts)


def check_run(path, controller, steps: int, ships: int, budget: int | None = None,
              map_size: tuple[int, int] | None = None,
              tracks: tuple[int, int] = (0, 0)) -> AbstractContextManager:  # fmt: skip
    """Refuse a run (:func:`run_parts`) that would need more than ``budget`` bytes (None: the
    default budget), in a line naming the scenario's ``path`` (None: nothing, for a caller that
    names it), the largest part and what lowers it; else the guard to run it in, its
    ``MemoryError`` one line with the same words."""
    parts = run_parts(controller, steps, ships, map_size, tracks)
    _, what, remedy = max(parts, key=lambda part: part[0])
    need = run_need(parts)
    prefix = f"{path}: " if path is not None else ""
    require(need, f"{prefix}the run ({what})", remedy, budget)
    return allocating(need, f"running {path or 'the scenario'} ({what})", remedy)
