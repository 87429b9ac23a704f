"""A paper's published table beside our figures, in the paper's form.

For each row of a :class:`~usvtool.report.papers.PaperTable` (a method in a case) and each
column with a counterpart metric, our figure is the column's statistic over our seeds
(:func:`usvtool.report.data.statistic`) times its ``scale`` (the paper's unit), set beside the
paper's printed figure. Our figures are over the runs that succeeded (collision-free routes;
runs that arrived without collision: :attr:`~usvtool.report.data.JobResults.succeeded`); the
failed column counts the others, which are never a success in another column. Where a penalty
enters the figure (:data:`PENALISED`: a colliding route's fitness carries the collision
penalty), the figure over every run follows in brackets when some failed. A row whose setup is
not ours (``comparable`` false) shows the paper's
figure alone. A table whose paper states its number of runs (``runs``) has a runs column: ours
(the runs behind our figures, from the results) beside the paper's. An optimisation rate
(``*_rate``) that the runs do not carry is computed from our medians against the reference
controller's, as :func:`usvtool.measures.optimisation_rate` defines it (UDWA Table 1: (UDWA -
CCDWA) / CCDWA of the average distance); the reference's own rate, against itself, is shown
as the reference (:data:`REFERENCE_MARK`), never 0.
"""

from __future__ import annotations

from usvtool import measures
from usvtool.report.data import Results, statistic
from usvtool.report.document import Cell, Table, number
from usvtool.report.papers import PAPERS, TABLES, PaperTable

#: The reference controller of the optimisation rates (UDWA paper, Table 1).
REFERENCE = "ccdwa"
#: What the reference controller's own optimisation rate shows (a rate against itself).
REFERENCE_MARK = "- (ref.)"
#: The metrics a failure's penalty enters (a colliding route's fitness).
PENALISED = frozenset({"fitness"})


def ours(results: Results, table: PaperTable, method: str, case: str, column,
         succeeded: bool = True) -> float | None:  # fmt: skip
    """Our figure of the column for ``method`` in ``case``: over the runs that succeeded (every
    run when ``succeeded`` is false), in the paper's unit."""
    kind = table.kind
    if column.metric.endswith("_rate") and method == REFERENCE:
        return None  # its rate is against itself: the table shows it as the reference
    value = statistic(results, kind, case, method, column.metric, column.statistic, succeeded)
    if value is None and column.metric.endswith("_rate"):
        base = column.metric.removesuffix("_rate") + "_m"
        mine = statistic(results, kind, case, method, base, "median", succeeded)
        ref = statistic(results, kind, case, REFERENCE, base, "median", succeeded)
        if mine is not None and ref not in (None, 0.0) and method != REFERENCE:
            value = float(measures.optimisation_rate(mine, ref))
    return None if value is None else value * column.scale


def is_reference(method: str, column) -> bool:
    """Whether ``column`` is an optimisation rate and ``method`` the controller it is against."""
    return column.metric is not None and column.metric.endswith("_rate") and method == REFERENCE


def _failed(results: Results, kind: str, case: str, method: str) -> Cell:
    jobs = results.select(kind, case, method)
    failed = sum(not j.succeeded for j in jobs)
    return Cell(f"{failed}/{len(jobs)}" if failed else "0", "num" + " fails" * bool(failed))


def _cell(results: Results, t: PaperTable, method: str, case: str, column, digits: int) -> Cell:
    """Ours over the successes; a penalised figure over every run in brackets, when they
    differ in runs."""
    mine = number(ours(results, t, method, case, column), digits)
    jobs = results.select(t.kind, case, method)
    if column.metric not in PENALISED or all(j.succeeded for j in jobs):
        return mine
    every = number(ours(results, t, method, case, column, succeeded=False), digits)
    return Cell(f"{mine.text} ({every.text})", "num")


def _digits(printed: str | None) -> int:
    if not printed or "e" in printed.lower() or "." not in printed:
        return 2 if printed and "e" in printed.lower() else 0
    return len(printed.split(".")[1])


def table(results: Results, paper_table: PaperTable) -> Table:
    t = paper_table
    columns = [c for c in t.columns if c.metric is not None]
    rows = []
    for r in t.rows:
        cells = [Cell(r.method), Cell(r.case)]
        if t.runs is not None:
            n = len(results.values(t.kind, r.case, r.method, columns[0].metric))
            cells += [Cell(str(n), "num"), Cell(str(t.runs), "num paper")]
        cells.append(_failed(results, t.kind, r.case, r.method) if r.comparable
                     else Cell("n/c", "num untested"))  # fmt: skip
        for c in columns:
            i = t.columns.index(c)
            printed = r.printed[i]
            digits = max(_digits(printed), 1)
            if not r.comparable:
                cells.append(Cell("n/c", "num untested"))
            elif is_reference(r.method, c):
                cells.append(Cell(REFERENCE_MARK, "num"))
            else:
                cells.append(_cell(results, t, r.method, r.case, c, digits))
            cells.append(Cell(printed or "-", "num paper"))
        rows.append(cells)
    headings = ["method", "case", *(["runs", "paper"] if t.runs is not None else []), "failed"]
    for c in columns:
        unit = f" ({c.unit})" if c.unit else ""
        headings += [f"{c.heading}{unit}", "paper"]
    paper = PAPERS[t.paper]
    counts = sorted({len(results.values(t.kind, r.case, r.method, columns[0].metric))
                     for r in t.rows if r.comparable} - {0})  # fmt: skip
    n = "-".join(map(str, dict.fromkeys(counts[:1] + counts[-1:]))) or "no"
    runs = (f" over the runs of the runs column (the paper's: {t.runs} each)"
            if t.runs is not None else f" over our seeds: {n} run(s) a row")  # fmt: skip
    kinds = "collision-free routes" if t.kind == "routes" else "runs that arrived without collision"
    penalised = (" (in brackets: over every run, the failures' penalties included)"
                 if any(c.metric in PENALISED for c in columns) else "")  # fmt: skip
    rates = any(is_reference(r.method, c) for r in t.rows for c in columns)
    reference = (f" The optimisation rates are against the reference controller {REFERENCE}, "
                 f"whose own rate (against itself) shows as {REFERENCE_MARK}."
                 if rates else "")  # fmt: skip
    caption = (f"{t.caption} Ours (statistics{runs}, in the paper's units) beside the "
               f"paper's printed figures (grey): over the {kinds}{penalised}; failed: the "
               f"others (failures, and any whose table does not say how they ended), never "
               f"counted in a figure; n/c: our setup is not the paper's. Setup: "
               f"{t.setup}{reference}")  # fmt: skip
    return Table(f"paper-{t.id}", f"{t.label} of the {paper.id.upper()} paper", caption,
                 headings, rows)


def tables(results: Results, kind: str, exclude: tuple[str, ...] = ()) -> list[Table]:
    """The published tables of ``kind`` with a counterpart metric and some case of ours, but
    those whose ids are in ``exclude`` (a section of their own shows them)."""
    have = set(results.cases(kind))
    return [table(results, t) for t in TABLES.values()
            if t.kind == kind and t.id not in exclude and any(c.metric for c in t.columns)
            and have & {r.case for r in t.rows}]  # fmt: skip
