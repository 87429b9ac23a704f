"""The papers' measures of a route and a run: one implementation each, used by every stage.

A route is a polyline of ``m`` points; every function takes an array of shape ``(..., m, 2)``
(one route, or a whole population at once), or the routes' segments from :func:`segments`
(complex, ``(..., m - 1)``: computed once when several metrics are wanted, as in the path
cost), and returns one value per route (shape ``(...)``).

Turn angle
    At an interior vertex, the deflection ``θ`` between the incoming and the outgoing segment
    (0 = straight on, 90° = right-angle turn, 180° = reversal). Zero-length segments (repeated
    points) have no heading: they are skipped, and the turn is measured between the last segment
    before them and the first segment after them.
Turn (steering cost, IWSO section 5.2)
    A vertex whose turn angle exceeds ``TURN_TOLERANCE_DEG`` (1°). Collinear vertices, repeated
    points and heading wobbles below the tolerance are not turns.

>>> square = [(0, 0), (1, 0), (1, 1)]
>>> float(path_length(square)), int(turns(square)), float(turn_cost(square))
(2.0, 1, 0.4)
>>> round(float(mot(square)), 4)
1.5708
"""

from __future__ import annotations

import numpy as np

TURN_TOLERANCE_DEG = 1.0
RIGHT_ANGLE_COST = 0.4  # ISSA: a right-angle turn costs 0.4, an obtuse one (45° deflection) 0.2


def path_length(points) -> np.ndarray:
    """Route length, IWSO eq. 28 with ``C_safe = 1``: the sum of the segment lengths.

    >>> float(path_length([(0, 0), (3, 4), (3, 10)]))
    11.0
    """
    return np.abs(segments(points)).sum(axis=-1)


def turn_angles(points) -> np.ndarray:
    """Turn angle (radians, in [0, π]) at each interior vertex, shape ``(..., m - 2)``.

    A vertex that ends a zero-length segment, or starts one, gets 0; the turn around repeated
    points is given to the vertex where the next non-degenerate segment starts.

    >>> np.degrees(turn_angles([(0, 0), (1, 0), (1, 0), (2, 1), (3, 2)])).round(6).tolist()
    [0.0, 45.0, 0.0]
    """
    seg = segments(points)
    if seg.shape[-1] < 2:
        return np.zeros(seg.shape[:-1] + (0,))
    real = seg != 0
    if real.all():
        turn = seg[..., 1:] * seg[..., :-1].conj()
        return np.abs(np.arctan2(turn.imag, turn.real))
    # u = the last non-degenerate segment before each segment (index -1 if none)
    n = real.shape[-1]
    prev = np.maximum.accumulate(np.where(real, np.arange(n), -1), axis=-1)[..., :-1]
    rows = np.arange(0, real.size, n).reshape(real.shape[:-1] + (1,))
    u = seg.ravel()[np.maximum(prev, 0) + rows]
    angle = np.abs(np.angle(seg[..., 1:] * u.conj()))
    return np.where(real[..., 1:] & (prev >= 0), angle, 0.0)


def segments(points) -> np.ndarray:
    """The segments of routes ``(..., m, 2)`` as complex numbers ``dx + i dy``, ``(..., m - 1)``
    (segments given again are returned as they are).

    >>> segments([(0, 0), (3, 4), (3, 10)]).tolist()
    [(3+4j), 6j]
    """
    if np.iscomplexobj(points):
        return points
    p = np.asarray(points, float)
    return (p[..., 1:, :] - p[..., :-1, :]).view(np.complex128)[..., 0]


def turns(points, tol_deg: float = TURN_TOLERANCE_DEG) -> np.ndarray:
    """Steering cost (IWSO Table 2): the number of vertices turning by more than ``tol_deg``.

    >>> int(turns([(0, 0), (1, 0), (2, 0), (2, 1), (2.5, 2)]))
    2
    """
    return (turn_angles(points) > np.radians(tol_deg)).sum(axis=-1)


def turn_cost(points) -> np.ndarray:
    """ISSA turning energy: 0.4 per right-angle turn and 0.2 per obtuse one (ISSA section 3.2).

    Generalised to any angle by interpolating linearly in the turn angle ``θ``: a turn costs
    ``0.4 · θ / 90°``, so 45° (an obtuse interior angle of 135°) costs 0.2, 90° costs 0.4 and a
    reversal 0.8. It is continuous, so no tolerance applies. The unit is the ISSA grid's cell
    side; the path problem scales it by the cell size.

    >>> float(turn_cost([(0, 0), (1, 0), (2, 1), (2, 2)]))
    0.4
    """
    return RIGHT_ANGLE_COST * turn_angles(points).sum(axis=-1) / (np.pi / 2)


def mot(points, tol_deg: float = TURN_TOLERANCE_DEG) -> np.ndarray:
    """Smoothness cost ``mot`` of IWSO eq. 27 (smaller is smoother).

    ``mot = ε · Σ_k (π θ_k / 180) / (1 + θ_{k+1})^{3/2}`` read as follows: ``θ_1 … θ_ε`` are the
    turn angles in degrees of the route's turns in order (vertices that are not turns, see
    :func:`turns`, are dropped, so collinear points change nothing), ``ε`` is their number, and
    ``θ_{ε+1} = 0``: after the last turn the route runs straight to the goal, so the last turn's
    term is its angle in radians. The numerator is thus the turn in radians (the π/180 factor),
    damped by the next turn in degrees. A straight route has ``mot = 0``.

    >>> round(float(mot([(0, 0), (1, 0), (1, 1), (2, 1)])), 4)  # 2 · (π/2 / 91^1.5 + π/2)
    3.1452
    """
    theta = np.degrees(turn_angles(points))
    is_turn = theta > tol_deg
    theta = np.where(is_turn, theta, 0.0)
    n = theta.shape[-1]
    # index of the next turn strictly after each vertex (n = none, whose angle reads as 0)
    idx = np.where(is_turn, np.arange(n), n)
    nxt = np.minimum.accumulate(idx[..., ::-1], axis=-1)[..., ::-1]
    after = np.concatenate([nxt[..., 1:], np.full(nxt.shape[:-1] + (1,), n)], axis=-1)
    padded = np.concatenate([theta, np.zeros(theta.shape[:-1] + (1,))], axis=-1)
    following = np.take_along_axis(padded, after, axis=-1)
    terms = np.radians(theta) / (1.0 + following) ** 1.5
    return is_turn.sum(axis=-1) * terms.sum(axis=-1)


# --- the figures of a table row (``usvtool metrics``) ---------------------------------------

#: Seconds between the samples of a simulated track on which turns and mot are counted.
TURN_WINDOW = 10.0


def track_samples(points, dt: float, window: float = TURN_WINDOW) -> np.ndarray:
    """The track ``(n, 2)`` of a run, one position every ``dt`` seconds, sampled every
    ``window`` seconds for :func:`turns` and :func:`mot`: every ``max(1, round(window / dt))``-th
    position from the first, and the last one when it is not among them.

    Per 0.1 s step a smooth turn would be a chain of sub-degree deflections (counted once per
    step, or never): a turn is a course change between two ``window``-long legs.

    >>> track_samples([(0, 0), (1, 0), (2, 0), (3, 1), (4, 2)], dt=1.0, window=2.0).tolist()
    [[0.0, 0.0], [2.0, 0.0], [4.0, 2.0]]
    >>> track_samples([(0, 0), (1, 0), (2, 0), (3, 1)], dt=1.0, window=2.0).tolist()
    [[0.0, 0.0], [2.0, 0.0], [3.0, 1.0]]
    """
    track = np.asarray(points, float)
    sampled = track[:: max(1, int(round(window / dt)))]
    if not np.array_equal(sampled[-1], track[-1]):
        sampled = np.vstack([sampled, track[-1]])
    return sampled


def length_ratio(length, optimum):
    """A route's length over the optimum of its chart (the exact any-angle route's length):
    1 for an optimal route, 1.05 for one 5 % longer; None when either is unknown or the
    optimum is not > 0.

    >>> length_ratio(105.0, 100.0)
    1.05
    """
    if length is None or optimum is None or not optimum > 0:
        return None
    return float(length) / float(optimum)


def optimisation_rate(value, reference):
    """The UDWA paper's optimisation rate (section 4.1, Table 1): the relative gain of a
    figure over the same figure of a reference, ``(value - reference) / reference`` (a
    fraction: 0.4325 is the paper's 43.25 %); None when either is unknown or the reference is 0.

    Table 1, head-on: UDWA's average distance 78.50 m against CCDWA's 54.80 m.

    >>> round(optimisation_rate(78.50, 54.80) * 100, 2)
    43.25
    """
    if value is None or reference is None or reference == 0:
        return None
    return (float(value) - float(reference)) / float(reference)


def target_distances(own_x, own_y, target_x, target_y) -> np.ndarray:
    """Centre distances ``(n, k)`` from the own ship (``(n,)`` x, y) to each of ``k`` targets
    (``(n, k)``, or ``(n,)`` for one target), in the unit of the coordinates."""
    ox, oy = np.asarray(own_x, float), np.asarray(own_y, float)
    n = ox.shape[0]
    tx = np.asarray(target_x, float).reshape(n, -1)
    ty = np.asarray(target_y, float).reshape(n, -1)
    return np.hypot(tx - ox[:, None], ty - oy[:, None])


def closest_distance(own_x, own_y, target_x, target_y):
    """Closest distance (UDWA Table 1): the smallest centre distance between the own ship and
    any target over all the steps given; None without a target or a step.

    >>> closest_distance([0, 0], [0, 10], [[30, 5], [20, 8]], [[0, 0], [10, 10]])  # 5, then 8
    5.0
    """
    d = target_distances(own_x, own_y, target_x, target_y)
    return float(d.min()) if d.size else None


def average_distance(own_x, own_y, target_x, target_y, steps=None):
    """Average distance (UDWA Table 1): the mean over the selected steps of the centre distance
    to the nearest target; ``steps`` a boolean mask ``(n,)`` (None: every step). For a run the
    steps are those of the collision-avoidance phase, the steps during which some encounter is
    latched (:func:`encounter_steps`). None without a target or a selected step.

    >>> tx, ty = [[30, 5], [20, 8], [0, 0]], [[0, 0], [10, 10], [0, 0]]
    >>> average_distance([0, 0, 0], [0, 10, 20], tx, ty)  # nearest: 5, 8, 20
    11.0
    >>> average_distance([0, 0, 0], [0, 10, 20], [30, 20, 0], [0, 10, 0], [False, True, True])
    20.0
    """
    d = target_distances(own_x, own_y, target_x, target_y)
    if not d.size:
        return None
    nearest = d.min(axis=1)
    if steps is not None:
        nearest = nearest[np.asarray(steps, bool)]
    return float(nearest.mean()) if nearest.size else None


def run_distances(own_x, own_y, target_x, target_y, steps) -> dict:
    """A run's two distance figures under their one name (the simulate summary's, the metrics
    table's and the report's): ``closest_distance_m`` (:func:`closest_distance`) and
    ``average_distance_m`` (:func:`average_distance` over the boolean ``steps``, the
    encounters' steps: the run's latched steps, or :func:`encounter_steps` of its events).

    >>> run_distances([0, 0, 0], [0, 10, 20], [30, 20, 0], [0, 10, 5], [False, True, True])
    {'closest_distance_m': 15.0, 'average_distance_m': 17.5}
    """
    return {
        "closest_distance_m": closest_distance(own_x, own_y, target_x, target_y),
        "average_distance_m": average_distance(own_x, own_y, target_x, target_y, steps),
    }


def encounter_steps(t, intervals) -> np.ndarray:
    """The steps ``(n,)`` (bool) inside some encounter: ``intervals`` are ``(onset_s,
    released_s)`` pairs, an encounter holding the steps with ``onset_s <= t < released_s``
    (``released_s`` None: latched until the last step). These are the events JSON's
    ``encounters`` (of a class other than ``none``), whose ``released_s`` is the first step no
    longer latched. Times are compared to half a millisecond (files hold them to 1 ms).

    >>> encounter_steps([0, 1, 2, 3, 4], [(1, 3), (4, None)]).tolist()
    [False, True, True, False, True]
    """
    t = np.asarray(t, float)
    inside = np.zeros(t.shape, bool)
    for onset, released in intervals:
        end = np.inf if released is None else released
        inside |= (t >= onset - 5e-4) & (t < end - 5e-4)
    return inside
