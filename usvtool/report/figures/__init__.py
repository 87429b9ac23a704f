"""The report's figures: pure functions from loaded data to a :class:`Plot`, deterministic PNG
bytes (Matplotlib, Agg, fixed size and dpi) and the CSV text of exactly the data plotted.

docs/report-figures.md says what each figure shows and its data columns.
"""

from usvtool.report.figures.canvas import Plot
from usvtool.report.figures.encounters import encounter_snapshots, snapshot_times
from usvtool.report.figures.maps import preprocessing, routes_on_grid
from usvtool.report.figures.raster import ChartImage, preview_chart
from usvtool.report.figures.runs import nearest_distance, states_against_time
from usvtool.report.figures.statistics import boxplots, convergence

__all__ = [
    "ChartImage",
    "Plot",
    "boxplots",
    "convergence",
    "encounter_snapshots",
    "nearest_distance",
    "preprocessing",
    "preview_chart",
    "routes_on_grid",
    "snapshot_times",
    "states_against_time",
]
