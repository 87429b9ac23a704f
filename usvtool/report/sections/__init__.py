"""The comparison report's sections (``usvtool report``, docs/report.md), one module each, in
reading order: :mod:`.claims` (the papers' claims and their verdicts), :mod:`.planning` (global
path planning), :mod:`.benchmark_functions`, :mod:`.encounters` (collision avoidance),
:mod:`.preprocessing` (charts and their grids) and :mod:`.methods` (what produced the results).
Each ``section(results)`` builds its part of the document (:mod:`usvtool.report.document`) from
the loaded results (:mod:`usvtool.report.data`), or None without data; :mod:`.published` sets a
paper's table beside our figures for the sections that show one. :mod:`usvtool.report.build`
puts them together.
"""
