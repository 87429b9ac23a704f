"""Animations of a run (``usvtool animate``, docs/animate.md): a GIF, an MP4 or a self-contained
HTML player of a trace CSV, its events JSON and its map.

One module a job: the scene read from the files (:mod:`.scene`), the player's decimation to an
error bound (:mod:`.decimate`), the frames drawn with Matplotlib (:mod:`.frames`), their GIF and
MP4 encoders (:mod:`.encode`), the HTML player (:mod:`.player`) and the entry point
:func:`animate` (:mod:`.build`).
"""

from usvtool.report.animation.build import AnimateOptions, AnimateResult, animate

__all__ = ["AnimateOptions", "AnimateResult", "animate"]
