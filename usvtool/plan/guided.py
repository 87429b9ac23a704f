"""Route-guided search: the ``+g`` variant of every optimizer (never part of a faithful algorithm).

The search is given the exact any-angle route (:func:`usvtool.plan.exact.any_angle`), and with
it the route's homotopy class (which side of each obstacle it passes), and optimises the
papers' cost around it.

Stations (:func:`stations`)
    The exact route is taut: it bends at every convex corner it wraps, and on a rasterised
    coast that is a run of corners a few degrees apart (the issue's river: 141 vertices). Two
    neighbouring vertices turning the same way are merged into one, at the point where the
    incoming leg of the first and the outgoing leg of the second meet (outside the corners, in
    the water the route already bends round), when the two new segments touch no blocked cell
    and the route's turns and mot (IWSO eq. 27) do not rise above the exact route's (a merge
    makes one sharper turn of two, and mot weighs the last turn by the number of turns); the
    cheapest merge (the least added length) first, while the added length stays within
    ``BUDGET`` of the exact route's length (``waypoints="auto"``), or until ``K`` vertices are
    left (``waypoints=K``; fewer merges if no allowed one is left). The stations are the
    interior vertices left: ``K`` is chosen from the chart's route, one waypoint per bend that
    matters. The station route is collision-free (every merge is checked exactly) and passes
    each obstacle on the exact route's side.
Encoding (:class:`GuidedProblem`)
    ``x = (u_1, v_1, …, u_K, v_K)``: waypoint ``k`` is station ``s_k`` moved by ``u_k`` along
    and ``v_k`` across the route there (``t_k``, the unit bisector of the legs' directions, and
    its normal ``n_k``): ``w_k = s_k + u_k t_k + v_k n_k``, each offset within half the shorter
    leg at the station, so waypoints keep their order along the route. ``x = 0`` is the station
    route. Offsets, not positions, for the reason of the faithful encoding
    (:mod:`usvtool.plan.problem`): several optimizers pull positions towards ``x = 0``, here the
    station route.
Feasibility by the decoder (repair)
    Waypoint by waypoint (a loop over the K waypoints, each step vectorised over the
    population), waypoint ``k`` is pulled back towards its station, ``s_k + λ (w_k - s_k)``,
    for the largest ``λ`` of ``1, 1/2, …, 2^-LEVELS, 0`` whose segments from the previous
    (repaired) waypoint and on to the next station ``s_{k+1}`` touch no blocked cell (exact
    check). ``λ = 0`` always qualifies: the previous step made sure its waypoint sees ``s_k``,
    and ``s_k`` sees ``s_{k+1}`` on the station route. So every route the optimizer is scored
    on, and the one it returns, is collision-free: a decoder in the sense of the constrained
    evolutionary-computation literature (Michalewicz & Schoenauer 1996, "Evolutionary
    algorithms for constrained parameter optimization problems"), the optimizer's variables
    untouched (Baldwinian repair). The cost is the papers' cost
    (:class:`~usvtool.plan.problem.PathProblem`: length, IWSO eq. 28, plus the ISSA turning
    energy, section 3.2), against the exact squares: its collision terms are zero for every
    repaired route, so the search's 1e-3 cell tolerance has no role here.

Turns: a ``+g`` route has at most ``K`` turns, fewer than the exact route's whenever a merge was
made. The optimizers are the published ones, run unchanged on this problem.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from usvtool import metrics
from usvtool.collision import SegmentChecker
from usvtool.plan.problem import PathProblem, Search

SUFFIX = "+g"
AUTO = "auto"
BUDGET = 0.02  # added length of the merges, share of the exact route's length (auto K)
LEVELS = 6  # repair steps: λ = 1, 1/2, …, 2^-LEVELS, then 0


def stations(checker: SegmentChecker, route, waypoints: int | str = AUTO) -> np.ndarray:
    """The station route of an exact route (cell coordinates ``(m, 2)``; module docstring).

    >>> b = np.zeros((6, 6), bool); b[0:3, 0:3] = True  # a block in the south-west
    >>> exact = [(0.5, 5.5), (3, 3), (5.5, 0.5)]
    >>> stations(SegmentChecker(b), exact).tolist()  # one corner: nothing to merge
    [[0.5, 5.5], [3.0, 3.0], [5.5, 0.5]]
    >>> free = SegmentChecker(np.zeros((4, 4), bool))  # two 45° turns become one of 90°
    >>> stations(free, [(0, 0), (2, 0), (3, 1), (3, 3)], 1).tolist()
    [[0.0, 0.0], [3.0, 0.0], [3.0, 3.0]]
    """
    route = np.array(route, float)
    most_turns, most_mot = metrics.turns(route), metrics.mot(route)
    limit = BUDGET * float(np.abs(metrics.segments(route)).sum()) if waypoints == AUTO else np.inf
    target = 0 if waypoints == AUTO else int(waypoints)
    added = 0.0
    refused: set[tuple[float, ...]] = set()  # merges found colliding (by their vertices)
    while len(route) - 2 > target:
        cost, points, index = _merges(route)
        order = np.argsort(cost)
        done = False
        for i in order[np.isfinite(cost[order])].tolist():
            if added + cost[i] > limit:
                break
            tag = tuple(route[i : i + 4].ravel())
            if tag in refused:
                continue
            a, p, b = route[i], points[i], route[i + 3]
            if checker.collides(np.array([a, p]), np.array([p, b])).any():
                refused.add(tag)
                continue
            merged = np.vstack([route[: i + 1], p, route[i + 3 :]])
            if metrics.turns(merged) > most_turns or metrics.mot(merged) > most_mot:
                continue  # a sharper last turn can raise mot (IWSO eq. 27) above the route's
            route = merged
            added += float(cost[i])
            done = True
            break
        if not done:
            break
    return route


def _merges(route: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each ``i``, merging vertices ``i + 1`` and ``i + 2``: the added length (inf when
    they turn opposite ways or not at all) and the merged vertex."""
    a, v, w, b = route[:-3], route[1:-2], route[2:-1], route[3:]
    d_in, d_mid, d_out = v - a, w - v, b - w
    turn1 = _cross(d_in, d_mid)
    turn2 = _cross(d_mid, d_out)
    denom = _cross(d_in, d_out)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = _cross(d_mid, d_out) / denom  # P = v + t d_in
        s = _cross(d_mid, d_in) / denom  # P = w + s d_out
    ok = (turn1 * turn2 > 0) & (np.sign(denom) == np.sign(turn1)) & (t >= 0) & (s <= 0)
    t = np.where(ok, t, 0.0)
    points = v + t[:, None] * d_in
    added = np.hypot(*(points - v).T) + np.hypot(*(w - points).T) - np.hypot(*d_mid.T)
    cost = np.where(ok & np.isfinite(added), added, np.inf)
    return cost, np.where(ok[:, None], points, v), np.arange(len(cost))


def _cross(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    return p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]


@dataclass
class GuidedProblem:
    """The guided encoding around the ``station`` route (cell coordinates ``(K + 2, 2)``) of a
    :class:`PathProblem` (whose grid, ends and cost it uses); call it on a population."""

    base: PathProblem
    station: np.ndarray
    checker: SegmentChecker = field(init=False, repr=False)

    def __post_init__(self):
        s = np.asarray(self.station, float)
        self.station = s
        self.checker = self.base.checker
        legs = np.diff(s, axis=0)
        length = np.hypot(*legs.T)
        unit = legs / length[:, None]
        tangent = unit[:-1] + unit[1:]
        tangent /= np.maximum(np.hypot(*tangent.T), 1e-12)[:, None]
        self._frame = np.stack([tangent, tangent[:, ::-1] * [-1.0, 1.0]], axis=1)  # (K, 2, 2)
        half = 0.5 * np.minimum(length[:-1], length[1:])
        self.upper = np.repeat(half, 2) * self.base.grid.cell_size
        self.lower = -self.upper

    @property
    def dim(self) -> int:
        return self.lower.size

    @property
    def waypoints(self) -> int:
        return len(self.station) - 2

    @property
    def unit(self) -> float:
        return self.base.unit

    def decode(self, X) -> np.ndarray:
        """Repaired routes of the population ``X`` ``(n, dim)`` (metres) as cell coordinates
        ``(n, K + 2, 2)``: collision-free (module docstring, Feasibility by the decoder)."""
        X = np.atleast_2d(np.asarray(X, float))
        n = X.shape[0]
        offsets = np.einsum("nkj,kjd->nkd", X.reshape(n, -1, 2), self._frame)
        offsets /= self.base.grid.cell_size
        lam = np.concatenate([0.5 ** np.arange(LEVELS + 1), [0.0]])
        s = self.station
        routes = np.broadcast_to(s, (n, *s.shape)).copy()
        for k in range(1, len(s) - 1):  # waypoint by waypoint, each over the whole population
            moved = s[k] + offsets[:, k - 1]
            ok = self._free(routes[:, k - 1], moved) & self._free(
                moved, np.broadcast_to(s[k + 1], moved.shape)
            )
            routes[:, k] = moved
            bad = np.flatnonzero(~ok)
            if bad.size:  # the smaller steps, for the routes whose whole step collides
                trial = s[k] + lam[1:, None, None] * offsets[bad, k - 1]  # (levels, bad, 2)
                prev = np.broadcast_to(routes[bad, k - 1], trial.shape)
                ok = self._free(prev, trial) & self._free(
                    trial, np.broadcast_to(s[k + 1], trial.shape)
                )
                ok[-1] = True  # λ = 0: free, since the previous waypoint sees this station
                routes[bad, k] = trial[np.argmax(ok, axis=0), np.arange(bad.size)]
        return routes

    def _free(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Whether each segment ``a[...] → b[...]`` (arrays ``(..., 2)``) lies in the grid and
        touches no blocked cell (exact check)."""
        g = self.base.grid
        shape = a.shape[:-1]
        a, b = a.reshape(-1, 2), b.reshape(-1, 2)
        top = [g.width, g.height]
        free = ((a >= 0) & (a <= top) & (b >= 0) & (b <= top)).all(axis=1)
        idx = np.flatnonzero(free)
        free[idx] = ~self.checker.collides(a[idx], b[idx])
        return free.reshape(shape)

    def __call__(self, X) -> np.ndarray:
        return self.cost(self.decode(X))

    def cost(self, routes, exact: bool = True) -> np.ndarray:
        """The papers' cost of the routes (:meth:`PathProblem.cost`, against the exact squares:
        the repaired routes are collision-free)."""
        return self.base.cost(routes, exact=True)

    def search(self) -> Search:
        """The dimensionless view (offsets and cost in units of the start-goal distance)."""
        scale = self.unit
        return Search(self, scale, self.unit, self.lower / scale, self.upper / scale)

    def to_map(self, route) -> np.ndarray:
        return self.base.to_map(route)
