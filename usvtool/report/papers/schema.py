"""What the papers' data is made of (docs/papers.md): a paper, its published tables (columns and
one row per method and case) and its claims, quoted.

The data itself is one module per paper (:mod:`usvtool.report.papers`); :func:`printed_row`
builds a row from its cells as the paper prints them.
"""

from __future__ import annotations

from dataclasses import dataclass

#: How a figure summarises runs: the paper's one figure (one run, or it does not say), the
#: lowest / highest / mean / sample variance / sample standard deviation over the runs, the
#: median (our summary where the paper gives one figure), the figure of the run whose fitness is
#: lowest, or every run (absolute claims).
STATISTICS = ("value", "min", "max", "mean", "variance", "std", "median", "of-best", "every")
BETTER = ("lower", "higher")


@dataclass(frozen=True)
class Paper:
    """One paper: its short id, the converted text's file name (in the project's papers
    directory, /work/shared/papers) and its citation."""

    id: str
    file: str
    citation: str


@dataclass(frozen=True)
class Column:
    """A column of a published table.

    ``heading`` and ``unit`` are the paper's (unit None: the paper gives none); ``metric`` is
    our counterpart (a column of ``usvtool metrics``, or ``final_cost``; None: we have none);
    ``statistic`` how the paper's figure summarises its runs (:data:`STATISTICS`); ``scale``
    converts ours to the paper's units: paper figure = ours x scale (100 for a per cent of our
    fraction, 1/60 for minutes of our seconds).
    """

    name: str
    heading: str
    unit: str | None
    metric: str | None
    statistic: str
    scale: float = 1.0


@dataclass(frozen=True)
class PaperRow:
    """One method in one case: the paper's names beside ours, and one cell per column."""

    method: str
    paper_method: str
    case: str
    paper_case: str
    values: tuple[float | None, ...]
    printed: tuple[str | None, ...]
    comparable: bool = True


@dataclass(frozen=True)
class PaperTable:
    """A published table (``label``: "Table 2"), or the figures a section gives in its text
    (``label``: "Section 5.3"); ``kind`` is the results table's kind of its cases."""

    id: str
    paper: str
    label: str
    section: str
    caption: str
    kind: str
    columns: tuple[Column, ...]
    rows: tuple[PaperRow, ...]
    setup: str
    notes: tuple[str, ...] = ()
    runs: int | None = None  # the runs behind each of the paper's figures, when it says

    def column(self, name: str) -> Column:
        """The column called ``name``; KeyError when the table has none."""
        for c in self.columns:
            if c.name == name:
                return c
        raise KeyError(f"{self.id}: no column {name!r}")

    def row(self, method: str, case: str) -> PaperRow | None:
        """The paper's row for ``method`` in ``case``; None when the paper has none."""
        return next((r for r in self.rows if r.method == method and r.case == case), None)

    def value(self, method: str, case: str, column: str) -> float | None:
        """The paper's figure, in its units; None when the paper gives none."""
        index = self.columns.index(self.column(column))
        row = self.row(method, case)
        return None if row is None else row.values[index]


@dataclass(frozen=True)
class Quote:
    """A passage of a paper, exact but for whitespace, and its section ("5.2", "Abstract")."""

    section: str
    text: str


#: The checks a claim's preconditions may name (:class:`Precondition`; the report makes them,
#: :mod:`usvtool.report.judging`).
CHECKS = ("turns-reachable",)


@dataclass(frozen=True)
class Precondition:
    """What our set-up must allow for the claim's metric to move at all, else the claim is
    *not testable*. ``check`` is one of :data:`CHECKS`: ``turns-reachable``, every route of the
    claim's method and rivals has enough vertices (its ``summary.json``'s ``points``, less the
    two ends) for as many turns as the paper's table gives any of them in the claim's cases.
    ``reason``: what the set-up would need, in words."""

    check: str
    reason: str


@dataclass(frozen=True)
class Claim:
    """A claim of a paper (:mod:`usvtool.report.papers` says how one is judged).

    ``cases``: a results case (``env1``), or a scene family's kind, ``ENTRY/KIND``, standing
    for every run of that kind (``emergency/head-on``: ``emergency/head-on/s000`` ...).
    ``paper_cases``: per case, the cases of the paper's table (``table``) it stands for
    (``emergency/head-on``: the paper's ``emergency-head-on``; empty: the paper's table has no
    row of it); empty altogether when they are the cases themselves. ``paper_change``: per
    case, the relative change of the method against the (first) rival that the paper states,
    in per cent as printed (a decrease for ``better == "lower"``, an increase for
    ``"higher"``), None where it states none; empty when it states none at all. ``table``: the
    id of the paper's table of these cases, if any (it may have no column of the claim's
    metric: the text states the claim alone). ``preconditions``: what the set-up must allow
    (:class:`Precondition`). ``target`` (an absolute claim's: a number, or another metric of
    the same run) is met by a run whose metric is at least as good in the claim's direction;
    ``share``: the share of the runs that must meet it (1: every run, the papers'; a user's
    claim may ask less, docs/statistics.md). ``context``: rivals compared and shown beside the
verdict, outside it and its Holm family (the UDWA paper's dwa, whose weights also differ, beside
the weather ablation). A user's claim (a pipeline's ``claims:``) has no
    paper (``paper`` empty, no quotes)."""

    id: str
    paper: str
    quotes: tuple[Quote, ...]
    kind: str
    metric: str
    statistic: str
    better: str
    method: str
    rivals: tuple[str, ...]
    cases: tuple[str, ...]
    table: str | None = None
    paper_change: tuple[str | None, ...] = ()
    target: float | str | None = None
    note: str = ""
    paper_cases: tuple[tuple[str, ...], ...] = ()
    preconditions: tuple[Precondition, ...] = ()
    share: float = 1.0
    context: tuple[str, ...] = ()

    def table_cases(self, case: str) -> tuple[str, ...]:
        """The cases of the paper's table that ``case`` (one of :attr:`cases`) stands for."""
        if not self.paper_cases:
            return (case,)
        return self.paper_cases[self.cases.index(case)]


def printed_row(method: str, paper_method: str, case: str, paper_case: str,
                *printed: str | None, comparable: bool = True) -> PaperRow:  # fmt: skip
    """A row whose cells are numbers as printed (E notation for Table 1's "m x 10^e")."""
    values = tuple(None if p is None else float(p) for p in printed)
    return PaperRow(method, paper_method, case, paper_case, values, tuple(printed), comparable)
