"""The report stage: comparison reports (:mod:`usvtool.report.build`, docs/report.md) and
regression reports (:mod:`usvtool.report.compare`, docs/compare.md) from results tables."""
