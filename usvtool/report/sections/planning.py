"""The report's global-planning section: the papers' tables beside ours, one table of every
algorithm on every chart and the routes on the charts of the papers' tables in the main body;
per chart, in the appendix, the routes of every algorithm (the other charts'), box plots over
seeds and a table of the route metrics, and (HTML only) the convergence curves.

A route job's grid is that of its grid job (:meth:`JobResults.grid_dir`); the route drawn for an
algorithm is that of its first seed, the figures over seeds use all of them.
"""

from __future__ import annotations

import numpy as np

from usvtool.report import edges, figures
from usvtool.report.data import JobResults, Results, seed_text, stats
from usvtool.report.document import APPENDIX, HTML, Cell, Figure, Section, Table, number
from usvtool.report.papers import TABLES
from usvtool.report.sections import published
from usvtool.route import read_path_geojson

#: The box-plot panels: (metric, label).
BOXES = (("length_m", "length (m)"), ("turns", "turns"), ("mot", "mot"),
         ("planning_time_s", "time (s)"))  # fmt: skip
#: The per-chart table: (metric, column, decimals).
COLUMNS = (("length_m", "length (m)", 2), ("length_ratio", "length / optimum", 4),
           ("turns", "turns", 1), ("mot", "mot", 4),
           ("planning_time_s", "time (s)", 3))  # fmt: skip


_grid = edges.grid_at  # one read of a grid per report, shared with the edge rule


def grid_of(job: JobResults):
    """The route job's grid (None when its grid job is not beside it)."""
    where = job.grid_dir()
    return _grid(where / "grid.tif") if where and (where / "grid.tif").is_file() else None


def _route(job: JobResults) -> tuple[np.ndarray, dict] | None:
    path = job.dir / "route.geojson"
    return read_path_geojson(path) if path.is_file() else None


def _first(jobs: list[JobResults]) -> JobResults:
    return min(jobs, key=lambda j: (j.seed is None, j.seed))


def chart_section(results: Results, chart: str) -> Section:
    """Routes, convergence, box plots and the metrics table of one chart."""
    methods = results.methods("routes", chart)
    jobs = {m: results.select("routes", chart, m) for m in methods}
    seeds = sorted({j.seed for js in jobs.values() for j in js if j.seed is not None})
    section = Section(f"routes-{chart}", f"Chart {chart}", placement=APPENDIX)
    section.paragraphs.append(
        f"{len(methods)} algorithms, {len(seeds)} seed(s) each for the optimizers "
        f"(seeds {seed_text(seeds)}); the exact planners run once.")
    along = edge_counts(jobs)
    if along:
        section.paragraphs.append(edge_paragraph(along))
    first = {m: _first(js) for m, js in jobs.items()}
    grid = next((g for g in map(grid_of, first.values()) if g is not None), None)
    routes = {m: r[0] for m, r in ((m, _route(j)) for m, j in first.items()) if r is not None}
    if grid is not None and routes:
        start, goal = next(iter(routes.values()))[[0, -1]]
        where = next(d for d in (j.grid_dir() for j in first.values()) if d)
        image = figures.preview_chart(where / "preview.png", grid) if grid.crs else None
        hugging = [m for m in routes if edges.hugs(first[m])]
        plot = figures.routes_on_grid(grid, routes, tuple(start), tuple(goal),
                                      f"{chart}: routes (first seed)", image,
                                      hugging)  # fmt: skip
        under = ("over the chart (its preview: obstacles tinted red, safety margin yellow, "
                 "outside the chart hatched)" if image else
                 "on the navigation grid (obstacles dark, safety margin grey)")  # fmt: skip
        section.blocks.append(Figure(f"routes-{chart}-map", f"Routes on {chart}",
                                     f"Each algorithm's route of its first seed {under}; line "
                                     "and marker give the family (papers' optimizers solid, "
                                     "our variants dashed, exact planners dash-dot)."
                                     + (f" {EDGE_RULE} are drawn over a wide dotted band and "
                                        "labelled (edges)." if hugging else ""),
                                     plot.png, plot.data))  # fmt: skip
    curves = {m: [c for c in (_convergence(j) for j in js) if c] for m, js in jobs.items()}
    curves = {m: c for m, c in curves.items() if c}
    if curves:
        plot = figures.convergence(curves, f"{chart}: convergence")
        section.blocks.append(Figure(f"routes-{chart}-convergence", f"Convergence on {chart}",
                                     "Best cost (m) after each iteration: the median over "
                                     "seeds and the interquartile band.",
                                     plot.png, plot.data, HTML))  # fmt: skip
    values = {label: {m: results.values("routes", chart, m, metric, succeeded=True)
                      for m in methods} for metric, label in BOXES}  # fmt: skip
    if len(seeds) > 1 and any(v for per in values.values() for v in per.values()):
        plot = figures.boxplots(values, f"{chart}: over {len(seeds)} seeds",
                                {m: _free_label(m, jobs[m]) for m in methods})
        section.blocks.append(Figure(f"routes-{chart}-boxes", f"Route metrics on {chart}",
                                     "Length, turns, smoothness mot and planning time over "
                                     "the collision-free routes of each algorithm's seeds (a "
                                     "label says how many when some collide: a route through "
                                     "land is a failure, not a short route). A value far "
                                     "enough to squash a panel is a triangle at its edge with "
                                     "its value (docs/report-figures.md, 'Outliers at the "
                                     "axis's edge'); the data keep it.",
                                     plot.png, plot.data))  # fmt: skip
    section.blocks.append(metrics_table(results, chart, methods))
    return section


#: The edge rule in words (usvtool/report/edges.py, docs/report-figures.md).
EDGE_RULE = (f"Routes that hug the grid's edges (more than {edges.THRESHOLD * 100:g} % of their "
             f"length within {edges.BAND:g} cell of its border)")


def edge_counts(jobs: dict[str, list[JobResults]]) -> dict[str, tuple[int, int]]:
    """Per method with some: (routes that hug the edges, routes whose files were read)."""
    counts = {}
    for m, js in jobs.items():
        flags = [f for f in map(edges.hugs, js) if f is not None]
        if any(flags):
            counts[m] = (sum(flags), len(flags))
    return counts


def edge_paragraph(counts: dict[str, tuple[int, int]]) -> str:
    """The chart's routes that hug the edges, per method, in words."""
    each = ", ".join(f"{m} {k} of {n}" for m, (k, n) in counts.items())
    return (f"{EDGE_RULE}: {each}. Such a route follows the map's frame (where an optimizer's "
            "waypoints clipped to the map's box also land) rather than the water between the "
            "obstacles: it turns little and runs long, so a turns claim it decides says more "
            "of the frame's shape than of the planner.")


def _free_label(method: str, jobs: list[JobResults]) -> str:
    """The method's name, with ``(k of n)`` when only k of its n routes are collision-free."""
    free = sum(j.succeeded for j in jobs)
    return method if free == len(jobs) else f"{method} ({free} of {len(jobs)})"


def metrics_table(results: Results, chart: str, methods: list[str]) -> Table:
    """Medians over the collision-free routes of the route metrics, the collision-free rate and
    the run count."""
    rows = []
    for m in methods:
        cells = [Cell(m)]
        for metric, _, digits in COLUMNS:
            mine = results.values("routes", chart, m, metric, succeeded=True)
            cells.append(number(stats(mine)["median"], digits))
        free = results.values("routes", chart, m, "collision_free")
        cells.append(number(100 * float(np.mean(free)) if free else None, 0))
        cells.append(Cell(str(len(results.select("routes", chart, m))), "num"))
        rows.append(cells)
    columns = ["algorithm", *(c for _, c, _ in COLUMNS), "collision-free (%)", "runs"]
    return Table(f"routes-{chart}-table", f"Route metrics on {chart}",
                 "Medians over the seeds' collision-free routes (a colliding route is a "
                 "failure, counted in the collision-free column, never a short route; - : "
                 "none); docs/metrics.md gives each definition; time is the planning time of "
                 "the machine of the methods section.", columns, rows)  # fmt: skip


def overview_table(results: Results, charts: list[str]) -> Table:
    """Every algorithm on every chart: the median over seeds of its route's length over the
    any-angle optimum (``length_ratio``), and its collision-free share over all its runs."""
    rows = []
    for m in results.methods("routes"):
        cells = [Cell(m)]
        for chart in charts:
            ratio = results.values("routes", chart, m, "length_ratio", succeeded=True)
            cells.append(number(stats(ratio)["median"], 3))
        free = [v for c in charts for v in results.values("routes", c, m, "collision_free")]
        cells.append(number(100 * float(np.mean(free)) if free else None, 0))
        rows.append(cells)
    return Table("routes-overview", "Route length over the optimum, every chart",
                 "Median over the seeds' collision-free routes of each route's length divided "
                 "by the any-angle optimum's (length_ratio, docs/metrics.md; - : not run there, "
                 "or no route collision-free), and the share of collision-free routes over all "
                 "the algorithm's runs. Per chart: the appendix.",
                 ["algorithm", *charts, "collision-free (%)"], rows)  # fmt: skip


def _convergence(job: JobResults) -> list[float]:
    route = _route(job)
    return list(route[1].get("convergence") or []) if route else []


def section(results: Results) -> Section | None:
    """The planning section: one subsection per chart."""
    charts = results.cases("routes")
    if not charts:
        return None
    top = Section("planning", "Global path planning")
    top.paragraphs.append(
        "Every algorithm plans a route from start to goal on each chart with the papers' cost "
        "(length, turn cost, inside-obstacle penalty). The any-angle route is the optimum of "
        "length; the optimizers run over several seeds.")
    top.blocks += published.tables(results, "routes")
    top.blocks.append(overview_table(results, charts))
    papers = {r.case for t in TABLES.values() if t.kind == "routes" for r in t.rows}
    for chart in charts:
        sub = chart_section(results, chart)
        if chart in papers:  # its route map stands in the main body
            top.blocks += [b for b in sub.blocks if b.id == f"routes-{chart}-map"]
            sub.blocks = [b for b in sub.blocks if b.id != f"routes-{chart}-map"]
        top.subsections.append(sub)
    return top
