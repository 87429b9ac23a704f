"""The papers' metrics of planned routes and simulated runs, one row each (``usvtool metrics``).

Reads the route contract (:mod:`usvtool.route`, path GeoJSON) and the trace contract
(:mod:`usvtool.trace`, trace CSV + events JSON); every figure comes from :mod:`usvtool.measures`.
The columns and their definitions: docs/metrics.md.
"""

from usvtool.metrics.tabulate import (
    ROUTE_COLUMNS,
    RUN_COLUMNS,
    MetricsOptions,
    MetricsResult,
    measure,
)

__all__ = ["ROUTE_COLUMNS", "RUN_COLUMNS", "MetricsOptions", "MetricsResult", "measure"]
