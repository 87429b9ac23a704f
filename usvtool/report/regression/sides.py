"""One side of a regression report: a results table and its timings, as groups (kind, case,
method, metric) and each group's figure over its jobs (:mod:`usvtool.report.regression`):
the median of numbers, the rate of ``True``, the share of jobs with an event, or the sorted
words; the values not of the metric's kind when there are any.
"""

from __future__ import annotations

import statistics
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

from usvtool.errors import UsvError
from usvtool.report import values
from usvtool.results import Row, read_results, timings_path

#: Metrics whose row marks an event (its value names it): compared as a share of the jobs.
EVENTS = ("collision", "controller_failed")
#: Metrics whose absence from a job means "none" (no collision, no failed rule).
ABSENT_IS_NONE = ("collision", "controller_failed", "failed_rules")
#: The distinct values an invalid group's figure shows at most.
INVALID_SHOWN = 3

Group = tuple[str, str, str, str]


@dataclass(frozen=True)
class _Figure:
    """A side's figure of a group: its aggregate, value, how many jobs (or values) it is over,
    and how many of them are invalid (the value then lists those, as words)."""

    aggregate: str
    value: float | str
    n: int
    invalid: int = 0


@dataclass
class Side:
    """One table (and its timings): the rows of each group, the jobs of each case and method."""

    values: dict[Group, list[Row]]
    jobs: dict[tuple[str, str, str], int]

    @classmethod
    def read(cls, table: str, refuse_invalid: bool) -> Side:
        """Read the table and the timings beside it; with ``refuse_invalid``, refuse either
        when it holds a value not of its metric's kind (:mod:`usvtool.report.values`)."""
        rows = _read(table, refuse_invalid)
        timings = timings_path(table)
        if timings.is_file() and timings.resolve() != Path(table).resolve():
            rows += _read(timings, refuse_invalid)
        groups: dict[Group, list[Row]] = defaultdict(list)
        keys: dict[tuple[str, str, str], set[str]] = defaultdict(set)
        for r in rows:
            groups[r.group].append(r)
            keys[r.group[:3]].add(r.key)
        return cls(dict(groups), {job: len(k) for job, k in keys.items()})

    def kind(self, metric: str) -> str | None:
        """The metric's kind: the contract's, else the one of this side's values."""
        return values.kind(metric) or values.inferred(
            [r for g, rows in self.values.items() if g[3] == metric for r in rows]
        )

    def figure(self, group: Group, kind: str | None) -> _Figure | None:
        """The figure of a group on this side, its values being of ``kind``; None when absent."""
        rows = self.values.get(group)
        jobs = self.jobs.get(group[:3], 0)
        metric = group[3]
        if rows is None and not (metric in ABSENT_IS_NONE and jobs):
            return None
        rows = rows or []
        if metric in EVENTS:
            return _Figure("share", len({r.key for r in rows}) / jobs, jobs)
        aggregate = {values.NUMBER: "median", values.BOOLEAN: "mean"}.get(kind)
        bad = [r.value for r in rows if not values.valid(kind, r.value)]
        if bad:
            shown = sorted(set(bad))
            text = ";".join(shown[:INVALID_SHOWN]) + (";…" if len(shown) > INVALID_SHOWN else "")
            return _Figure(aggregate, text, len(rows), len(bad))
        numbers = [r.number for r in rows]
        if rows and all(r.value in ("True", "False") for r in rows):
            return _Figure("mean", statistics.fmean(numbers), len(rows))
        if rows and None not in numbers:
            return _Figure("median", float(statistics.median(numbers)), len(rows))
        words = sorted({w for r in rows for w in r.value.split(";") if w})
        return _Figure("words", ";".join(words), len(rows))


def _read(path: str | Path, refuse_invalid: bool) -> list[Row]:
    rows = read_results(path)
    bad = values.invalid(rows) if refuse_invalid else []
    if bad:
        raise UsvError(values.refusal(path, bad))
    return rows
