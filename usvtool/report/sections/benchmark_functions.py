"""The report's benchmark-function section: the IWSO paper's Table 1 (best, worst, mean and
standard deviation of the final cost over the runs) with ours beside the paper's figures, then
the same statistics for every optimizer we ran, those the paper has not included."""

from __future__ import annotations

from usvtool.report.data import Results, stats
from usvtool.report.document import Cell, Section, Table, number
from usvtool.report.papers import TABLES
from usvtool.report.sections import published

STATS = ("best", "worst", "mean", "std")


def _function_order(name: str) -> tuple:
    digits = name.lstrip("Ff")
    return (0, int(digits)) if digits.isdigit() else (1, name)


def table(results: Results) -> Table:
    """One row per function and algorithm, over its runs."""
    rows = []
    for f in sorted(results.cases("functions"), key=_function_order):
        for a in results.methods("functions", f):
            s = stats(results.values("functions", f, a, "final_cost"))
            rows.append([Cell(f), Cell(a), Cell(str(s["n"]), "num"),
                         *(number(s[name], 3) for name in STATS)])  # fmt: skip
    return Table("functions-table", "Benchmark functions: every optimizer",
                 "Final cost after the last iteration, over the runs of each optimizer.",
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
    s.blocks.append(table(results))
    return s
