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

The entry points are imported when first asked for (PEP 562): ``usvtool animate`` and
``usvtool compare`` do not pay for the comparison report's sections and their SciPy.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from usvtool.report.animation import AnimateOptions, AnimateResult, animate
    from usvtool.report.build import ReportOptions, ReportResult, make_report
    from usvtool.report.regression.compare import CompareOptions, CompareResult, compare

#: Each entry point and the module that defines it.
_ENTRY_POINTS = {
    **dict.fromkeys(("AnimateOptions", "AnimateResult", "animate"), "usvtool.report.animation"),
    **dict.fromkeys(("ReportOptions", "ReportResult", "make_report"), "usvtool.report.build"),
    **dict.fromkeys(("CompareOptions", "CompareResult", "compare"),
                    "usvtool.report.regression.compare"),
}  # fmt: skip

__all__ = ["AnimateOptions", "AnimateResult", "CompareOptions", "CompareResult",
           "ReportOptions", "ReportResult", "animate", "compare", "make_report"]  # fmt: skip


def __getattr__(name: str):
    if name not in _ENTRY_POINTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(_ENTRY_POINTS[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
