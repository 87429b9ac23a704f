"""Encounters between ships: geometry, CPA, the COLREGs classes and the ship domain.

A contract below the stages: the simulation classifies its targets with it, step by step
(:mod:`usvtool.sim.tracking`, through a compiled copy of :func:`assess` that gives the same bits,
:mod:`usvtool.sim.tracking_kernels`: a change here is made there too, and
tests/sim/test_tracking_kernels.py compares the two) and over a finished run
(:mod:`usvtool.sim.verdicts`), its controllers keep the targets out of the domain, the report
draws the domain. It imports no stage, so any stage (one of recorded AIS encounters too)
classifies with the same classifier.

Conventions. Positions are map metres, ``x`` east and ``y`` north. Angles in every argument and
result are compass degrees: 0 = north, clockwise, headings and bearings in ``[0, 360)``
(:mod:`usvtool.angles`). A ship moves along her heading: her velocity is ``speed · (sin h, cos
h)`` (no leeway, no current). Every function broadcasts its arguments (positions carry a
trailing axis of 2), so one call covers all ``k`` targets of a control step (own ship arrays of
shape ``()``, targets ``(k,)``) or a whole run (own ``(n, 1)``, targets ``(n, k)``); there are
no Python loops over targets or steps. Class codes are small integers (``NONE`` …
``OVERTAKEN``) named by :data:`CLASS_NAMES`.

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
Ship domain (:func:`in_domain`, UDWA paper section 4.1)
    An ellipse centred on the own ship, its major axis ``7 L`` along her heading and its minor
    axis ``3 L`` across (semi-axes 3.5 L and 1.5 L, ``L`` her length). A target (its reference
    point) is inside when ``(a / 3.5 L)² + (c / 1.5 L)² ≤ 1`` (closed), ``a`` and ``c`` its
    along- and across-heading offsets (:func:`domain_ellipse`).

Sources, and the readings of the papers, are in docs/colregs.md.

>>> names = lambda codes: [CLASS_NAMES[c] for c in codes]
>>> own, heading, speed = (0.0, 0.0), 0.0, 4.0
>>> targets = [(0.0, 300.0), (70.0, 80.0), (-80.0, 80.0), (0.0, 90.0)]
>>> names(classify(own, heading, speed, targets, [180.0, 270.0, 90.0, 0.0], [3.0, 4.0, 4.0, 2.0]))
['head-on', 'crossing-give-way', 'crossing-stand-on', 'overtaking']
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from usvtool.angles import wrap360

NONE, HEAD_ON, CROSSING_GIVE_WAY, CROSSING_STAND_ON, OVERTAKING, OVERTAKEN = range(6)
CLASS_NAMES = (
    "none",
    "head-on",
    "crossing-give-way",
    "crossing-stand-on",
    "overtaking",
    "overtaken",
)

#: Rule 13(b): "more than 22.5 degrees abaft her beam", 90 + 22.5 … 270 - 22.5 (closed).
STERN_SECTOR_DEG = (112.5, 247.5)
#: Rule 14: both relative bearings within this of dead ahead (MOOS-IvP BHV_AvdColregsV17: 12).
HEAD_ON_BEARING_DEG = 12.0
#: Relative speeds below this (m/s) are zero in :func:`cpa`.
VEL_EPS = 1e-9
#: UDWA section 4.1: the domain's axes, in ship lengths ("seven times ... thrice ...").
DOMAIN_LENGTH_FACTOR = 7.0
DOMAIN_WIDTH_FACTOR = 3.0


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


# ----------------------------------------------------------------------------- ship domain


def domain_semi_axes(length) -> tuple:
    """The domain's semi-axes ``(along, across)`` of a ship of ``length``: 3.5 L and 1.5 L.

    >>> domain_semi_axes(10.0)
    (35.0, 15.0)
    """
    return 0.5 * DOMAIN_LENGTH_FACTOR * length, 0.5 * DOMAIN_WIDTH_FACTOR * length


def domain_ellipse(dx, dy, ux, uy, length) -> np.ndarray:
    """The domain's quadratic form ``(a / 3.5 L)² + (c / 1.5 L)²`` (≤ 1 inside) of offsets
    ``(dx, dy)`` (target minus own ship, map metres) in the domain of a ship of ``length``
    heading along the unit vector ``(ux, uy)`` (east, north): ``a`` the offset along it, ``c``
    across; ``dx`` and ``dy`` of one shape, ``ux`` and ``uy`` of one shape, broadcasting.

    >>> domain_ellipse([0.0, 15.0, 0.0, 10.0], [35.0, 0.0, -70.0, 0.0], 0.0, 1.0, 10.0).tolist()
    [1.0, 1.0, 4.0, 0.4444444444444444]
    """
    a, b = domain_semi_axes(np.asarray(length, float))
    along = np.asarray(np.multiply(dx, ux), float)  # in place from here (rollouts: 20 x 500)
    along += np.multiply(dy, uy)
    along /= a
    across = np.asarray(np.multiply(dx, uy), float)
    across -= np.multiply(dy, ux)
    across /= b
    np.square(along, out=along)
    along += np.square(across, out=across)
    return along


def in_domain(own_xy, own_heading, target_xy, length) -> np.ndarray:
    """Whether each target is inside the (closed) 7 L × 3 L domain of the own ship at
    ``own_xy`` on compass ``own_heading`` (degrees); positions carry a trailing axis of 2.

    >>> in_domain((0, 0), 90.0, [(35, 0), (0, 15), (0, 15.01), (0, 35)], 10.0).tolist()
    [True, True, False, False]
    """
    d = np.asarray(target_xy, float) - np.asarray(own_xy, float)
    h = np.radians(np.asarray(own_heading, float))
    return domain_ellipse(d[..., 0], d[..., 1], np.sin(h), np.cos(h), length) <= 1.0
