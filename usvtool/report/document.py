"""The report as data: sections of paragraphs, figures and tables, rendered by the templates.

Building the document (:mod:`.sections`) is kept apart from writing it (:mod:`.page`), so
that the HTML and the PDF come from one document and the tests can look at it directly.

Each section, subsection, table, figure and player has a **placement**: :data:`MAIN` (the
default: the report's main body), :data:`APPENDIX` (after the main body, under "Appendix", in
the HTML and the PDF) or :data:`HTML` (the HTML only, folded in a ``<details>``; left out of
the PDF).
:func:`layout` splits the sections into the main body and the appendix for the templates.
A :class:`Player` (a run's animation) is always placed :data:`HTML`: the PDF keeps its figures.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from usvtool.results import file_name

MAIN, APPENDIX, HTML = "main", "appendix", "html"
PLACEMENTS = (MAIN, APPENDIX, HTML)


@dataclass(frozen=True)
class Cell:
    """A table cell: its text and a CSS class (``num``, ``paper``, ``holds``, ``fails``...);
    ``link``: the id of an element of the page the cell links to (a :class:`Player`'s, on the
    screen only: the PDF has no players), none when empty."""

    text: str
    css: str = ""
    link: str = ""


@dataclass(frozen=True)
class Table:
    id: str
    title: str
    caption: str
    columns: list[str]
    rows: list[list[Cell]]
    placement: str = MAIN


@dataclass(frozen=True)
class Figure:
    """A figure: ``png`` bytes and ``data``, the CSV of what it plots (written beside the
    report as ``figures/<file>.png`` and ``data/<file>.csv``)."""

    id: str
    title: str
    caption: str
    png: bytes
    data: str
    placement: str = MAIN

    @property
    def file(self) -> str:
        """The name of its files (without the suffix): its id as a
        :func:`usvtool.results.file_name` (an id holds a case's name)."""
        return file_name(self.id)


#: How a player's fragment starts (:func:`usvtool.report.animation.player.fragment`).
PLAYER_START = '<div class="usv-player" '


@dataclass(frozen=True)
class Player:
    """A run's animation (:mod:`usvtool.report.animation`): ``fragment`` is the player's
    ``div`` as :func:`usvtool.report.animation.player.player` writes it (the run's data as JSON
    escaped there: no text of an input becomes markup), put in the page as it is, folded in a
    ``<details>`` of id ``id`` (a link's target: :attr:`Cell.link`) under its ``title``, with
    its ``caption`` (both escaped by the template). Placed :data:`HTML` only; the page holds
    the player's styles and script once when it holds a player (:func:`has_players`)."""

    id: str
    title: str
    caption: str
    fragment: str
    placement: str = HTML

    def __post_init__(self):
        if self.placement != HTML:
            raise ValueError(f"player {self.id}: placed {self.placement!r}; a player is placed "
                             f"{HTML!r} only (the PDF keeps its figures)")  # fmt: skip
        if not (self.fragment.startswith(PLAYER_START) and self.fragment.endswith("</div>")):
            raise ValueError(f"player {self.id}: its fragment is not a player's div")


@dataclass
class Section:
    id: str
    title: str
    paragraphs: list[str] = field(default_factory=list)
    blocks: list[Table | Figure | Player] = field(default_factory=list)
    subsections: list[Section] = field(default_factory=list)
    placement: str = MAIN

    def figures(self) -> list[Figure]:
        own = [b for b in self.blocks if isinstance(b, Figure)]
        return own + [f for s in self.subsections for f in s.figures()]

    def tables(self) -> list[Table]:
        own = [b for b in self.blocks if isinstance(b, Table)]
        return own + [t for s in self.subsections for t in s.tables()]

    def players(self) -> list[Player]:
        own = [b for b in self.blocks if isinstance(b, Player)]
        return own + [p for s in self.subsections for p in s.players()]


def anchor(*parts: str) -> str:
    """An element id (a link's target) made of names from the results, joined by ``_``: each
    part its :func:`usvtool.results.file_name` with ``%`` as ``~`` and ``_`` as ``~5F``, so
    that the id holds letters, digits and ``._+-~`` only and two lists of names never give one
    id.

    >>> anchor("play", "imazu/05/s000", "udwa+"), anchor("a_b", "c")
    ('play_imazu~2F05~2Fs000_udwa+', 'a~5Fb_c')
    """
    return "_".join(file_name(p).replace("%", "~").replace("_", "~5F") for p in parts)


def has_players(sections: list[Section]) -> bool:
    """Whether any of the sections holds a :class:`Player` (the page then needs its script)."""
    return any(s.players() for s in sections)


def _check(placement: str, what: str) -> None:
    if placement not in PLACEMENTS:
        raise ValueError(f"{what}: placement {placement!r} is not one of {', '.join(PLACEMENTS)}")


def _split(s: Section) -> tuple[Section | None, Section | None]:
    """The section's main-body part and its appendix part (None when empty). A main section's
    appendix blocks and subsections go to a section of the same title in the appendix (id
    ``<id>-appendix``); HTML-only ones stay where they are (the templates fold them)."""
    _check(s.placement, f"section {s.id}")
    for b in s.blocks:
        _check(b.placement, f"{s.id}: {b.id}")
    if s.placement == APPENDIX:
        return None, s
    if s.placement == HTML:
        return s, None
    parts = [_split(sub) for sub in s.subsections]
    main = replace(s, blocks=[b for b in s.blocks if b.placement != APPENDIX],
                   subsections=[m for m, _ in parts if m is not None])  # fmt: skip
    later = [b for b in s.blocks if b.placement == APPENDIX]
    later_subs = [a for _, a in parts if a is not None]
    if not later and not later_subs:
        return main, None
    return main, Section(f"{s.id}-appendix", s.title, blocks=later, subsections=later_subs,
                         placement=APPENDIX)  # fmt: skip


def layout(sections: list[Section]) -> tuple[list[Section], list[Section]]:
    """The main body and the appendix: the top-level sections placed in the appendix, and the
    appendix parts of the others (:func:`_split`), in reading order."""
    parts = [_split(s) for s in sections]
    return [m for m, _ in parts if m is not None], [a for _, a in parts if a is not None]


def number(value: float | None, digits: int = 2) -> Cell:
    """A right-aligned number with ``digits`` decimals (``-`` when unknown), with more decimals
    where those would keep fewer than two significant digits of a number from 1e-3 to 1 (0.0027
    at 2 decimals is 0.0027, 0.4 at none 0.40: a non-zero never prints as 0), and in scientific
    notation with three significant digits below 1e-3 and from 1e6 up, as the papers print
    such figures.

    >>> [number(v, 2).text for v in (0.0027, 0.1, 0.099, 0.0, -3e-5, 2.5e6, 12.345)]
    ['0.0027', '0.10', '0.099', '0.00', '-3.00e-05', '2.50e+06', '12.35']
    >>> [number(v, 0).text for v in (3, 0.4)], number(0.04, 1).text
    (['3', '0.40'], '0.040')
    """
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return Cell("-", "num")
    if value != 0 and (abs(value) < 1e-3 or abs(value) >= 1e6):
        return Cell(f"{value:.2e}", "num")
    if value != 0 and abs(value) < 1:
        digits = max(digits, 1 - math.floor(math.log10(abs(value))))
    return Cell(f"{value:.{digits}f}", "num")


def paper(value: float | None, digits: int = 2) -> Cell:
    """A published figure, set apart from ours."""
    cell = number(value, digits)
    return Cell(cell.text, "num paper")
