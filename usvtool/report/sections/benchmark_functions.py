"""The report's benchmark-function section: the IWSO paper's Table 1 (best, worst, mean and
standard deviation of the final cost over the runs) with ours beside the paper's figures, then
the same statistics for what that table does not show of ours: the optimizers the paper has not
included, and the functions whose rows are not comparable."""

from __future__ import annotations

from usvtool.report.data import Results, stats
from usvtool.report.document import Cell, Section, Table, number
from usvtool.report.papers import TABLES
from usvtool.report.sections import published

STATS = ("best", "worst", "mean", "std")


def _function_order(name: str) -> tuple:
    digits = name.lstrip("Ff")
    return (0, int(digits)) if digits.isdigit() else (1, name)


def shown_beside_the_paper(results: Results) -> set[tuple[str, str]]:
    """The (function, algorithm) pairs a published table of the section shows our figures of:
    its comparable rows (a row not comparable shows the paper's figures alone)."""
    shown = {t.id for t in published.tables(results, "functions")}
    return {(r.case, r.method) for t in TABLES.values() if f"paper-{t.id}" in shown for r in t.rows
            if r.comparable}  # fmt: skip


def table(results: Results) -> Table | None:
    """One row per function and algorithm, over its runs, but those the paper's table already
    shows with ours (:func:`shown_beside_the_paper`); None when none is left."""
    beside = shown_beside_the_paper(results)
    rows, apart = [], set()
    for f in sorted(results.cases("functions"), key=_function_order):
        for a in results.methods("functions", f):
            if (f, a) in beside:
                apart.add(a)
                continue
            s = stats(results.values("functions", f, a, "final_cost"))
            rows.append([Cell(f), Cell(a), Cell(str(s["n"]), "num"),
                         *(number(s[name], 3) for name in STATS)])  # fmt: skip
    if not rows:
        return None
    label = " and ".join(t.label for t in TABLES.values() if t.kind == "functions")
    cases = {f for f, _ in beside}
    nc = [f for f in sorted(results.cases("functions"), key=_function_order)
          if f not in cases and any(t.kind == "functions" and r.case == f for t in TABLES.values()
                                    for r in t.rows)]  # fmt: skip
    left = (f" Not repeated here: {label} above, which shows ours beside the paper's for "
            f"{', '.join(sorted(apart, key=lambda m: results.methods('functions').index(m)))}"
            + (f"; on {', '.join(nc)}, which it marks n/c, every optimizer is here." if nc
               else ".") if apart else "")  # fmt: skip
    title = "Benchmark functions: the optimizers the paper leaves out" if apart else (
        "Benchmark functions: every optimizer")  # fmt: skip
    return Table("functions-table", title,
                 "Final cost after the last iteration, over the runs of each optimizer." + left,
                 ["function", "algorithm", "runs", *STATS], rows)


def section(results: Results) -> Section | None:
    if not results.cases("functions"):
        return None
    s = Section("functions", "Benchmark functions")
    counts = sorted({len(results.select("functions", f, a)) for f in results.cases("functions")
                     for a in results.methods("functions", f)})  # fmt: skip
    runs = " or ".join(map(str, counts))
    theirs = ", ".join(f"{t.label} {t.runs}" for t in TABLES.values()
                       if t.kind == "functions" and t.runs)  # fmt: skip
    s.paragraphs.append(
        "Each optimizer minimises F1-F10 (unimodal F1-F7, multimodal F8-F10; "
        f"usvtool/plan/benchmark_functions.py) from its own seeds: {runs} run(s) each (the "
        f"paper's {theirs}: the runs columns set ours beside it). Figures below 1 that two "
        "significant digits would not survive at the table's decimals are printed in "
        "scientific notation, so no non-zero figure reads 0.00.")
    s.blocks += published.tables(results, "functions")
    rest = table(results)
    if rest is not None:
        s.blocks.append(rest)
    return s
