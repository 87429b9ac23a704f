"""Indexed colour: an image as indices into its distinct colours.

A chart holds few distinct colours, so every stage works on ``(index, palette)``: ``index``
(H, W) unsigned, ``palette`` (n, 3) uint8 RGB. Raster sources produce it (a palette band is
already one), segmentation clusters the palette instead of the pixels.

>>> rgb = np.array([[[255, 255, 255], [0, 0, 0]], [[0, 0, 0], [0, 0, 0]]], np.uint8)
>>> index, palette = colour_index(rgb)
>>> index.tolist(), palette.tolist()
([[1, 0], [0, 0]], [[0, 0, 0], [255, 255, 255]])
"""

from __future__ import annotations

import numpy as np


def pack(r: np.ndarray, g: np.ndarray, b: np.ndarray) -> np.ndarray:
    """24-bit packed RGB (uint32) of three uint8 channels."""
    return (r.astype(np.uint32) << 16) | (g.astype(np.uint32) << 8) | b


def index_dtype(n: int):
    """The smallest unsigned dtype holding 0..n."""
    return next(t for t in (np.uint8, np.uint16, np.uint32) if n <= np.iinfo(t).max)


def index_packed(packed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(index, palette) of packed RGB values, the palette in packed order.

    One pass marks the colours seen in a 2^24 table, one look-up gives the indices: no sort,
    linear in the pixels. The index has the smallest unsigned dtype that also holds n (the
    value sources reserve for pixels outside the chart while warping).
    """
    seen = np.zeros(1 << 24, bool)
    seen[packed] = True
    colours = np.flatnonzero(seen)
    lut = np.zeros(1 << 24, index_dtype(colours.size))
    lut[colours] = np.arange(colours.size)
    palette = np.stack([colours >> 16, (colours >> 8) & 255, colours & 255], 1).astype(np.uint8)
    return lut[packed], palette


def colour_index(rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(index, palette) of an (H, W, 3) uint8 image (see :func:`index_packed`)."""
    return index_packed(pack(rgb[..., 0], rgb[..., 1], rgb[..., 2]))
