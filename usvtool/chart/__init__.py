"""Chart inputs, S-52 rendering, segmentation, gridding and swelling.

Entry points (docs/api.md): :func:`preprocess` turns a chart into a navigation grid
(``usvtool preprocess``, :mod:`.preprocessing`); :func:`render` draws an S-57 cell in the S-52
day colours (``usvtool render``, :mod:`.rendering`). Each takes its options and gives a result
with the grid or image and the command's ``summary()``.
"""

from usvtool.chart.preprocessing import PreprocessOptions, PreprocessResult, preprocess
from usvtool.chart.rendering import RenderOptions, RenderResult, render

__all__ = ["PreprocessOptions", "PreprocessResult", "RenderOptions", "RenderResult", "preprocess",
           "render"]  # fmt: skip
