"""The report stage: comparison reports (:mod:`usvtool.report.build`, docs/report.md) and
regression reports (:mod:`usvtool.report.regression`, docs/compare.md) from results tables.

The comparison report is put together from its sections (:mod:`.sections`), which set the
papers' data (:mod:`.papers`) beside ours. Both reports use the pieces at this level: the value
kinds of a results table (:mod:`.values`), the all-or-nothing output writer (:mod:`.output`) and
the templates (:mod:`.templating`); the comparison report also the document model
(:mod:`.document`), its loaded results (:mod:`.data`), its page and PDF (:mod:`.page`) and its
figures (:mod:`.figures`).

Entry points (docs/api.md): :func:`make_report` writes the comparison report (``usvtool
report``, :mod:`.build`); :func:`compare` compares a results table with a baseline (``usvtool
compare``, :mod:`.regression.compare`); :func:`animate` animates a run (``usvtool animate``,
:mod:`.animation`).
"""

from usvtool.report.animation import AnimateOptions, AnimateResult, animate
from usvtool.report.build import ReportOptions, ReportResult, make_report
from usvtool.report.regression.compare import CompareOptions, CompareResult, compare

__all__ = ["AnimateOptions", "AnimateResult", "CompareOptions", "CompareResult",
           "ReportOptions", "ReportResult", "animate", "compare", "make_report"]  # fmt: skip
