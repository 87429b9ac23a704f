"""The papers' path metrics: one implementation, used by every stage.

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
