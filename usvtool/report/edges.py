"""Routes that hug the grid's edges (docs/report-figures.md, "Routes along the grid's edges").

An optimizer's waypoints are clipped to the grid's box, so a route can run along the frame of
the map: it turns little and runs long, and says nothing of the water. A route **hugs the
edges** when more than :data:`THRESHOLD` of its length lies within :data:`BAND` cell of the
grid's border (the outermost ring of cells: a point whose distance to the nearest side of the
grid's bounds is at most one cell size). The share is exact: the part of a segment off the
band is its clip to the grid's box shrunk by the band (a convex box: one interval).

:func:`band_share` of a polyline is pure; :func:`hugs` reads a route job's files (its
``route.geojson`` and its grid job's ``grid.tif``, as the planning section does);
:func:`edge_share` counts, for a routes claim, the routes of each method and case that hug.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from typing import NamedTuple

import numpy as np

from usvtool.grid import read_grid
from usvtool.report.data import JobResults, Results
from usvtool.route import read_path_geojson

#: The edge band's width, in cells: the outermost ring of the grid.
BAND = 1.0
#: A route hugs the edges when more than this share of its length is in the band: more of it
#: runs along the map's frame than through the map (the straight diagonal of a 20 x 20 grid has
#: 5 % in the band, grid20's any-angle optimum, from corner to corner, 20 %, a route along two
#: sides 100 %).
THRESHOLD = 0.5


def band_share(points, bounds: tuple[float, float, float, float], band: float) -> float:
    """The share of the polyline ``points`` ``(m, 2)``'s length within ``band`` (map units) of
    the border of ``bounds`` (left, bottom, right, top); 1.0 for a route of no length whose
    points are all in the band, else 0.0 for one of no length.

    >>> box = (0.0, 0.0, 20.0, 20.0)
    >>> band_share([[0.5, 0.5], [0.5, 19.5], [19.5, 19.5]], box, 1.0)  # along two sides
    1.0
    >>> band_share([[0.5, 10.0], [19.5, 10.0]], box, 1.0)  # across: 0.5 m at each end of 19
    0.05263157894736842
    """
    p = np.asarray(points, float)
    left, bottom, right, top = bounds
    inner = (left + band, bottom + band, right - band, top - band)
    total = inside = 0.0
    for a, b in zip(p[:-1], p[1:], strict=True):
        length = float(np.hypot(*(b - a)))
        total += length
        inside += length * _clip(a, b, inner)
    if total == 0.0:
        return float(all(_clip(q, q, inner) == 0.0 for q in p)) if len(p) else 0.0
    return float((total - inside) / total)


def _clip(a, b, box) -> float:
    """The fraction of the segment ``a``-``b`` strictly inside ``box`` (left, bottom, right,
    top; Liang-Barsky); for a point (``a == b``) 1.0 when it is inside, else 0.0."""
    left, bottom, right, top = box
    if left >= right or bottom >= top:
        return 0.0
    d = b - a
    t0, t1 = 0.0, 1.0
    for p, q in ((-d[0], a[0] - left), (d[0], right - a[0]), (-d[1], a[1] - bottom),
                 (d[1], top - a[1])):  # fmt: skip
        if p == 0.0:
            if q <= 0.0:
                return 0.0
        elif p < 0.0:
            t0 = max(t0, q / p)
        else:
            t1 = min(t1, q / p)
    return max(0.0, t1 - t0)


@cache
def grid_at(path: Path):
    """The grid file at ``path``, read once per report (the planning section shares it)."""
    return read_grid(path)


def route_share(job: JobResults) -> float | None:
    """The share of the route job's length in its grid's edge band (:data:`BAND` cells); None
    without its route or its grid."""
    route, where = job.dir / "route.geojson", job.grid_dir()
    if not route.is_file() or where is None or not (where / "grid.tif").is_file():
        return None
    grid = grid_at(where / "grid.tif")
    return band_share(read_path_geojson(route)[0], grid.bounds, BAND * grid.cell_size)


def hugs(job: JobResults) -> bool | None:
    """Whether the route job's route hugs the edges (more than :data:`THRESHOLD` of its length
    in the band); None without its route or its grid."""
    share = route_share(job)
    return None if share is None else share > THRESHOLD


class EdgeCount(NamedTuple):
    """How many routes of ``method`` in ``case`` hug the edges: ``hugging`` of ``known`` routes
    whose files could be read (of ``runs`` in the table); ``keys`` the hugging routes' jobs."""

    case: str
    method: str
    hugging: int
    known: int
    runs: int
    keys: tuple[str, ...]

    def text(self) -> str:
        """``24 of 50 routes of issa in grid20 hug the grid's edges``."""
        unread = f" ({self.runs - self.known} without files)" if self.known < self.runs else ""
        return (f"{self.hugging} of {self.known} routes of {self.method} in {self.case} hug "
                f"the grid's edges{unread}")  # fmt: skip


def edge_share(results: Results, claim) -> tuple[EdgeCount, ...]:
    """For a claim on routes (``claim.kind == "routes"``), per case of ``claim.cases`` and per
    method (``claim.method``, then ``claim.rivals``), the routes that hug the edges
    (:class:`EdgeCount`, :func:`hugs`); () for a claim of another kind. Every route of the
    table counts, whatever its seed or whether it collides; a route without its files is not
    in ``known``. Judging is untouched: the caller says where the flagged routes decide a
    verdict (e.g. judging the claim again without ``keys``)."""
    if claim.kind != "routes":
        return ()
    counts = []
    for case in claim.cases:
        for method in (claim.method, *claim.rivals):
            jobs = results.group("routes", case, method)
            flags = [(j.key, hugs(j)) for j in jobs]
            known = [(k, f) for k, f in flags if f is not None]
            counts.append(EdgeCount(case, method, sum(f for _, f in known), len(known),
                                    len(jobs), tuple(k for k, f in known if f)))  # fmt: skip
    return tuple(counts)
