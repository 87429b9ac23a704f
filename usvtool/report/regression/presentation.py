"""The regression report's pages: the HTML page (``templates/regression.html.j2``) and the
Markdown summary for CI logs, which share each group's cells (docs/compare.md)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from usvtool import __version__
from usvtool.report.regression.groups import CLASSES, FAILING, Comparison

if TYPE_CHECKING:
    from usvtool.report.regression.compare import CompareResult

#: Rows of the Markdown summary's table at most.
MARKDOWN_ROWS = 30
MARKDOWN_COLUMNS = ("class", "kind", "case", "method", "metric", "BASE", "HEAD", "change",
                    "tolerance")  # fmt: skip
MARKDOWN_CELLS = ("status", "kind", "case", "method", "metric", "base", "head", "change",
                  "tolerance")  # fmt: skip


def html(result: CompareResult) -> str:
    """The self-contained page ``index.html``."""
    from usvtool.report.templating import render

    rows = [_cells(c) for c in _report_order(c for c in result.comparisons if not c.timing)]
    timings = [_cells(c) for c in _report_order(c for c in result.comparisons if c.timing)]
    return render(
        "regression.html.j2", verdict=_verdict(result), inputs=_inputs(result),
        counts=result.counts(), timing_counts=result.counts(timing=True),
        count_timings=result.tolerances.count_timings, rows=rows, timings=timings,
        version=__version__,
    )  # fmt: skip


def markdown(result: CompareResult) -> str:
    """The short summary for CI logs (docs/compare.md)."""
    shown = ("invalid", "regressed", "missing", "improved")
    timings = "counted" if result.tolerances.count_timings else "not counted"
    lines = [
        f"## usvtool compare: {_verdict(result)}",
        "",
        f"Groups: {_counts_line(result.counts())}.",
        f"Timings ({timings}): {_counts_line(result.counts(timing=True))}.",
        "",
        f"- baseline: `{result.baseline}`",
        f"- current: `{result.current}`",
        f"- tolerances: `{result.tolerances.path}`" if result.tolerances.path
        else "- tolerances: built-in defaults",
    ]
    listed = [c for c in _report_order(result.comparisons) if c.counted and c.status in shown]
    if listed:
        lines += ["", "| " + " | ".join(MARKDOWN_COLUMNS) + " |",
                  "|---|---|---|---|---|---:|---:|---:|---:|"]  # fmt: skip
        for c in listed[:MARKDOWN_ROWS]:
            cells = _cells(c)
            lines.append("| " + " | ".join(_md(cells[k]) for k in MARKDOWN_CELLS) + " |")
        if len(listed) > MARKDOWN_ROWS:
            lines += ["", f"… and {len(listed) - MARKDOWN_ROWS} more: see regression.json "
                      "or index.html."]  # fmt: skip
    return "\n".join(lines) + "\n"


def _md(text: str) -> str:
    return text.replace("|", "\\|")


def _report_order(comparisons) -> list[Comparison]:
    return sorted(comparisons, key=lambda c: (CLASSES.index(c.status), c.label))


def _number(x: float) -> str:
    return str(int(x)) if x.is_integer() and abs(x) < 1e15 else format(x, ".6g")


def _figure(value: float | str | None) -> str:
    if value is None:
        return "—"
    if isinstance(value, str):
        return value or "(none)"
    return _number(value)


def _cells(c: Comparison) -> dict[str, str]:
    """The display text of a comparison's columns, and its class."""
    change = ""
    if c.change:
        change = ("+" if c.change > 0 else "") + _number(c.change)
        if c.relative_change is not None:
            change += f" ({c.relative_change:+.1%})".replace("%", " %")
    elif c.change == 0:
        change = "0"
    elif c.status == "invalid":
        expected = "True/False" if c.aggregate == "mean" else "numbers"
        change = f"{c.invalid} of {c.n_head} not {expected}"
    elif c.status == "changed":
        change = "changed"
    n = str(c.n_base) if c.n_base == c.n_head else f"{c.n_base} → {c.n_head}"
    if c.n_base == 0 or c.n_head == 0:
        n = str(c.n_base or c.n_head)
    return {
        "status": c.status, "kind": c.kind, "case": c.case, "method": c.method,
        "metric": c.metric, "better": c.better, "over": f"{c.aggregate} of {n}",
        "base": _figure(c.base), "head": _figure(c.head), "change": change,
        "tolerance": "" if c.allowed is None else "±" + _number(c.allowed),
    }  # fmt: skip


def _verdict(result: CompareResult) -> str:
    counts = result.counts()
    if result.tolerances.count_timings:
        for name, n in result.counts(timing=True).items():
            counts[name] += n
    text = "FAIL" if result.status else "PASS"
    failed = [f"{counts[name]} {name}" for name in FAILING if counts[name]]
    return f"{text}: {', '.join(failed)}" if failed else text


def _inputs(result: CompareResult) -> list[tuple[str, str]]:
    return [("baseline", result.baseline), ("current", result.current),
            ("tolerances", result.tolerances.path or "(built-in defaults)")]  # fmt: skip


def _counts_line(counts: dict[str, int]) -> str:
    return ", ".join(f"{n} {name}" for name, n in counts.items())
