"""The three papers' published figures and improvement claims, as data (docs/papers.md): one
module per paper (:mod:`.iwso_dwa`, :mod:`.issa`, :mod:`.udwa`, each with its ``PAPER``, its
``TABLES`` and its ``CLAIMS``) on the types of :mod:`.schema`; this package gathers them, in
the papers' order, into the lookups below. A new paper is a module and its entry in
:data:`PAPER_MODULES`.

Tables (:data:`TABLES`, by id): each :class:`PaperTable` holds one published table (or the
figures a paper gives in its text), its columns with the paper's headings and units, and one
:class:`PaperRow` per method and case, with every cell as the paper prints it beside its float (None
where the paper gives nothing). Names are usvtool's: algorithms as the optimizer registry spells
them, controllers as the controller registry, cases as the bundled charts (routes), scenarios
(runs) and benchmark functions (functions) are named in the results table
(:mod:`usvtool.results`). A row is ``comparable`` when our case is built to the paper's setup, so
that the report may put our figure beside the paper's; otherwise the report shows the paper's
figure alone. ``notes`` say how cells of the converted (partly garbled) texts were read.

Claims (:data:`CLAIMS`): each improvement (or absolute) claim a paper makes, quoted with its
section: the metric (a column of ``usvtool metrics``, or ``final_cost``), the statistic a paper
states it by, the better direction, the method that should win and the rivals it should beat,
the cases it covers (a chart, a function, or a scene family's kind ``ENTRY/KIND``: every scene
of it, paired by scene across controllers), the paper's table cases each stands for, and the
preconditions our set-up must meet for the metric to move. The report judges each over our
seeds and scenes (:mod:`usvtool.report.judging`, docs/statistics.md): a relative claim
with rank tests, Holm-corrected across the claims table, and an effect size with a bootstrap
interval; an absolute claim (no rivals) by whether every run of the method in every case
reaches ``target`` (a number, or the name of another metric of the same run that the metric
must equal), with a Clopper-Pearson interval of the proportion that does.

>>> UDWA_TABLE_1.value("udwa", "emergency-head-on", "closest_distance_m")
59.48
>>> IWSO_DWA_TABLE_1.value("iwso", "F5", "mean")
1.03e-06
>>> IWSO_DWA_TABLE_1.value("issa", "F5", "mean") is None  # not in the paper
True
>>> [c.id for c in CLAIMS if c.paper == "udwa"][:2]
['udwa-larger-closest-distance', 'udwa-larger-average-distance']
"""

from __future__ import annotations

from usvtool.report.papers import issa, iwso_dwa, udwa
from usvtool.report.papers.issa import ISSA_FIGURE_11, ISSA_TABLE_3
from usvtool.report.papers.iwso_dwa import IWSO_DWA_ENCOUNTERS, IWSO_DWA_TABLE_1, IWSO_DWA_TABLE_2
from usvtool.report.papers.schema import (
    BETTER,
    CHECKS,
    STATISTICS,
    Claim,
    Column,
    Paper,
    PaperRow,
    PaperTable,
    Precondition,
    Quote,
)
from usvtool.report.papers.udwa import UDWA_TABLE_1, UDWA_WIND

#: The papers' modules, in the order of their files (000, 002, 004): the order of the lookups.
PAPER_MODULES = (iwso_dwa, issa, udwa)
#: Each paper by its id.
PAPERS: dict[str, Paper] = {m.PAPER.id: m.PAPER for m in PAPER_MODULES}
#: Each published table by its id, paper by paper.
TABLES: dict[str, PaperTable] = {t.id: t for m in PAPER_MODULES for t in m.TABLES}
#: Every claim, paper by paper.
CLAIMS: tuple[Claim, ...] = tuple(c for m in PAPER_MODULES for c in m.CLAIMS)

__all__ = [
    "BETTER", "CHECKS", "CLAIMS", "PAPERS", "PAPER_MODULES", "STATISTICS", "TABLES", "Claim",
    "Column", "Paper", "PaperRow", "PaperTable", "Precondition", "Quote", "ISSA_FIGURE_11",
    "ISSA_TABLE_3", "IWSO_DWA_ENCOUNTERS", "IWSO_DWA_TABLE_1", "IWSO_DWA_TABLE_2", "UDWA_TABLE_1",
    "UDWA_WIND",
]  # fmt: skip
