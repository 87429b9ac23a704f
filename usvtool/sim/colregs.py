"""COLREGs encounters: geometry, classification, latching, the ship domain and run verdicts.

Conventions. Positions are map metres, ``x`` east and ``y`` north. Angles in every argument and
result are compass degrees: 0 = north, clockwise, headings and bearings in ``[0, 360)``. A ship
moves along her heading: her velocity is ``speed · (sin h, cos h)`` (no leeway, no current).
Every function broadcasts its arguments (positions carry a trailing axis of 2), so one call
covers all ``k`` targets of a control step (own ship arrays of shape ``()``, targets ``(k,)``)
or a whole run (own ``(n, 1)``, targets ``(n, k)``); there are no Python loops over targets or
steps, except in :func:`evaluate`'s per-encounter bookkeeping. Class codes are small integers
(``NONE`` … ``OVERTAKEN``) named by :data:`CLASS_NAMES`.

Geometry (own ship O at ``p_o`` heading ``h_o``, target T at ``p_t`` heading ``h_t``)
    ``β`` (:func:`relative_bearing` of T from O): the compass bearing of T from O minus ``h_o``,
    in ``[0, 360)``; ``α``: the same for O seen from T, relative to ``h_t``. Course difference
    ``Δψ = h_t - h_o`` in ``[0, 360)``; ``Δψ = 180 + β - α`` (mod 360) always. Relative position
    ``p = p_t - p_o``, relative velocity ``v = v_t - v_o``.
CPA (:func:`cpa`)
    Straight-line extrapolation: ``tcpa = -p·v / |v|²`` and ``dcpa = |p + tcpa v|``. ``tcpa``
    is not clamped: ``tcpa < 0`` means the ships are moving apart and the CPA is in the past.
    A relative speed below ``VEL_EPS`` (1e-9 m/s) keeps the range constant: then ``tcpa = 0``
    and ``dcpa = |p|`` (finite values, so results stay valid JSON). The target is *closing*
    when ``p·v < 0`` (equivalently ``tcpa > 0``).
Classes (:func:`classify_angles`, the first rule that holds wins)
    1. ``none``: not closing (moving apart, or no relative motion).
    2. ``overtaking`` (own overtakes, Rule 13): ``α`` in the stern sector ``[112.5, 247.5]``
       (more than 22.5° abaft the target's beam) while closing. Closing from that sector is how
       "coming up with" is read; for a target on the same course it is the same as "own
       faster", and unlike a speed test it also covers a slower own ship closing at an angle.
    3. ``overtaken`` (the target overtakes own): ``β`` in ``[112.5, 247.5]`` while closing. The two
       sectors together give ``p·v_t ≥ 0 ≥ p·v_o``, so ``p·v ≥ 0``: they never both hold while
       closing.
    4. ``head-on`` (Rule 14): ``|β| ≤ HEAD_ON_BEARING_DEG`` and ``|α| ≤ HEAD_ON_BEARING_DEG``
       (each sees the other ahead or nearly ahead, Rule 14(b); by ``Δψ = 180 + β - α`` the
       courses are then within 24° of reciprocal). 12° is MOOS-IvP's BHV_AvdColregs
       ``headon_abs_relbng_thresh``, which tests the same two bearings; DNV's trafficgen uses 5°
       on them (``theta14Criteria``).
    5. ``crossing-give-way`` (Rule 15): the target on own starboard side, ``β`` in
       ``[0, 112.5)`` (dead ahead counts as starboard: in doubt, keep clear).
    6. ``crossing-stand-on`` (Rule 17): the target on own port side, ``β`` in ``(247.5, 360)``.
    Every border is closed on the side listed first: 112.5 and 247.5 belong to the stern
    sectors (Rule 13(c): in doubt, assume overtaking), ±12° to head-on. Swapping the ships'
    roles swaps ``β`` and ``α``: head-on stays head-on, overtaking and overtaken swap, and give-way
    and stand-on swap whenever ``β`` and ``α`` lie on opposite sides (always so on a collision
    course; two ships that see each other on the same side are passing clear of each other).
Latching (:class:`EncounterTracker`, :func:`latch_series`)
    An encounter starts (its class is latched) at the first step at which the target is
    classified (not ``none``) and ``dcpa < risk_distance`` and ``0 < tcpa < horizon_s``
    (``RISK_HORIZON_S`` = 120 s). The class is kept, whatever the geometry does, until the
    target is passed: ``tcpa < 0`` and the range larger than at the previous step and at least
    ``clear_distance`` (default ``risk_distance``: not released while still that close), or the
    range beyond ``release_distance`` (default infinite). The releasing step reports ``none``;
    a new encounter with the same target can start from the next step.
Ship domain (:func:`usvtool.encounter.in_domain`, UDWA paper section 4.1)
    The 7 L x 3 L ellipse of :mod:`usvtool.encounter`. *Domain intrusion* is the time during
    which some target is inside (:func:`intrusion_time`, trapezoidal on the samples).
Manoeuvre (on the sampled own track, :func:`evaluate`)
    A manoeuvre is detected at the first sample ``i`` (from the encounter's onset) from which
    the heading changes by at least ``MANOEUVRE_COURSE_DEG`` (5°), or the speed by at least
    ``MANOEUVRE_SPEED_FRACTION`` (10 %) of the speed at ``i`` (at least ``SPEED_FLOOR`` m/s),
    within the following ``MANOEUVRE_WINDOW_S`` (10 s). It starts at the last sample before the
    threshold is crossed whose heading is within ``MANOEUVRE_START_DEG`` (1°) and speed within
    ``MANOEUVRE_START_FRACTION`` (2 %) of those at ``i`` (so a fast turn is not dated up to 10 s
    early). Its course change is the signed heading deviation from ``i`` of largest magnitude
    until the CPA (positive = starboard), its speed change the signed relative speed deviation of
    largest magnitude; its side is starboard/port when the course change is at least 5° either
    way, else none (a speed manoeuvre).

Verdicts (:func:`evaluate`, per encounter; ``r`` the range, ``r_on`` at onset, ``r_crit`` the
critical range, default ``CRITICAL_RANGE_LENGTHS`` = 10 own lengths)
    Give-way roles (head-on, crossing-give-way, overtaking) fail ``rule16-no-action`` without a
    manoeuvre before the CPA; ``rule8-readily-apparent`` unless it changes course by at least
    ``APPARENT_COURSE_DEG`` (30°) or cuts speed by at least ``APPARENT_SPEED_FRACTION`` (50 %);
    ``rule16-in-time`` unless it starts at ``r ≥ TIMELY_RANGE_FRACTION · r_on`` (half) and
    ``r ≥ r_crit`` (waived when ``r_on < r_crit``); ``rule8-safe-distance`` (overtaking:
    ``rule13-keep-clear``) if the target enters the own domain. Head-on also fails
    ``rule14-starboard`` unless the manoeuvre is a starboard alteration, and
    ``rule14-port-to-port`` unless the target is on the own port side at the CPA. Crossing
    give-way fails ``rule15-ahead`` if the own ship crosses the target's heading line ahead of
    her bow. Stand-on roles (crossing-stand-on, overtaken) fail ``rule17-keep-course-speed`` if,
    while ``r ≥ r_crit``, the heading leaves its onset value by more than
    ``STAND_ON_COURSE_DEG`` (10°) or the speed by more than ``STAND_ON_SPEED_FRACTION`` (10 %);
    ``rule17b-no-action`` if the target enters the own domain and no manoeuvre starts once
    ``r < r_crit``; crossing-stand-on fails ``rule17c-port-turn`` if that manoeuvre is to port.
    A Rule 2 departure record of the controller within the encounter excuses the side and
    stand-on rules (:data:`EXCUSABLE`), never Rules 8, 16, 13(a) or 17(b). Sources, and the
    readings of the papers, are in docs/colregs.md.

>>> names = lambda codes: [CLASS_NAMES[c] for c in codes]
>>> own, heading, speed = (0.0, 0.0), 0.0, 4.0
>>> targets = [(0.0, 300.0), (70.0, 80.0), (-80.0, 80.0), (0.0, 90.0)]
>>> names(classify(own, heading, speed, targets, [180.0, 270.0, 90.0, 0.0], [3.0, 4.0, 4.0, 2.0]))
['head-on', 'crossing-give-way', 'crossing-stand-on', 'overtaking']
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from usvtool import metrics
from usvtool.angles import wrap360
from usvtool.encounter import (
    DOMAIN_LENGTH_FACTOR,
    DOMAIN_WIDTH_FACTOR,
    domain_semi_axes,
    in_domain,
)

NONE, HEAD_ON, CROSSING_GIVE_WAY, CROSSING_STAND_ON, OVERTAKING, OVERTAKEN = range(6)
CLASS_NAMES = (
    "none",
    "head-on",
    "crossing-give-way",
    "crossing-stand-on",
    "overtaking",
    "overtaken",
)
CLASSES = CLASS_NAMES  # alias: the name usvtool.sim.sides refers to

#: Rule 13(b): "more than 22.5 degrees abaft her beam", 90 + 22.5 … 270 - 22.5 (closed).
STERN_SECTOR_DEG = (112.5, 247.5)
#: Rule 14: both relative bearings within this of dead ahead (MOOS-IvP BHV_AvdColregsV17: 12).
HEAD_ON_BEARING_DEG = 12.0
#: Latching: a risk must be within this time to CPA (our choice; scenarios close at ≤ 10 m/s).
RISK_HORIZON_S = 120.0
#: Relative speeds below this (m/s) are zero in :func:`cpa`.
VEL_EPS = 1e-9
#: Offsets (m) from a target's heading line below this are on it (for ahead/astern crossings).
LINE_EPS = 1e-6
#: Manoeuvre detection on the sampled track.
MANOEUVRE_COURSE_DEG = 5.0
MANOEUVRE_WINDOW_S = 10.0
MANOEUVRE_SPEED_FRACTION = 0.1
MANOEUVRE_START_DEG = 1.0
MANOEUVRE_START_FRACTION = 0.02
SPEED_FLOOR = 0.01  # m/s: speed thresholds are relative to at least this
#: Rule 8(b) "readily apparent": a course change of at least 30° or a speed reduction to half.
APPARENT_COURSE_DEG = 30.0
APPARENT_SPEED_FRACTION = 0.5
#: Rule 16 "early": the give-way manoeuvre starts before the range halves from the onset...
TIMELY_RANGE_FRACTION = 0.5
#: ... and before the critical range, default 10 own ship lengths (Rule 17(a)(ii)/(b)).
CRITICAL_RANGE_LENGTHS = 10.0
#: Rule 17(a)(i): the stand-on vessel keeps her course within 10° and speed within 10 %.
STAND_ON_COURSE_DEG = 10.0
STAND_ON_SPEED_FRACTION = 0.1

NO_ACTION = "rule16-no-action"
APPARENT = "rule8-readily-apparent"
IN_TIME = "rule16-in-time"
SAFE_DISTANCE = "rule8-safe-distance"
KEEP_CLEAR = "rule13-keep-clear"
STARBOARD_TURN = "rule14-starboard"
PORT_TO_PORT = "rule14-port-to-port"
NOT_AHEAD = "rule15-ahead"
STAND_ON = "rule17-keep-course-speed"
IN_EXTREMIS = "rule17b-no-action"
NOT_PORT = "rule17c-port-turn"
#: Every rule a verdict can fail, and those a Rule 2 departure record excuses.
RULES = (
    NO_ACTION,
    APPARENT,
    IN_TIME,
    SAFE_DISTANCE,
    KEEP_CLEAR,
    STARBOARD_TURN,
    PORT_TO_PORT,
    NOT_AHEAD,
    STAND_ON,
    IN_EXTREMIS,
    NOT_PORT,
)
EXCUSABLE = frozenset({STARBOARD_TURN, PORT_TO_PORT, NOT_AHEAD, STAND_ON, NOT_PORT})


# ----------------------------------------------------------------------------- geometry


def velocity(heading, speed) -> np.ndarray:
    """Velocity vectors ``(..., 2)`` (east, north) of ships on compass ``heading`` at ``speed``.

    >>> velocity([0.0, 90.0], 2.0).round(12).tolist()
    [[0.0, 2.0], [2.0, 0.0]]
    """
    h = np.radians(np.asarray(heading, float))
    s = np.asarray(speed, float)
    return np.stack(np.broadcast_arrays(s * np.sin(h), s * np.cos(h)), axis=-1)


def bearing(from_xy, to_xy) -> np.ndarray:
    """Compass bearing (degrees, ``[0, 360)``) of ``to_xy`` from ``from_xy``; 0 if they coincide.

    >>> bearing((0, 0), [(1, 1), (0, -1), (-1, 0)]).tolist()
    [45.0, 180.0, 270.0]
    """
    d = np.asarray(to_xy, float) - np.asarray(from_xy, float)
    return wrap360(np.degrees(np.arctan2(d[..., 0], d[..., 1])))


def relative_bearing(from_xy, from_heading, to_xy) -> np.ndarray:
    """Bearing of ``to_xy`` seen from a ship at ``from_xy`` heading ``from_heading``: ``[0, 360)``.

    The target from the own ship is ``β = relative_bearing(own_xy, own_heading, target_xy)``;
    the own ship seen from the target is ``α = relative_bearing(target_xy, target_heading,
    own_xy)``.

    >>> relative_bearing((0, 0), 90.0, [(0, 10), (10, 0)]).tolist()
    [270.0, 0.0]
    """
    return wrap360(bearing(from_xy, to_xy) - np.asarray(from_heading, float))


def course_difference(own_heading, target_heading) -> np.ndarray:
    """``Δψ``: the target's heading minus the own ship's, in ``[0, 360)`` (180 = reciprocal).

    >>> float(course_difference(350.0, 170.0)), float(course_difference(10.0, 0.0))
    (180.0, 350.0)
    """
    return wrap360(np.asarray(target_heading, float) - np.asarray(own_heading, float))


def cpa(rel_pos, rel_vel) -> tuple[np.ndarray, np.ndarray]:
    """``(dcpa, tcpa)`` of targets at ``rel_pos`` (target minus own, ``(..., 2)``) moving at
    ``rel_vel`` relative to the own ship; see the module docstring for ``tcpa`` ≤ 0 and zero
    relative velocity.

    >>> d, t = cpa([(70.0, 80.0), (0.0, 100.0)], [(-4.0, -4.0), (0.0, 0.0)])
    >>> d.round(6).tolist(), t.tolist()
    ([7.071068, 100.0], [18.75, 0.0])
    """
    p = np.asarray(rel_pos, float)
    v = np.asarray(rel_vel, float)
    vv = (v * v).sum(axis=-1)
    moving = vv > VEL_EPS * VEL_EPS
    tcpa = np.where(moving, -(p * v).sum(axis=-1) / np.where(moving, vv, 1.0), 0.0)
    at = p + tcpa[..., None] * v
    return np.hypot(at[..., 0], at[..., 1]), tcpa


# ----------------------------------------------------------------------------- classes


def classify_angles(beta, alpha, closing) -> np.ndarray:
    """Class codes (``int8``) from the relative bearings ``β``, ``α`` (degrees) and whether the
    target is closing: the rules of the module docstring, exactly at every border.

    >>> [CLASS_NAMES[c] for c in classify_angles([12.0, 12.5, 0.0, 247.5], [348.0, 350.0,
    ...                                           112.5, 0.0], True)]
    ['head-on', 'crossing-give-way', 'overtaking', 'overtaken']
    """
    beta = wrap360(beta)
    alpha = wrap360(alpha)
    lo, hi = STERN_SECTOR_DEG
    b = HEAD_ON_BEARING_DEG
    cls = np.where(beta < lo, CROSSING_GIVE_WAY, CROSSING_STAND_ON)
    ahead = ((beta <= b) | (beta >= 360.0 - b)) & ((alpha <= b) | (alpha >= 360.0 - b))
    cls = np.where(ahead, HEAD_ON, cls)
    cls = np.where((beta >= lo) & (beta <= hi), OVERTAKEN, cls)
    cls = np.where((alpha >= lo) & (alpha <= hi), OVERTAKING, cls)
    return np.where(np.asarray(closing, bool), cls, NONE).astype(np.int8)


class Situation(NamedTuple):
    """Everything one control step needs about its targets (arrays of one shape)."""

    cls: np.ndarray  # class codes
    beta: np.ndarray  # target's relative bearing from own (deg)
    alpha: np.ndarray  # own's relative bearing from the target (deg)
    range: np.ndarray  # m
    dcpa: np.ndarray  # m
    tcpa: np.ndarray  # s


def assess(own_xy, own_heading, own_speed, target_xy, target_heading, target_speed) -> Situation:
    """Classes, bearings, ranges and CPA of every target (arguments broadcast; module docstring).

    >>> s = assess((0, 0), 0.0, 4.0, [(70.0, 80.0)], [270.0], [4.0])
    >>> CLASS_NAMES[s.cls[0]], round(float(s.beta[0]), 2), round(float(s.tcpa[0]), 9)
    ('crossing-give-way', 41.19, 18.75)
    """
    own_xy = np.asarray(own_xy, float)
    target_xy = np.asarray(target_xy, float)
    p = target_xy - own_xy
    v = velocity(target_heading, target_speed) - velocity(own_heading, own_speed)
    dcpa, tcpa = cpa(p, v)
    beta = relative_bearing(own_xy, own_heading, target_xy)
    alpha = relative_bearing(target_xy, target_heading, own_xy)
    closing = (p * v).sum(axis=-1) < 0.0
    cls = classify_angles(beta, alpha, closing)
    return Situation(cls, beta, alpha, np.hypot(p[..., 0], p[..., 1]), dcpa, tcpa)


def classify(own_xy, own_heading, own_speed, target_xy, target_heading, target_speed):
    """Class codes of targets (``int8``, names in :data:`CLASS_NAMES`): :func:`assess`'s ``cls``."""
    return assess(own_xy, own_heading, own_speed, target_xy, target_heading, target_speed).cls


# ----------------------------------------------------------------------------- latching


class EncounterTracker:
    """Latched encounter classes of ``n_targets`` targets, one :meth:`step` per control step.

    Distances may be scalars or one per target. ``latched`` holds the current codes (``NONE``
    outside an encounter), ``onset_t`` the onset times (NaN outside).

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
        self.risk_distance = np.asarray(risk_distance, float)
        self.horizon_s = float(horizon_s)
        self.clear_distance = (
            self.risk_distance if clear_distance is None else np.asarray(clear_distance, float)
        )
        self.release_distance = np.asarray(release_distance, float)
        self.latched = np.full(n_targets, NONE, np.int8)
        self.onset_t = np.full(n_targets, np.nan)
        self.tcpa = np.full(n_targets, np.nan)
        self._prev_range = np.full(n_targets, np.nan)

    def step(self, t: float, cls, dcpa, tcpa, rng) -> np.ndarray:
        """Advance one step with this step's classes, CPA and ranges; the latched codes (a copy)."""
        cls = np.asarray(cls)
        dcpa, tcpa, rng = (np.asarray(a, float) for a in (dcpa, tcpa, rng))
        active = self.latched != NONE
        release = active & (self._opening(tcpa, rng) | (rng > self.release_distance))
        onset = ~active & _onset(cls, dcpa, tcpa, self.risk_distance, self.horizon_s)
        self.latched = np.where(release, NONE, np.where(onset, cls, self.latched)).astype(np.int8)
        self.onset_t = np.where(onset, float(t), np.where(release, np.nan, self.onset_t))
        self.tcpa = tcpa
        self._prev_range = rng
        return self.latched.copy()

    def update(self, t, own_xy, own_heading, own_speed, target_xy, target_heading, target_speed):
        """:func:`assess` the targets, then :meth:`step`; returns the :class:`Situation`."""
        s = assess(own_xy, own_heading, own_speed, target_xy, target_heading, target_speed)
        self.step(t, s.cls, s.dcpa, s.tcpa, s.range)
        return s

    def most_urgent(self) -> int | None:
        """Index of the latched target with the smallest positive ``tcpa`` (None if none)."""
        urgent = (self.latched != NONE) & (self.tcpa > 0)
        if not urgent.any():
            return None
        return int(np.argmin(np.where(urgent, self.tcpa, np.inf)))

    def _opening(self, tcpa, rng):
        with np.errstate(invalid="ignore"):
            return (tcpa < 0) & (rng > self._prev_range) & (rng >= self.clear_distance)


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


# ----------------------------------------------------------------------------- ship domain


def onset_distance(length: float) -> float:
    """The DCPA below which an encounter begins: the domain's semi-major axis, ``3.5 L``."""
    return domain_semi_axes(length)[0]


def intrusion_time(t, inside) -> float:
    """Seconds during which ``inside`` (``(n,)``, or ``(n, k)``: any target) holds, counting
    each sample interval by the trapezoid rule (half an interval when one end is inside).

    >>> intrusion_time([0.0, 1.0, 2.0, 3.0], [False, True, True, False])
    2.0
    """
    inside = np.asarray(inside, bool)
    if inside.ndim > 1:
        inside = inside.any(axis=tuple(range(1, inside.ndim)))
    t = np.asarray(t, float)
    if len(t) < 2:
        return 0.0
    return float((np.diff(t) * (inside[1:].astype(float) + inside[:-1]) / 2).sum())


# ----------------------------------------------------------------------------- evaluation


def _range_extrema(a: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """Max and min of ``a[lo_i … hi_i]`` (inclusive, ``lo ≤ hi``) for all ``i``: sparse table."""
    n = len(a)
    tmax, tmin = [a], [a]
    width = 1
    while 2 * width <= n:
        m, s = tmax[-1], tmin[-1]
        tmax.append(np.concatenate([np.maximum(m[:-width], m[width:]), m[-width:]]))
        tmin.append(np.concatenate([np.minimum(s[:-width], s[width:]), s[-width:]]))
        width *= 2
    level = np.floor(np.log2(hi - lo + 1)).astype(int)
    tmax, tmin = np.array(tmax), np.array(tmin)
    right = hi - (1 << level) + 1
    return (
        np.maximum(tmax[level, lo], tmax[level, right]),
        np.minimum(tmin[level, lo], tmin[level, right]),
    )


class _Track:
    """The own ship's sampled track with its manoeuvre flags (module docstring)."""

    def __init__(self, t, heading, speed):
        self.t = t
        self.h = np.degrees(np.unwrap(np.radians(heading)))
        self.v = speed
        n = len(t)
        self.end = np.searchsorted(t, t + MANOEUVRE_WINDOW_S, side="right") - 1
        self.thr = MANOEUVRE_SPEED_FRACTION * np.maximum(speed, SPEED_FLOOR)
        lo = np.minimum(np.arange(n) + 1, n - 1)
        hi = np.maximum(self.end, lo)
        valid = self.end > np.arange(n)
        hmax, hmin = _range_extrema(self.h, lo, hi)
        vmax, vmin = _range_extrema(self.v, lo, hi)
        dev_h = np.maximum(hmax - self.h, self.h - hmin)
        dev_v = np.maximum(vmax - self.v, self.v - vmin)
        self.flag = valid & ((dev_h >= MANOEUVRE_COURSE_DEG) | (dev_v >= self.thr))

    def manoeuvre(self, first: int, last: int, extent: int):
        """The first manoeuvre detected at a sample in ``[first, last]``, its extent measured up
        to sample ``extent``: ``(start index, course change deg, speed change or None)``."""
        hits = np.flatnonzero(self.flag[first : last + 1])
        if not hits.size:
            return None
        i = first + int(hits[0])
        h0, v0 = self.h[i], self.v[i]
        win = slice(i + 1, self.end[i] + 1)
        over = (np.abs(self.h[win] - h0) >= MANOEUVRE_COURSE_DEG) | (
            np.abs(self.v[win] - v0) >= self.thr[i]
        )
        cross = i + 1 + int(np.argmax(over))
        seg = slice(i, cross)
        v_tol = MANOEUVRE_START_FRACTION * max(v0, SPEED_FLOOR)
        calm = np.abs(self.h[seg] - h0) <= MANOEUVRE_START_DEG
        calm &= np.abs(self.v[seg] - v0) <= v_tol
        start = i + int(np.flatnonzero(calm)[-1])
        span = slice(start, max(extent, cross) + 1)
        dh = self.h[span] - h0
        dv = self.v[span] - v0
        course = float(dh[np.argmax(np.abs(dh))])
        speed = float(dv[np.argmax(np.abs(dv))] / v0) if v0 > 0 else None
        return start, course, speed


def _side(beta: float) -> str:
    s, c = np.sin(np.radians(beta)), np.cos(np.radians(beta))
    if abs(s) > 1e-12:
        return "starboard" if s > 0 else "port"
    return "ahead" if c > 0 else "astern"


def _crossing(own_xy, target_xy, target_heading) -> str | None:
    """Whether the own ship first crosses the target's heading line ahead of or astern of her."""
    d = own_xy - target_xy
    h = np.radians(target_heading)
    along = d[:, 0] * np.sin(h) + d[:, 1] * np.cos(h)
    lateral = d[:, 0] * np.cos(h) - d[:, 1] * np.sin(h)
    lateral = np.where(np.abs(lateral) < LINE_EPS, 0.0, lateral)  # on the line: rounding
    # a side change from a nonzero lateral offset (starting on the line is not a crossing)
    flips = np.flatnonzero((lateral[:-1] != 0) & (lateral[:-1] * lateral[1:] <= 0))
    if not flips.size:
        return None
    i = int(flips[0])
    f = lateral[i] / (lateral[i] - lateral[i + 1])
    return "ahead" if along[i] + f * (along[i + 1] - along[i]) > 0 else "astern"


def _num(x, digits: int = 3):
    if x is None or not np.isfinite(x):
        return None
    return round(float(x), digits)


def evaluate(
    t,
    own_x,
    own_y,
    own_heading,
    own_speed,
    target_x,
    target_y,
    target_heading,
    target_speed,
    own_length: float,
    target_length=None,
    rule2=None,
    *,
    risk_distance=None,
    horizon_s: float = RISK_HORIZON_S,
    clear_distance=None,
    release_distance=np.inf,
    critical_range=None,
) -> dict:
    """Encounters, manoeuvres and verdicts of a finished run, as plain JSON-ready data.

    ``t`` and the own ship's arrays are ``(n,)``; the targets' are ``(n, k)`` (or ``(n,)`` for
    one target); ``target_length`` (scalar or ``(k,)``) only feeds ``own_in_target_domain_s``.
    ``rule2`` lists the controller's Rule 2 departure records ``{"t", "target", "reason"}``
    (target = index). Defaults: ``risk_distance`` = the domain's semi-major axis ``3.5 L``,
    ``clear_distance`` = ``risk_distance``, ``critical_range`` = ``10 L``.

    Returns ``{"events": [...], "figures": {...}, "thresholds": {...}, "unmatched_rule2":
    [...]}``. Each event is one encounter (a target without one gets a single event of class
    ``none``, ``compliant`` None): ``target``, ``class``, ``onset_s``, ``onset_range_m``,
    ``released_s``, ``cpa_time_s``, ``closest_distance_m``, ``passing_side`` (the side of the
    own ship the target is on at the CPA), ``crossing`` (where the own ship first passes from
    one side of the target's heading line to the other between onset and release: ``ahead`` of
    her bow, ``astern``, or None), ``first_manoeuvre`` (``t``, ``side``, ``course_change_deg``,
    ``speed_change``, ``range_m``, or None), ``domain_intrusion_s``, ``own_in_target_domain_s``,
    ``rule2_departure`` (the records in the encounter, or None), ``compliant``, ``failed_rules``
    and ``excused_rules`` (failures excused by a Rule 2 record). ``figures``:
    :func:`usvtool.metrics.run_distances` (``closest_distance_m`` to any target,
    ``average_distance_m`` to the nearest target over the steps with a latched encounter),
    ``domain_intrusion_s`` (some target inside); distances to 1 mm.
    ``thresholds`` echoes the values used (an infinite ``release_distance`` is null);
    ``unmatched_rule2`` the records that fall in no encounter of their target.
    """
    t = np.asarray(t, float)
    n = len(t)
    own_h = np.asarray(own_heading, float)
    own_v = np.asarray(own_speed, float)
    own_xy = np.stack([np.asarray(own_x, float), np.asarray(own_y, float)], axis=-1)
    tx, ty, th, tv = (
        np.asarray(a, float).reshape(n, -1)
        for a in (target_x, target_y, target_heading, target_speed)
    )
    k = tx.shape[1]
    txy = np.stack([tx, ty], axis=-1)
    length = float(own_length)
    t_len = np.broadcast_to(
        np.asarray(length if target_length is None else target_length, float), (k,)
    )
    risk = onset_distance(length) if risk_distance is None else risk_distance
    r_crit = CRITICAL_RANGE_LENGTHS * length if critical_range is None else float(critical_range)
    sit = assess(own_xy[:, None], own_h[:, None], own_v[:, None], txy, th, tv)
    latched = latch_series(
        sit.cls, sit.dcpa, sit.tcpa, sit.range, risk, horizon_s, clear_distance, release_distance
    )
    inside = in_domain(own_xy[:, None], own_h[:, None], txy, length)
    own_inside = in_domain(txy, th, own_xy[:, None], t_len)
    track = _Track(t, own_h, own_v)
    records = [dict(r) for r in (rule2 or [])]
    matched = [False] * len(records)
    events = []
    for j in range(k):
        col = latched[:, j]
        edges = np.flatnonzero(np.diff(np.concatenate([[0], (col != NONE).astype(int), [0]])))
        if not edges.size:
            events.append(_no_encounter(j, sit.range[:, j]))
            continue
        for on, off in edges.reshape(-1, 2):
            last = off - 1
            window = slice(on, last + 1)
            i_cpa = on + int(np.argmin(sit.range[window, j]))
            mine = [
                q
                for q, r in enumerate(records)
                if int(r.get("target", -1)) == j
                and t[on] <= float(r.get("t", np.nan)) <= t[min(off, n - 1)]
            ]
            for q in mine:
                matched[q] = True
            event = _verdict(
                j,
                int(col[on]),
                t,
                on,
                last,
                off < n,
                i_cpa,
                sit,
                track,
                inside[:, j],
                own_inside[:, j],
                _crossing(own_xy[window], txy[window, j], th[window, j]),
                r_crit,
                [records[q] for q in mine],
            )
            events.append(event)
    distances = metrics.run_distances(own_xy[:, 0], own_xy[:, 1], tx, ty,
                                      (latched != NONE).any(axis=1))  # fmt: skip
    figures = {
        **{name: _num(value) for name, value in distances.items()},
        "domain_intrusion_s": _num(intrusion_time(t, inside) if k else 0.0),
    }
    thresholds = {
        "risk_distance_m": _num(float(np.max(risk))),
        "horizon_s": horizon_s,
        "clear_distance_m": _num(float(np.max(risk if clear_distance is None else clear_distance))),
        "release_distance_m": _num(float(np.max(release_distance))),
        "critical_range_m": _num(r_crit),
        "head_on_bearing_deg": HEAD_ON_BEARING_DEG,
        "stern_sector_deg": list(STERN_SECTOR_DEG),
        "domain_axes_m": [DOMAIN_LENGTH_FACTOR * length, DOMAIN_WIDTH_FACTOR * length],
        "manoeuvre": {
            "course_deg": MANOEUVRE_COURSE_DEG,
            "window_s": MANOEUVRE_WINDOW_S,
            "speed_fraction": MANOEUVRE_SPEED_FRACTION,
        },
        "apparent": {"course_deg": APPARENT_COURSE_DEG, "speed_reduction": APPARENT_SPEED_FRACTION},
        "timely_range_fraction": TIMELY_RANGE_FRACTION,
        "stand_on": {"course_deg": STAND_ON_COURSE_DEG, "speed_fraction": STAND_ON_SPEED_FRACTION},
    }
    unmatched = [r for r, m in zip(records, matched, strict=True) if not m]
    return {
        "events": events,
        "figures": figures,
        "thresholds": thresholds,
        "unmatched_rule2": unmatched,
    }


def _no_encounter(j: int, rng: np.ndarray) -> dict:
    return {
        "target": j,
        "class": "none",
        "onset_s": None,
        "onset_range_m": None,
        "released_s": None,
        "cpa_time_s": None,
        "closest_distance_m": _num(rng.min()) if len(rng) else None,
        "passing_side": None,
        "crossing": None,
        "first_manoeuvre": None,
        "domain_intrusion_s": None,
        "own_in_target_domain_s": None,
        "rule2_departure": None,
        "compliant": None,
        "failed_rules": [],
        "excused_rules": [],
    }


def _verdict(
    j, code, t, on, last, released, i_cpa, sit, track, inside, own_inside, crossing, r_crit, rule2
) -> dict:
    """One encounter's event and verdict (the rules are listed in docs/colregs.md)."""
    rng = sit.range[:, j]
    window = slice(on, last + 1)
    r_on = float(rng[on])
    side = _side(float(sit.beta[i_cpa, j]))
    man = track.manoeuvre(on, i_cpa, i_cpa)
    first = None
    if man is not None:
        s, course, speed = man
        first = {
            "t": _num(t[s]),
            "side": "starboard"
            if course >= MANOEUVRE_COURSE_DEG
            else "port"
            if course <= -MANOEUVRE_COURSE_DEG
            else None,
            "course_change_deg": _num(course),
            "speed_change": _num(speed, 4),
            "range_m": _num(rng[s]),
        }
    intruded = bool(inside[window].any())
    failed = []
    if code in (HEAD_ON, CROSSING_GIVE_WAY, OVERTAKING):
        if man is None:
            failed.append(NO_ACTION)
        else:
            s, course, speed = man
            apparent = abs(course) >= APPARENT_COURSE_DEG or (
                speed is not None and speed <= -APPARENT_SPEED_FRACTION
            )
            if not apparent:
                failed.append(APPARENT)
            r_man = float(rng[s])
            timely = r_man >= TIMELY_RANGE_FRACTION * r_on and (r_man >= r_crit or r_on < r_crit)
            if not timely:
                failed.append(IN_TIME)
        if intruded:
            failed.append(KEEP_CLEAR if code == OVERTAKING else SAFE_DISTANCE)
        if code == HEAD_ON:
            if first is None or first["side"] != "starboard":
                failed.append(STARBOARD_TURN)
            if side != "port":
                failed.append(PORT_TO_PORT)
        if code == CROSSING_GIVE_WAY and crossing == "ahead":
            failed.append(NOT_AHEAD)
    elif code in (CROSSING_STAND_ON, OVERTAKEN):
        below = np.flatnonzero(rng[on : i_cpa + 1] < r_crit)
        i_crit = on + int(below[0]) if below.size else i_cpa + 1
        if i_crit > on:
            keep = slice(on, i_crit)
            dh = np.abs(track.h[keep] - track.h[on]).max()
            dv = np.abs(track.v[keep] - track.v[on]).max()
            if dh > STAND_ON_COURSE_DEG or dv > STAND_ON_SPEED_FRACTION * max(
                track.v[on], SPEED_FLOOR
            ):
                failed.append(STAND_ON)
        late = track.manoeuvre(i_crit, i_cpa, i_cpa) if i_crit <= i_cpa else None
        if late is None and intruded:
            failed.append(IN_EXTREMIS)
        if code == CROSSING_STAND_ON and late is not None and late[1] <= -MANOEUVRE_COURSE_DEG:
            failed.append(NOT_PORT)
    excused = [r for r in failed if rule2 and r in EXCUSABLE]
    failed = [r for r in failed if r not in excused]
    return {
        "target": j,
        "class": CLASS_NAMES[code],
        "onset_s": _num(t[on]),
        "onset_range_m": _num(r_on),
        "released_s": _num(t[last + 1]) if released else None,
        "cpa_time_s": _num(t[i_cpa]),
        "closest_distance_m": _num(rng[i_cpa]),
        "passing_side": side,
        "crossing": crossing,
        "first_manoeuvre": first,
        "domain_intrusion_s": _num(intrusion_time(t[window], inside[window])),
        "own_in_target_domain_s": _num(intrusion_time(t[window], own_inside[window])),
        "rule2_departure": rule2 or None,
        "compliant": not failed,
        "failed_rules": failed,
        "excused_rules": excused,
    }
