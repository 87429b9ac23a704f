"""The report's benchmark-function section: the IWSO paper's Table 1 (best, worst, mean and
standard deviation of the final cost over the runs) with ours beside the paper's figures, then
the same statistics for what that table does not show of ours: the optimizers the paper has not
included, and the functions whose rows are not comparable."""

from __future__ import annotations

import json
import math
from typing import NamedTuple

from usvtool.report.data import Results, stats
from usvtool.report.document import HTML, Cell, Section, Table, number
from usvtool.report.papers import CLAIMS, TABLES
from usvtool.report.sections import published

STATS = ("best", "worst", "mean", "std")
#: The paper's table of the functions, the method whose runs are set beside it in words, its
#: rival in the mean claim, and that claim.
TABLE_1, METHOD, MEAN_CLAIM = "iwso-dwa-table-1", "iwso", "iwso-functions-lower-mean"
#: Our mean is far from the paper's when it lies outside the paper's best-worst range by more
#: than this share of the range's larger magnitude, or :data:`FLOOR` (the functions' margin of
#: docs/statistics.md: 1 %, at least 1e-8, below which CEC counts an error as 0).
SHARE, FLOOR = 0.01, 1e-8


class Far(NamedTuple):
    """A function where our mean of ``method`` is far from the paper's (:func:`far`)."""

    function: str
    method: str
    runs: int
    mean: float
    best: float
    worst: float
    paper_mean: float
    paper_best: float
    paper_worst: float


def far(results: Results, method: str) -> list[Far]:
    """The comparable functions of Table 1 where our mean final cost of ``method`` lies outside
    the paper's best-worst range of it by more than the margin (:data:`SHARE`, :data:`FLOOR`),
    in function order."""
    t = TABLES[TABLE_1]
    found = []
    for f in sorted(results.cases("functions"), key=_function_order):
        row = t.row(method, f)
        mine = stats(results.values("functions", f, method, "final_cost"))
        if row is None or not row.comparable or not mine["n"]:
            continue
        best, worst, mean = (t.value(method, f, c) for c in ("best", "worst", "mean"))
        slack = max(FLOOR, SHARE * max(abs(best), abs(worst)))
        if not best - slack <= mine["mean"] <= worst + slack:
            found.append(Far(f, method, mine["n"], mine["mean"], mine["best"], mine["worst"],
                             mean, best, worst))  # fmt: skip
    return found


def _set_up(results: Results) -> str | None:
    """The functions' runs' dimension, agents and iterations as their ``job.json`` records;
    None when it does not record them."""
    jobs = results.select("functions")
    parts = []
    for key, word in (("dim", "-D"), ("pop", " agents"), ("iters", " iterations")):
        found = sorted({j.config.get(key) for j in jobs} - {None})
        if not found:
            return None
        parts.append("/".join(map(str, found)) + word)
    return f"{parts[0]}, {parts[1]} x {parts[2]}"


def _evaluations(results: Results, f: str, method: str) -> float | None:
    """The mean evaluations of the runs of ``method`` on ``f`` (their ``summary.json``)."""
    counts = []
    for j in results.select("functions", f, method):
        path = j.dir / "summary.json"
        if path.is_file():
            rows = json.loads(path.read_text(encoding="utf-8")).get("results") or []
            counts += [r["evaluations"] for r in rows if isinstance(r.get("evaluations"),
                                                                   int | float)]  # fmt: skip
    return sum(counts) / len(counts) if counts else None


def _g(v: float) -> str:
    """Three significant digits, fixed-point from 1e-3 to 1e6 (``-5480``, ``28.8``).

    >>> [_g(v) for v in (-5477.3, 28.82, 0.000458, 1.03e-6, 0.0)]
    ['-5480', '28.8', '4.58e-04', '1.03e-06', '0']
    """
    if v == 0 or not 1e-3 <= abs(v) < 1e6:
        return "0" if v == 0 else f"{v:.2e}"
    return f"{round(v, 2 - math.floor(math.log10(abs(v)))):g}"


def discussion(results: Results) -> str | None:
    """In words, where our IWSO is far from Table 1 (:func:`far`), what was checked, and the
    functions where its mean is not below WSO's (the mean claim's); None when nowhere far."""
    gone = far(results, METHOD)
    if not gone:
        return None
    t = TABLES[TABLE_1]
    each = "; ".join(
        f"{g.function} mean {_g(g.mean)} (best {_g(g.best)}, worst {_g(g.worst)}, {g.runs} "
        f"runs) against the paper's {_g(g.paper_mean)} ({_g(g.paper_best)} to "
        f"{_g(g.paper_worst)})" for g in gone)  # fmt: skip
    rivals = []
    for g in gone:
        others = [r.method for r in t.rows if r.case == g.function and r.comparable
                  and r.method != METHOD and results.values("functions", g.function, r.method,
                                                            "final_cost")]  # fmt: skip
        near = [m for m in others if m not in {x.method for x in far(results, m)
                                                 if x.function == g.function}]  # fmt: skip
        if others:
            rivals.append((g.function, len(near), len(others)))
    set_up = _set_up(results)
    text = (f"Far from the paper: our IWSO's mean lies outside the paper's best-worst range "
            f"(by more than {SHARE * 100:g} % of its larger magnitude, or {FLOOR:g}) on "
            f"{len(gone)} function(s): {each}. "
            + (f"Our runs are {set_up}, the paper's set-up as docs/optimizers.md reads it. "
               if set_up else "")
            + (("The other optimizers of Table 1 land within the paper's range on "
                + ", ".join(f"{f} {k} of {n}" for f, k, n in rivals)
                + (": for most of them the functions, bounds and dimension give the paper's "
                   "figures, so the gap lies in IWSO itself (ours, or details the paper does "
                   "not state). " if all(2 * k > n for _, k, n in rivals) else ". "))
               if rivals else ""))
    evals = {m: _evaluations(results, gone[0].function, m) for m in (METHOD, "wso")}
    if all(evals.values()):
        text += (f"IWSO spends {evals[METHOD] / evals['wso']:.1f} times WSO's evaluations "
                 f"({evals[METHOD]:.0f} against {evals['wso']:.0f} on {gone[0].function}, its "
                 "simplex steps), so the budget does not explain it. ")
    claim = next(c for c in CLAIMS if c.id == MEAN_CLAIM)
    worse = []
    for f in claim.cases:
        mine = stats(results.values("functions", f, METHOD, "final_cost"))["mean"]
        theirs = stats(results.values("functions", f, claim.rivals[0], "final_cost"))["mean"]
        if mine is not None and theirs is not None and mine >= theirs:
            worse.append(f"{f} ({_g(mine)} against {_g(theirs)})")
    if worse:
        text += (f"Our IWSO's mean is not below WSO's on {', '.join(worse)}, which the "
                 f"{MEAN_CLAIM} claim turns on. ")
    return text + ("What was checked (definitions against the paper's text, bounds, "
                   "dimension, iterations, convergence): docs/optimizers.md, \"IWSO far from "
                   "Table 1\".")


def _function_order(name: str) -> tuple:
    digits = name.lstrip("Ff")
    return (0, int(digits)) if digits.isdigit() else (1, name)


def shown_beside_the_paper(results: Results) -> set[tuple[str, str]]:
    """The (function, algorithm) pairs a published table of the section shows our figures of:
    its comparable rows (a row not comparable shows the paper's figures alone)."""
    shown = {t.id for t in published.tables(results, "functions")}
    return {(r.case, r.method) for t in TABLES.values() if f"paper-{t.id}" in shown for r in t.rows
            if r.comparable}  # fmt: skip


def table(results: Results) -> Table:
    """One row per function and algorithm, over its runs, but those the paper's table already
    shows with ours (:func:`shown_beside_the_paper`); when none is left, the table says so in
    the HTML only (nothing in print)."""
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
    label = " and ".join(t.label for t in TABLES.values() if t.kind == "functions")
    if not rows:
        return Table("functions-table", "Benchmark functions: the optimizers the paper leaves "
                     "out", f"None: every optimizer and function of our runs is in {label} "
                     "above, beside the paper's figures.", ["function", "algorithm", "runs",
                                                            *STATS], [], HTML)  # fmt: skip
    cases = {f for f, _ in beside}
    nc = [f for f in sorted(results.cases("functions"), key=_function_order)
          if f not in cases and any(t.kind == "functions" and r.case == f for t in TABLES.values()
                                    for r in t.rows)]  # fmt: skip
    left = (f" Left to {label} above (ours beside the paper's), not repeated here: "
            f"{', '.join(sorted(apart, key=lambda m: results.methods('functions').index(m)))}"
            " on the functions it compares"
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
    words = discussion(results)
    if words:
        s.paragraphs.append(words)
    s.blocks += published.tables(results, "functions")
    s.blocks.append(table(results))
    return s
