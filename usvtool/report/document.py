"""The report as data: sections of paragraphs, figures and tables, rendered by the templates.

Building the document (:mod:`.sections`) is kept apart from writing it (:mod:`.page`), so
that the HTML and the PDF come from one document and the tests can look at it directly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Cell:
    """A table cell: its text and a CSS class (``num``, ``paper``, ``holds``, ``fails``...)."""

    text: str
    css: str = ""


@dataclass(frozen=True)
class Table:
    id: str
    title: str
    caption: str
    columns: list[str]
    rows: list[list[Cell]]


@dataclass(frozen=True)
class Figure:
    """A figure: ``png`` bytes and ``data``, the CSV of what it plots (written beside the
    report as ``data/<id>.csv``)."""

    id: str
    title: str
    caption: str
    png: bytes
    data: str


@dataclass
class Section:
    id: str
    title: str
    paragraphs: list[str] = field(default_factory=list)
    blocks: list[Table | Figure] = field(default_factory=list)
    subsections: list[Section] = field(default_factory=list)

    def figures(self) -> list[Figure]:
        own = [b for b in self.blocks if isinstance(b, Figure)]
        return own + [f for s in self.subsections for f in s.figures()]

    def tables(self) -> list[Table]:
        own = [b for b in self.blocks if isinstance(b, Table)]
        return own + [t for s in self.subsections for t in s.tables()]


def number(value: float | None, digits: int = 2) -> Cell:
    """A right-aligned number with ``digits`` decimals (``-`` when unknown); scientific notation
    for magnitudes below 1e-3 or above 1e6, as the papers print such figures."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return Cell("-", "num")
    if value != 0 and (abs(value) < 1e-3 or abs(value) >= 1e6):
        return Cell(f"{value:.{max(digits, 2)}e}", "num")
    return Cell(f"{value:.{digits}f}", "num")


def paper(value: float | None, digits: int = 2) -> Cell:
    """A published figure, set apart from ours."""
    cell = number(value, digits)
    return Cell(cell.text, "num paper")
