"""Encounter tracking for the run: each target's COLREGs class latched for its encounter.

The simulation classifies every target at every control step (:func:`usvtool.encounter.assess`,
compass degrees, compiled for the step: :mod:`usvtool.sim.tracking_kernels`) and latches the
class here; the controller's side rule follows the most urgent latched encounter. The verdicts
of a finished run (:mod:`usvtool.sim.verdicts`) latch the whole run at once with
:func:`latch_series`, which gives what the step-by-step tracker gives.

Latching (:class:`EncounterTracker`, :func:`latch_series`)
    An encounter starts (its class is latched) at the first step at which the target is
    classified (not ``none``) and ``dcpa < risk_distance`` and ``0 < tcpa < horizon_s``
    (``RISK_HORIZON_S`` = 120 s). The class is kept, whatever the geometry does, until the
    target is passed: ``tcpa < 0`` and the range larger than at the previous step and at least
    ``clear_distance`` (default ``risk_distance``: not released while still that close), or the
    range beyond ``release_distance`` (default infinite). The releasing step reports ``none``;
    a new encounter with the same target can start from the next step.
"""

from __future__ import annotations

import numpy as np

from usvtool.encounter import NONE, Situation, domain_semi_axes

#: Latching: a risk must be within this time to CPA (our choice; scenarios close at ≤ 10 m/s).
RISK_HORIZON_S = 120.0


def onset_distance(length: float) -> float:
    """The DCPA below which an encounter begins: the domain's semi-major axis, ``3.5 L``."""
    return domain_semi_axes(length)[0]


class EncounterTracker:
    """Latched encounter classes of ``n_targets`` targets, one :meth:`step` per control step.

    Distances may be scalars or one per target. ``latched`` holds the current codes (``NONE``
    outside an encounter), ``onset_t`` the onset times (NaN outside).

    >>> from usvtool.encounter import CROSSING_GIVE_WAY, HEAD_ON
    >>> tr = EncounterTracker(1, risk_distance=20.0)
    >>> [int(tr.step(t, [c], [d], [tc], [r])[0]) for t, c, d, tc, r in [
    ...     (0, HEAD_ON, 5, 30, 300), (1, CROSSING_GIVE_WAY, 5, 20, 200),  # latched, then kept
    ...     (2, NONE, 30, -1, 25), (3, NONE, 30, -2, 40)]]  # range fell; then opening past 20 m
    [1, 1, 1, 0]
    """

    def __init__(
        self,
        n_targets: int,
        risk_distance,
        horizon_s: float = RISK_HORIZON_S,
        clear_distance=None,
        release_distance=np.inf,
    ):
        from usvtool.lazy_kernels import load
        from usvtool.sim import tracking_kernels  # numba's import: a run's, not the CLI's

        self._kernels = tracking_kernels
        load(tracking_kernels, "track_urgent", "first_touching")  # a run's step's
        self.risk_distance = np.asarray(risk_distance, float)
        self.horizon_s = float(horizon_s)
        self.clear_distance = (
            self.risk_distance if clear_distance is None else np.asarray(clear_distance, float)
        )
        self.release_distance = np.asarray(release_distance, float)
        self._limits = tuple(
            _per_target(d, n_targets, float)
            for d in (self.risk_distance, self.clear_distance, self.release_distance)
        )
        self.latched = np.full(n_targets, NONE, np.int8)
        self.onset_t = np.full(n_targets, np.nan)
        self.tcpa = np.full(n_targets, np.nan)
        self._prev_range = np.full(n_targets, np.nan)
        self._scratch = None  # update_urgent's classes and situation, overwritten each step

    def step(self, t: float, cls, dcpa, tcpa, rng) -> np.ndarray:
        """Advance one step with this step's classes, CPA and ranges; the latched codes (a copy)."""
        k = self.latched.size
        self._kernels.latch(float(t), _per_target(cls, k, np.int8),
                            *(_per_target(a, k, float) for a in (dcpa, tcpa, rng)),
                            *self._limits, self.horizon_s, *self._state)  # fmt: skip
        return self.latched.copy()

    def update(self, t, own_xy, own_heading, own_speed, target_xy, target_heading, target_speed):
        """:func:`usvtool.encounter.assess` the targets, then :meth:`step`, in one compiled call
        (:func:`usvtool.sim.tracking_kernels.track`: the same bits); returns the
        :class:`~usvtool.encounter.Situation`."""
        k = self.latched.size
        cls, out = np.empty(k, np.int8), np.empty((5, k))
        self._kernels.track(float(t), float(own_xy[0]), float(own_xy[1]), float(own_heading),
                            float(own_speed), np.ascontiguousarray(target_xy, float).reshape(k, 2),
                            _per_target(target_heading, k, float),
                            _per_target(target_speed, k, float), *self._limits, self.horizon_s,
                            *self._state, cls, out)  # fmt: skip
        return Situation(cls, *out)

    def update_urgent(self, t, own_x, own_y, own_heading, own_speed, target_xy,
                      target_heading, target_speed) -> int | None:  # fmt: skip
        """:meth:`update`, then :meth:`most_urgent`, in one compiled call
        (:func:`usvtool.sim.tracking_kernels.track_urgent`), the situation not kept: a run's
        step. The targets' arrays are the kernel's (C-ordered float64, ``(k, 2)`` and
        ``(k,)``, as a run holds them)."""
        k = self.latched.size
        if self._scratch is None:
            self._scratch = np.empty(k, np.int8), np.empty((5, k))
        at = self._kernels.track_urgent(float(t), float(own_x), float(own_y), float(own_heading),
                                        float(own_speed), target_xy, target_heading, target_speed,
                                        *self._limits, self.horizon_s, *self._state,
                                        *self._scratch)  # fmt: skip
        return None if at < 0 else at

    def most_urgent(self) -> int | None:
        """Index of the latched target with the smallest positive ``tcpa`` (None if none)."""
        at = self._kernels.most_urgent(self.latched, self.tcpa)
        return None if at < 0 else at

    @property
    def _state(self) -> tuple:
        """The arrays the kernels update in place."""
        return self.latched, self.onset_t, self.tcpa, self._prev_range


def _per_target(a, k: int, dtype) -> np.ndarray:
    """``a`` as a writeable contiguous ``(k,)`` array of ``dtype`` (the kernels' arguments; a
    scalar for every target), copied only when it is not one."""
    a = np.ascontiguousarray(a, dtype)
    return a if a.shape == (k,) and a.flags.writeable else np.broadcast_to(a, (k,)).copy()


def _onset(cls, dcpa, tcpa, risk_distance, horizon_s):
    return (cls != NONE) & (dcpa < risk_distance) & (tcpa > 0) & (tcpa < horizon_s)


def latch_series(
    cls,
    dcpa,
    tcpa,
    rng,
    risk_distance,
    horizon_s: float = RISK_HORIZON_S,
    clear_distance=None,
    release_distance=np.inf,
) -> np.ndarray:
    """The latched codes ``(n, k)`` that :class:`EncounterTracker` gives on a whole run
    (arrays ``(n, k)``, step along axis 0), vectorised over steps and targets.

    The onset and release conditions of a step do not depend on the latch, so the latch is the
    alternation of first passages: the first onset, the first release after it, the first onset
    after that, …, found for all targets at once, one round per encounter.

    >>> latch_series([[1], [2], [0], [0], [3]], [[5], [5], [30], [30], [5]],
    ...              [[30], [20], [-1], [-2], [9]], [[300], [200], [25], [40], [100]], 20.0)[:, 0]
    array([1, 1, 1, 0, 3], dtype=int8)
    """
    cls = np.asarray(cls)
    dcpa, tcpa, rng = (np.asarray(a, float) for a in (dcpa, tcpa, rng))
    n, k = cls.shape
    clear = risk_distance if clear_distance is None else clear_distance
    prev = np.vstack([np.full((1, k), np.nan), rng[:-1]])
    with np.errstate(invalid="ignore"):
        opening = (tcpa < 0) & (rng > prev) & (rng >= np.asarray(clear, float))
    release = opening | (rng > np.asarray(release_distance, float))
    next_on = _next_true(_onset(cls, dcpa, tcpa, np.asarray(risk_distance, float), horizon_s))
    next_off = _next_true(release)
    cols = np.arange(k)
    cursor = np.zeros(k, int)
    delta = np.zeros((n + 1, k), int)
    start = np.zeros((n, k), bool)
    while True:
        on = next_on[cursor, cols]
        live = on < n
        if not live.any():
            break
        off = next_off[np.minimum(on + 1, n), cols]
        delta[on[live], cols[live]] += 1
        delta[off[live], cols[live]] -= 1
        start[on[live], cols[live]] = True
        cursor = np.where(live, np.minimum(off + 1, n), n)
    active = np.cumsum(delta[:-1], axis=0) > 0
    first = np.maximum.accumulate(np.where(start, np.arange(n)[:, None], 0), axis=0)
    return np.where(active, np.take_along_axis(cls, first, axis=0), NONE).astype(np.int8)


def _next_true(mask: np.ndarray) -> np.ndarray:
    """``(n + 1, k)``: the first index ``≥ i`` where ``mask[:, j]`` holds, ``n`` if none."""
    n = mask.shape[0]
    idx = np.where(mask, np.arange(n)[:, None], n)
    idx = np.vstack([idx, np.full((1, mask.shape[1]), n)])
    return np.minimum.accumulate(idx[::-1], axis=0)[::-1]
