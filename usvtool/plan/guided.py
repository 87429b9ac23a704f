"""Route-guided search: the ``+g`` variant of every optimizer (never part of a faithful algorithm).

The search is given the exact any-angle route (:func:`usvtool.plan.exact.any_angle`), and with
it the route's homotopy class (which side of each obstacle it passes), and optimises the
papers' cost around a station route drawn from it.

Stations (:func:`stations`)
    The exact route is taut: it bends at every convex corner it wraps, and on a rasterised
    coast that is a run of corners a few degrees apart (the issue's river: 141 vertices).

    *Merges.* Two neighbouring vertices turning the same way are merged into one, at the point
    where the incoming leg of the first and the outgoing leg of the second meet (outside the
    corners, in the water the route already bends round), when the two new segments touch no
    blocked cell and the route's turns and mot (IWSO eq. 27) do not rise above the exact
    route's (a merge makes one sharper turn of two, and mot weighs the last turn by the number
    of turns); the cheapest merge (the least added length) first, while the added length stays
    within ``BUDGET`` of the exact route's length (``waypoints="auto"``), or until ``K``
    vertices are left (``waypoints=K``, the route then used; fewer merges if no allowed one is
    left).

    *Fewest turns* (``waypoints="auto"``). Merges keep the exact route's legs, and so cannot
    undo turns that are not a same-way run (islands passed on alternate sides), nor trade a
    sharper early turn for a gentler last one, which is what lowers mot. So a minimum-link
    search (:func:`_links`) also runs over the visibility graph of the exact route's vertices
    and a lattice of points in a corridor about it (step ``SPACING``, half-width ``CORRIDOR``
    of the route's length): for each number of links, the shortest collision-free route and
    the smoothest (lowest mot) of those whose last two links are free to choose, each at most
    ``LONGEST`` longer than the exact route. The station route is, of the merged route and
    those, the one with the fewest turns whose turns and mot are both below the exact route's
    (the lowest mot among those), else the merged route. Every segment is checked exactly, so
    the station route is collision-free; it keeps to the corridor but, unlike the merged
    route, may pass a small obstacle in it on the other side.

    The stations are the interior vertices of the station route: ``K`` is chosen from the
    chart's route, one waypoint per bend that matters.
Encoding (:class:`GuidedProblem`)
    ``x = (u_1, v_1, …, u_K, v_K)``: waypoint ``k`` is station ``s_k`` moved by ``u_k`` along
    and ``v_k`` across the route there (``t_k``, the unit bisector of the legs' directions, and
    its normal ``n_k``): ``w_k = s_k + u_k t_k + v_k n_k``, each offset within half the shorter
    leg at the station, so waypoints keep their order along the route. ``x = 0`` is the station
    route. Offsets, not positions, for the reason of the faithful encoding
    (:mod:`usvtool.plan.problem`): several optimizers pull positions towards ``x = 0``, here the
    station route.
Feasibility by the decoder (repair)
    Waypoint by waypoint, waypoint ``k`` is kept where its segments from the previous
    (repaired) waypoint and on to the next station ``s_{k+1}`` touch no blocked cell (exact
    check), else it is put back on its station ``s_k``, which is always free: the previous
    waypoint sees ``s_k`` (it was kept only if it did), and ``s_k`` sees ``s_{k+1}`` on the
    station route. The checks a population needs are made in one compiled call
    (:meth:`GuidedProblem.decode`, :func:`usvtool.plan.cost_kernels.decode_guided`), waypoint
    by waypoint as the choices need them (the NumPy decoder it replaced, kept as
    ``GuidedProblem._decode_python``, made them all in two vectorised calls and then chose by
    boolean operations: the same routes, bit for bit). So every route
    the optimizer is scored on, and the one it returns, is collision-free: a decoder in the
    sense of the constrained evolutionary-computation literature (Michalewicz & Schoenauer
    1996, "Evolutionary algorithms for constrained parameter optimization problems"), the
    optimizer's variables untouched (Baldwinian repair). The cost is the papers' cost
    (:class:`~usvtool.plan.problem.PathProblem`: length, IWSO eq. 28, plus the ISSA turning
    energy, section 3.2), whose collision terms are zero for every repaired route
    (:meth:`GuidedProblem.cost`).

    Margin. The search pulls routes onto the corners they wrap, and a segment the exact check
    passes 1e-12 cell from a corner can collide once the route is written in lon/lat and read
    back (22 of 1100 ``+g`` runs on the NOAA grids did, before this). So the stations at convex
    corners are moved ``OFF_CORNER`` = 2 ``PAD`` off them (:func:`clear_of_corners`) and, when
    the station route then clears the squares grown by the search's ``PAD`` = 1e-3 cell, the
    decoder judges every segment against those grown squares (``margin``), as the faithful
    search's penalty does; else it keeps the exact check. The planner also returns the station
    route if the search's best is not free once in map metres.

    An earlier decoder pulled a refused waypoint back by ``λ = 1/2, 1/4, …, 1/64`` before
    giving up. Over whole runs (PSO, 50 x 300, on the generated walls and islands-sparse maps)
    0.3-0.5 % of the waypoints ended on one of those steps, 95-99 % on their station; and its
    checks, in sequence (up to four calls per waypoint and population), took 9-11 s an IWSO
    run on walls, against 0.3 s for faithful IWSO. Keep-or-station needs no sequence of checks.

Result (:func:`settle`): the optimizer's best route, or the station route where that has fewer
turns and a lower mot than the exact route and the best has not (the papers' cost weighs
neither). A ``+g`` route has at most ``K`` turns. The optimizers are the published ones, run
unchanged on this problem."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from usvtool import measures
from usvtool.collision import SegmentChecker
from usvtool.plan.problem import PAD, PathProblem, Search

SUFFIX = "+g"
AUTO = "auto"
BUDGET = 0.02  # added length of the merges, share of the exact route's length (auto K)
LONGEST = 0.03  # the fewest-turn search's station routes: at most this much over the exact one
SPACING = 1 / 50  # its lattice step, share of the exact route's length
CORRIDOR = 1 / 10  # the half-width of its corridor about the exact route, share of the length
PAIRS = 2048  # last pairs of links whose routes' mot the search compares, at most
OFF_CORNER = 2 * PAD  # a station at a convex corner is moved this far off it, diagonally


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
    merged = _merged(checker, route, waypoints)
    return _fewest_turns(checker, route, merged) if waypoints == AUTO else merged


def settle(exact: np.ndarray, station: np.ndarray, best: np.ndarray) -> tuple[np.ndarray, bool]:
    """The ``+g`` route: ``(route, whether it is the station route)``. The optimizer's ``best``
    route, unless the station route has fewer turns and a lower mot than the ``exact`` route
    and ``best`` has not: the papers' cost weighs neither (its turning energy sums the turn
    angles), so a search that shortens the station route can add a turn at one of its straight
    vertices or sharpen its last turn. Both routes are collision-free.

    >>> exact = np.array([[0, 0], [2, 1], [4, 0], [6, 1], [8, 0]], float)  # 3 turns
    >>> station = exact[[0, 2, 4]]  # straight: 0 turns
    >>> settle(exact, station, exact)[1], settle(exact, station, exact[[0, 1, 2, 4]])[1]
    (True, False)
    """
    turns, mot = measures.turns(exact), measures.mot(exact)

    def bar(route) -> bool:
        return measures.turns(route) < turns and measures.mot(route) < mot

    if bar(station) and not bar(best):
        return station, not np.array_equal(station, best)
    return best, False


def _merged(checker: SegmentChecker, route: np.ndarray, waypoints: int | str) -> np.ndarray:
    """The exact route with its same-way corner runs merged (module docstring, Stations)."""
    most_turns, most_mot = measures.turns(route), measures.mot(route)
    limit = BUDGET * float(np.abs(measures.segments(route)).sum()) if waypoints == AUTO else np.inf
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
            if measures.turns(merged) > most_turns or measures.mot(merged) > most_mot:
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


def _fewest_turns(checker: SegmentChecker, exact: np.ndarray, merged: np.ndarray) -> np.ndarray:
    """The station route of ``waypoints="auto"`` (module docstring, Stations): of ``merged``
    and the routes of the fewest-link search (:func:`_links`), the one with the fewest turns
    whose turns and mot are both below the exact route's (the lowest mot among those); else
    ``merged``."""
    turns, mot = measures.turns(exact), measures.mot(exact)
    routes = [merged, *_links(checker, exact)]
    scores = [(measures.turns(r), measures.mot(r)) for r in routes]
    good = [(t, m, i) for i, (t, m) in enumerate(scores) if t < turns and m < mot]
    return routes[min(good)[2]] if good else merged


def _links(checker: SegmentChecker, exact: np.ndarray) -> list[np.ndarray]:
    """Collision-free routes from start to goal of 1 … ``len(exact) - 1`` links through the exact
    route's vertices and a lattice about it (:func:`_lattice`), at most :data:`LONGEST` longer
    than the exact route: for each number of links the shortest, and the one of lowest mot
    among those whose last two links are any pair of visible points (the earlier ones shortest;
    of more than :data:`PAIRS` pairs, those turning least between their two links).

    The search is Bellman-Ford over the visibility graph of those points, one relaxation per
    link (a minimum-link shortest path, as in Mitchell, Rote and Woeginger 1992, "Minimum-link
    paths among obstacles in the plane", on a discrete point set); a pair of points is checked
    (exactly) only when a route through it can be short enough (the ellipse bound)."""
    limit = (1.0 + LONGEST) * float(measures.path_length(exact))
    points = np.vstack([exact[:1], exact[-1:], exact[1:-1], _lattice(checker, exact)])
    n = len(points)
    start = np.hypot(*(points - exact[0]).T)
    goal = np.hypot(*(points - exact[-1]).T)
    dist = np.hypot(*(points[:, None] - points[None]).transpose(2, 0, 1))
    short = start[:, None] + dist + goal[None, :] <= limit  # u → v on a route short enough
    short &= dist > 0  # no link from a point to itself (or to a lattice point on a vertex)
    u, v = np.nonzero(np.triu(short | short.T))
    weight = np.full((n, n), np.inf)
    free = ~checker.collides(points[u], points[v])
    weight[u[free], v[free]] = weight[v[free], u[free]] = dist[u[free], v[free]]
    weight[~short] = np.inf
    best = np.full(n, np.inf)
    best[0] = 0.0
    history, parents, routes = [best], [], []
    for links in range(1, len(exact)):
        total = best[:, None] + weight
        parent = np.argmin(total, axis=0)
        best = total[parent, np.arange(n)]
        history.append(best)
        parents.append(parent)
        if best[1] <= limit:
            routes.append(points[_trace(parents, np.array([1]))[0]])
        if links >= 2:  # the last two links free: ... u → w → goal
            ends = history[-3][:, None] + weight + weight[:, 1][None, :] <= limit
            pu, pw = np.nonzero(ends)
            if pu.size > PAIRS:  # the pairs turning least at w, the last turn (mot's weight)
                into, out = points[pw] - points[pu], points[1] - points[pw]
                turn = np.arctan2(np.abs(_cross(into, out)), (into * out).sum(axis=1))
                keep = np.argpartition(turn, PAIRS)[:PAIRS]
                pu, pw = pu[keep], pw[keep]
            if pu.size:
                chains = _trace(parents[:-2], pu) if links > 2 else pu[:, None]
                candidates = points[np.column_stack([chains, pw, np.ones_like(pw)])]
                routes.append(candidates[np.argmin(measures.mot(candidates))])
    return routes


def _trace(parents: list[np.ndarray], last: np.ndarray) -> np.ndarray:
    """The vertex indices ``(k, len(parents) + 1)`` of the Bellman-Ford routes ending at
    ``last`` (``k`` indices), from the start."""
    chain = [last]
    for parent in reversed(parents):
        chain.append(parent[chain[-1]])
    return np.column_stack(chain[::-1])


def _lattice(checker: SegmentChecker, exact: np.ndarray) -> np.ndarray:
    """Cell centres every ``SPACING`` of the exact route's length (at least one cell) in its
    bounding box grown by the corridor, touching no blocked cell, within ``CORRIDOR`` of its
    length from it."""
    length = float(measures.path_length(exact))
    step = max(1, int(round(SPACING * length)))
    reach = CORRIDOR * length
    low = np.maximum(np.floor(exact.min(axis=0) - reach), 0).astype(int)
    high = np.minimum(np.ceil(exact.max(axis=0) + reach), [checker.width, checker.height])
    cols = np.arange(low[0] + step // 2, high[0], step)
    rows = np.arange(low[1] + step // 2, high[1], step)
    c, r = (a.ravel() for a in np.meshgrid(cols, rows.astype(int)))
    points = np.column_stack([c, r]) + 0.5
    points = points[~checker.collides(points, points)]  # off the blocked cells
    a, d = exact[:-1], np.diff(exact, axis=0)
    t = np.clip(((points[:, None] - a) * d).sum(axis=2) / (d**2).sum(axis=1), 0.0, 1.0)
    near = np.hypot(*(points[:, None] - a - t[..., None] * d).transpose(2, 0, 1)).min(axis=1)
    return points[near <= reach]


def _cross(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    return p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]


def clear_of_corners(checker: SegmentChecker, station: np.ndarray) -> np.ndarray | None:
    """The station route with every interior vertex that sits at a grid point (a convex corner
    of the exact route, 1e-5 cell off it) moved to :data:`OFF_CORNER` off that point along the
    same diagonal, if the route then clears the blocked squares grown by the search's ``PAD``
    (``checker.pad``); else None. With it the decoder can demand that clearance of every
    segment (module docstring, Feasibility by the decoder).

    >>> b = np.zeros((4, 4), bool); b[0:2, 0:2] = True  # a block in the north-west
    >>> route = np.array([[0.5, 3.5], [2 + 1e-5, 2 + 1e-5], [3.5, 0.5]])
    >>> clear_of_corners(SegmentChecker(b, pad=PAD), route)[1].tolist()
    [2.002, 2.002]
    """
    moved = np.array(station, float)
    inner = moved[1:-1]
    corner = np.round(inner)
    at = np.abs(inner - corner).max(axis=1) < 1e-4
    inner[at] = corner[at] + OFF_CORNER * np.sign(inner[at] - corner[at])
    touches = checker.guide(moved[:-1], moved[1:], exact=False)[0]
    return None if touches.any() else moved


@dataclass
class GuidedProblem:
    """The guided encoding around the ``station`` route (cell coordinates ``(K + 2, 2)``) of a
    :class:`PathProblem` (whose grid, ends and cost it uses); call it on a population."""

    base: PathProblem
    station: np.ndarray
    margin: bool = False  # judge segments against the squares grown by PAD (clear_of_corners)
    checker: SegmentChecker = field(init=False, repr=False)

    def __post_init__(self):
        s = np.asarray(self.station, float)
        self.station = s
        self.checker = self.base.checker
        self._blocked = np.ascontiguousarray(self.base.grid.blocked)
        self._station = np.ascontiguousarray(s)
        from usvtool.plan import cost_kernels

        cost_kernels.warm("guided")  # compiled or loaded now, not in a timed call
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
        ``(n, K + 2, 2)``: collision-free (module docstring, Feasibility by the decoder).

        One compiled call (:func:`usvtool.plan.cost_kernels.decode_guided`), making the checks
        waypoint by waypoint as the choices need them; :meth:`_decode_python` the same routes
        in NumPy."""
        X = np.atleast_2d(np.ascontiguousarray(X, dtype=float))
        if X.ndim != 2 or X.shape[1] != self.dim:
            raise ValueError(f"a population of shape (n, {self.dim}), not {X.shape}")
        from usvtool.plan import cost_kernels

        return cost_kernels.decode_guided(
            X, self._station, self._frame, float(self.base.grid.cell_size), self._blocked,
            *self.checker.kernel_args(self.checker.pad if self.margin else 0.0),
        )  # fmt: skip

    def _decode_python(self, X) -> np.ndarray:
        """:meth:`decode` in NumPy (the reference of tests/plan/test_cost_kernels.py).

        Two exact checks over the whole population: first whether each moved waypoint ``w_j``
        sees the next station ``s_{j+1}`` (without that it is never kept), then, only where it
        does, the segments to ``w_j`` from ``s_{j-1}`` and from ``w_{j-1}``; the choices are
        then made waypoint by waypoint as boolean operations over the population."""
        X = np.atleast_2d(np.asarray(X, float))
        n = X.shape[0]
        s = self.station
        k = len(s) - 2
        moved = (
            s[1:-1]
            + np.einsum("nkj,kjd->nkd", X.reshape(n, k, 2), self._frame) / self.base.grid.cell_size
        )
        fixed = np.broadcast_to(s, (n, *s.shape))
        first = self._free(
            np.concatenate([moved, fixed[:, :1]], axis=1),
            np.concatenate([fixed[:, 2:], moved[:, :1]], axis=1),
        )
        on = first[:, :k]  # w_j → s_{j+1}
        after_station = np.zeros((n, k), bool)  # s_{j-1} → w_j, where w_j → s_{j+1} is free
        after_station[:, 0] = first[:, k]
        after_moved = np.zeros((n, k - 1), bool)  # w_{j-1} → w_j, where both see on
        from_station, from_moved = on[:, 1:], on[:, 1:] & on[:, :-1]
        a = np.concatenate([fixed[:, 1:-2][from_station], moved[:, :-1][from_moved]])
        b = np.concatenate([moved[:, 1:][from_station], moved[:, 1:][from_moved]])
        if len(a):
            free = self._free(a, b)
            after_station[:, 1:][from_station] = free[: from_station.sum()]
            after_moved[from_moved] = free[from_station.sum() :]
        keep = np.empty((n, k), bool)
        keep[:, 0] = after_station[:, 0] & on[:, 0]
        for j in range(1, k):  # the previous waypoint is w_j-1 where kept, else s_j-1
            seen = np.where(keep[:, j - 1], after_moved[:, j - 1], after_station[:, j])
            keep[:, j] = seen & on[:, j]
        routes = fixed.copy()
        routes[:, 1:-1] = np.where(keep[..., None], moved, s[1:-1])
        return routes

    def _free(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Whether each segment ``a[...] → b[...]`` (arrays ``(..., 2)``) lies in the grid and
        touches no blocked cell (exact check; with ``margin``, no square grown by ``PAD``)."""
        g = self.base.grid
        shape = a.shape[:-1]
        a, b = a.reshape(-1, 2), b.reshape(-1, 2)
        top = [g.width, g.height]
        free = ((a >= 0) & (a <= top) & (b >= 0) & (b <= top)).all(axis=1)
        idx = np.flatnonzero(free)
        for end in (a, b):  # an end in a blocked cell (the one holding it) collides: no check
            col, row = (np.minimum(end[idx].astype(np.intp), [g.width - 1, g.height - 1])).T
            idx = idx[~self._blocked[row, col]]
        free[:] = False
        if self.margin:
            free[idx] = ~self.checker.guide(a[idx], b[idx], exact=False)[0]
        else:
            free[idx] = ~self.checker.collides(a[idx], b[idx])
        return free.reshape(shape)

    def __call__(self, X) -> np.ndarray:
        return self.cost(self.decode(X))

    def cost(self, routes, exact: bool = True) -> np.ndarray:
        """The papers' cost of repaired (collision-free) routes: :meth:`PathProblem.cost`'s
        ``ℓ (L + w T)``, its collision terms being zero for them (the same floats as
        ``PathProblem.cost(routes, exact=True)``, without the collision check; ``exact`` is
        the planner's interface: repaired routes are always scored so). Compiled
        (:mod:`usvtool.plan.cost_kernels`); :meth:`_cost_python` the same floats in NumPy."""
        return self.base._kernel_cost(routes, False, 0.0)

    def _cost_python(self, routes, exact: bool = True) -> np.ndarray:
        """:meth:`cost` in NumPy (the reference of tests/plan/test_cost_kernels.py)."""
        seg = measures.segments(np.asarray(routes, float))
        return self.base.grid.cell_size * self.base.free_cost(seg)

    def search(self) -> Search:
        """The dimensionless view (offsets and cost in units of the start-goal distance)."""
        scale = self.unit
        return Search(self, scale, self.unit, self.lower / scale, self.upper / scale)

    def to_map(self, route) -> np.ndarray:
        return self.base.to_map(route)
