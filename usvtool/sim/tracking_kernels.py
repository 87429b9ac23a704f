"""Compiled kernels of the encounter tracker (:mod:`usvtool.sim.tracking`), with numba.

The run classifies every target at every control step and latches the classes: done with
NumPy, some 60 array calls on arrays of a few targets cost 0.1-0.2 ms a step, a quarter of a
family run's time (docs/batch.md, "Figures"); here each step is one loop over the targets.

:func:`assess` is :func:`usvtool.encounter.assess` (the contract, which stays the reference:
the verdicts and the scene families call it on whole runs and scenes), and :func:`latch` the
latching rule of :mod:`usvtool.sim.tracking`'s docstring (its one definition: the tracker's
``step``). Each repeats the NumPy expressions operation by operation: ``np.radians`` and
``np.degrees`` are the products by ``pi / 180`` and ``180 / pi``, ``np.mod`` is Python's ``%``
(both the floor modulo), a sum over the last axis of 2 is ``0.0 + a + b``, and ``sin``,
``cos``, ``atan2`` and ``hypot`` are the C library's in both; no fused multiply-add (numba
contracts none without ``fastmath``). So classes, bearings, ranges and CPA are the same bits
(tests/sim/test_tracking_kernels.py compares them on random and border geometries).

Each kernel's signature is compiled, or loaded from numba's cache, at its first call
(:func:`usvtool.lazy_kernels.declared`), not at import; imported lazily, by
:class:`usvtool.sim.tracking.EncounterTracker` when it is made, so that reading a scenario or
building the command line does not import numba. numba's cache keys a kernel on this file only: the
thresholds imported from :mod:`usvtool.encounter` are compiled in as constants, so after changing
one there, remove ``usvtool/sim/__pycache__/tracking_kernels.*.nb*`` (or touch this file)."""

from __future__ import annotations

import math

import numpy as np
from numba import types as nt

from usvtool.encounter import (
    CROSSING_GIVE_WAY,
    CROSSING_STAND_ON,
    HEAD_ON,
    HEAD_ON_BEARING_DEG,
    NONE,
    OVERTAKEN,
    OVERTAKING,
    STERN_SECTOR_DEG,
    VEL_EPS,
)
from usvtool.lazy_kernels import declared

_F, _I, _K = nt.float64, nt.int64, nt.int8
_OPTIONS = {"cache": True, "nogil": True}
_LO, _HI = STERN_SECTOR_DEG
_RADIANS, _DEGREES = math.pi / 180.0, 180.0 / math.pi  # np.radians's and np.degrees's factors


@declared(_F(_F), inline="always", **_OPTIONS)
def _wrap360(deg) -> float:
    """:func:`usvtool.angles.wrap360` of one angle."""
    a = deg % 360.0
    return a - 360.0 if a >= 360.0 else a


@declared(_F(_F, _F, _F), inline="always", **_OPTIONS)
def _relative_bearing(dx, dy, heading) -> float:
    """:func:`usvtool.encounter.relative_bearing` of the offset ``(dx, dy)`` (to minus from)."""
    return _wrap360(_wrap360(math.atan2(dx, dy) * _DEGREES) - heading)


@declared(_K(_F, _F, nt.boolean), inline="always", **_OPTIONS)
def classify_angles(beta, alpha, closing) -> int:
    """:func:`usvtool.encounter.classify_angles` of one target."""
    beta, alpha = _wrap360(beta), _wrap360(alpha)
    b = HEAD_ON_BEARING_DEG
    if not closing:
        return NONE
    if _LO <= alpha <= _HI:
        return OVERTAKING
    if _LO <= beta <= _HI:
        return OVERTAKEN
    if (beta <= b or beta >= 360.0 - b) and (alpha <= b or alpha >= 360.0 - b):
        return HEAD_ON
    return CROSSING_GIVE_WAY if beta < _LO else CROSSING_STAND_ON


@declared(nt.void(_F, _F, _F, _F, _F[:, ::1], _F[::1], _F[::1], _K[::1], _F[:, ::1]),
          **_OPTIONS)
def assess(own_x, own_y, own_heading, own_speed, target_xy, target_heading, target_speed, cls,
           out) -> None:  # fmt: skip
    """:func:`usvtool.encounter.assess` of ``k`` targets (``target_xy`` ``(k, 2)``, headings
    and speeds ``(k,)``) seen from one own ship, into ``cls`` ``(k,)`` and the rows of ``out``
    ``(5, k)``: the :class:`usvtool.encounter.Situation`'s ``cls`` and ``beta``, ``alpha``,
    ``range``, ``dcpa``, ``tcpa`` (arrays handed in: numba's boxing of returned arrays would
    cost more than the arithmetic)."""
    h = own_heading * _RADIANS
    own_vx, own_vy = own_speed * math.sin(h), own_speed * math.cos(h)
    for j in range(target_xy.shape[0]):
        tx, ty = target_xy[j, 0], target_xy[j, 1]
        px, py = tx - own_x, ty - own_y
        h = target_heading[j] * _RADIANS
        vx = target_speed[j] * math.sin(h) - own_vx
        vy = target_speed[j] * math.cos(h) - own_vy
        vv = 0.0 + vx * vx + vy * vy
        pv = 0.0 + px * vx + py * vy
        t = -pv / vv if vv > VEL_EPS * VEL_EPS else 0.0
        beta = _relative_bearing(px, py, own_heading)
        alpha = _relative_bearing(own_x - tx, own_y - ty, target_heading[j])
        cls[j] = classify_angles(beta, alpha, pv < 0.0)
        out[0, j], out[1, j], out[2, j] = beta, alpha, math.hypot(px, py)
        out[3, j], out[4, j] = math.hypot(px + t * vx, py + t * vy), t


_ARRAY = _F[::1]


@declared(nt.void(_F, _K[::1], _ARRAY, _ARRAY, _ARRAY, _ARRAY, _ARRAY, _ARRAY, _F,  # the step
              _K[::1], _ARRAY, _ARRAY, _ARRAY),  # the tracker's state, updated
      **_OPTIONS)  # fmt: skip
def latch(t, cls, dcpa, tcpa, rng, risk, clear, release, horizon, latched, onset_t, last_tcpa,
          prev_range):  # fmt: skip
    """One step of the latch (:mod:`usvtool.sim.tracking`'s docstring) for each target: an
    encounter starts where none is latched, the target is classified, ``dcpa < risk`` and ``0 <
    tcpa < horizon``; a latched one is released (``NONE``) when opening (``tcpa < 0``, the range
    above ``prev_range`` and at least ``clear``) or beyond ``release``. Updates the state:
    ``latched``, ``onset_t`` (``t`` at an onset, NaN at a release), ``last_tcpa`` (this step's
    ``tcpa``) and ``prev_range`` (this step's range)."""
    for j in range(cls.shape[0]):
        if latched[j] != NONE:
            opening = tcpa[j] < 0 and rng[j] > prev_range[j] and rng[j] >= clear[j]
            if opening or rng[j] > release[j]:
                latched[j] = NONE
                onset_t[j] = np.nan
        elif cls[j] != NONE and dcpa[j] < risk[j] and 0 < tcpa[j] < horizon:
            latched[j] = cls[j]
            onset_t[j] = t
        last_tcpa[j] = tcpa[j]
        prev_range[j] = rng[j]


_TARGETS = (_F[:, ::1], _ARRAY, _ARRAY)
_STATE = (_K[::1], _ARRAY, _ARRAY, _ARRAY)


@declared(nt.void(_F, _F, _F, _F, _F, *_TARGETS, _ARRAY, _ARRAY, _ARRAY, _F, *_STATE, _K[::1],
              _F[:, ::1]), **_OPTIONS)  # fmt: skip
def track(t, own_x, own_y, own_heading, own_speed, target_xy, target_heading, target_speed, risk,
          clear, release, horizon, latched, onset_t, last_tcpa, prev_range, cls,
          out) -> None:  # fmt: skip
    """A control step of the tracker in one call: :func:`assess` into ``cls`` and ``out``, then
    :func:`latch` of its classes, CPA and ranges."""
    assess(own_x, own_y, own_heading, own_speed, target_xy, target_heading, target_speed, cls,
           out)  # fmt: skip
    latch(t, cls, out[3], out[4], out[2], risk, clear, release, horizon, latched, onset_t,
          last_tcpa, prev_range)  # fmt: skip


@declared(_I(_K[::1], _ARRAY), **_OPTIONS)
def most_urgent(latched, tcpa) -> int:
    """The index of the latched target with the smallest positive ``tcpa``, the first of equals
    (``np.argmin`` of those ``tcpa``, ``inf`` elsewhere); -1 if none is latched with a positive
    one."""
    best, at, urgent = np.inf, 0, False
    for j in range(latched.shape[0]):
        if latched[j] != NONE and tcpa[j] > 0:
            urgent = True
            if tcpa[j] < best:
                best, at = tcpa[j], j
    return at if urgent else -1


@declared(_I(_F, _F, _F, _F, _F, *_TARGETS, _ARRAY, _ARRAY, _ARRAY, _F, *_STATE, _K[::1],
         _F[:, ::1]), **_OPTIONS)  # fmt: skip
def track_urgent(t, own_x, own_y, own_heading, own_speed, target_xy, target_heading,
                 target_speed, risk, clear, release, horizon, latched, onset_t, last_tcpa,
                 prev_range, cls, out) -> int:  # fmt: skip
    """:func:`track`, then :func:`most_urgent` of the latch (a run's step: one call)."""
    track(t, own_x, own_y, own_heading, own_speed, target_xy, target_heading, target_speed,
          risk, clear, release, horizon, latched, onset_t, last_tcpa, prev_range, cls,
          out)  # fmt: skip
    return most_urgent(latched, last_tcpa)


@declared(_I(_F[:, ::1], _F, _F, _ARRAY), **_OPTIONS)
def first_touching(target_xy, x, y, reach) -> int:
    """The first target whose centre lies closer than ``reach`` to the own ship's ``(x, y)``
    (the run's collision test: ``np.hypot`` of the offsets below ``reach``, ``hypot`` the C
    library's in both); -1 for none."""
    for j in range(target_xy.shape[0]):
        if math.hypot(target_xy[j, 0] - x, target_xy[j, 1] - y) < reach[j]:
            return j
    return -1
