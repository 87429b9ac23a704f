"""Do routes with fewer turns than the exact route exist within 5 % of the optimum? (issue 14)

The ``+g`` variants are asked for fewer turns than the exact (any-angle) route, within 5 % of
its length. On some maps no such route may exist. This script looks for one far more densely
than ``+g``'s own station search (``usvtool.plan.guided._links``, a lattice of cell centres
about the route): every point of a lattice ``--spacing`` cells apart inside the ellipse of
routes at most ``--bound`` longer than the optimum (``|p - start| + |p - goal| <= (1 + bound)
L``) that lies on no blocked cell, with the start and the goal. Over that point set it finds,
for each number of links up to the exact route's, the shortest collision-free route of at most
that many links: Bellman-Ford, one round per link (Mitchell, Rote and Woeginger 1992 on a
discrete point set); a link is checked with the exact line of sight
(``usvtool.collision_kernels.touches``) only when a route through it can still be short
enough and improves its end. Compiled with numba: the rounds visit n² pairs.

A route of ``k`` links has at most ``k - 1`` turns. (The turn metric drops vertices that turn
by 1° or less, so a polyline of many sub-degree bends counts as straight; such routes are not
what "fewer turns" asks for, and this search does not look for them.) The lattice gives upper
bounds: the shortest route of fewer links that it finds is at most that long; a route of
fewer links shorter than it could only pass closer to the corners than the lattice reaches.

Prints, per map: the exact route's length (cells), links and turns, the lattice's size, and
for each number of links the shortest route found, as a ratio to the optimum, with its
vertices. Not a test: the figures of docs/planning.md, "Where fewer turns do not exist".

Usage: python benchmarks/bench_fewest_links.py [--maps grid20,walls:3:200] [--spacing 0.1]
       [--bound 0.1]
Maps: a bundled chart with a route in pipelines/report.yaml (grid20, env1, ...), or
``KIND:MAP_SEED[:SIZE]`` of charts/make_complex.py (the tests' small maps use SIZE 200 and a
1 m margin, as here for any SIZE below 500).
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

from usvtool import measures
from usvtool.collision import SegmentChecker
from usvtool.collision_kernels import touches
from usvtool.plan.planner import PlanOptions, plan_route

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))


@njit(cache=True)
def shortest_by_links(points, limit, max_links, prefix, stride):
    """``(lengths, parents)``: for 1 … ``max_links`` links, the shortest free route from point 0
    to point 1 of at most that many links (inf if none within ``limit``), and each round's
    parent of every point."""
    n = points.shape[0]
    to_goal = np.sqrt(((points - points[1]) ** 2).sum(axis=1))
    best = np.full(n, np.inf)
    best[0] = 0.0
    lengths = np.full(max_links + 1, np.inf)
    parents = np.full((max_links + 1, n), -1, np.int64)
    for links in range(1, max_links + 1):
        new = best.copy()  # at most this many links: fewer are allowed
        parent = np.arange(n)  # a point that keeps its route is its own parent this round
        for u in range(n):
            if best[u] == np.inf:
                continue
            ux, uy = points[u, 0], points[u, 1]
            for v in range(n):
                d = best[u] + np.sqrt((points[v, 0] - ux) ** 2 + (points[v, 1] - uy) ** 2)
                if d >= new[v] or d + to_goal[v] > limit or v == u:
                    continue
                if not touches(prefix, stride, ux, uy, points[v, 0], points[v, 1]):
                    new[v] = d
                    parent[v] = u
        best = new
        lengths[links] = best[1]
        parents[links] = parent
    return lengths, parents


def route_of(points, parents, links: int) -> np.ndarray:
    """The vertices of the round-``links`` route to the goal (repeated points dropped)."""
    chain, v = [1], 1
    for k in range(links, 0, -1):
        v = int(parents[k, v])
        if v != chain[-1]:
            chain.append(v)
    return points[chain[::-1]]


def load(name: str):
    """``(grid, start, goal)`` in map metres of a bundled chart or a generated map."""
    if ":" in name:
        spec = importlib.util.spec_from_file_location("mc", ROOT / "charts" / "make_complex.py")
        make_complex = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(make_complex)
        kind, seed, *size = name.split(":")
        size = float(size[0]) if size else 500.0
        options = {"margin": 1} if size < 500 else None
        doc, grid = make_complex.connected_map(kind, int(seed), size, options)
        return grid, tuple(doc["start"]), tuple(doc["goal"])
    from bench_charts import bundled_case

    return bundled_case(name) or sys.exit(f"bench_fewest_links: no grid for {name!r}")


def fewest_links(checker: SegmentChecker, route, spacing: float, bound: float):
    """``(lengths, routes, size)``: for 1 … ``len(route) - 1`` links, the shortest free route
    (cell coordinates) from the route's start to its end over the lattice (module docstring),
    and its length, or inf and None when none is within ``bound``; ``size`` the lattice's
    number of points."""
    route = np.asarray(route, float)
    length = float(measures.path_length(route))
    s, g = route[0], route[-1]
    xs = np.arange(spacing / 2, checker.width, spacing)
    ys = np.arange(spacing / 2, checker.height, spacing)
    lattice = np.column_stack([a.ravel() for a in np.meshgrid(xs, ys)])
    inside = np.hypot(*(lattice - s).T) + np.hypot(*(lattice - g).T) <= (1 + bound) * length
    lattice = lattice[inside]
    lattice = lattice[~checker.collides(lattice, lattice)]  # on no blocked cell
    points = np.ascontiguousarray(np.vstack([s, g, lattice]))
    found, parents = shortest_by_links(
        points, (1 + bound) * length, len(route) - 1, checker._prefix, checker.width + 2
    )
    routes = [route_of(points, parents, k) if np.isfinite(found[k]) else None
              for k in range(len(found))]  # fmt: skip
    return found, routes, len(lattice)


def analyse(name: str, spacing: float, bound: float) -> None:
    grid, start, goal = load(name)
    checker = SegmentChecker(grid.blocked)
    exact = plan_route(grid, start, goal, PlanOptions("anyangle")).route
    route = np.column_stack(grid.to_cell_coords(*np.asarray(exact.points, float).T))
    length = float(measures.path_length(route))
    t0 = time.perf_counter()
    found, routes, size = fewest_links(checker, route, spacing, bound)
    seconds = time.perf_counter() - t0
    print(f"\n{name}: exact route {length:.3f} cells, {len(route) - 1} links, "
          f"{int(exact.turns)} turns, mot {exact.mot:.3f}; {size} lattice points every "
          f"{spacing} cell within {bound:.0%} ({seconds:.1f} s)")  # fmt: skip
    for k in range(1, len(route)):
        r = routes[k]
        if r is None:
            print(f"  {k} links: none within {bound:.0%}")
            continue
        print(f"  {k} links: {found[k] / length:.4f} x the optimum, {int(measures.turns(r))} "
              f"turns, mot {float(measures.mot(r)):.3f}: "
              + " ".join(f"({x:.2f}, {y:.2f})" for x, y in r))  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--maps", default="grid20,walls:3:200")
    ap.add_argument("--spacing", type=float, default=0.1, help="lattice spacing (cells)")
    ap.add_argument("--bound", type=float, default=0.1, help="length bound over the optimum")
    args = ap.parse_args()
    for name in args.maps.split(","):
        analyse(name, args.spacing, args.bound)


if __name__ == "__main__":
    main()
