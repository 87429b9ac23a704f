"""Segmentation of chart images into land and water (ISSA paper section 3.1 and Figure 8).

The pipeline, each stage with a real library:

1. fuzzy C-means clustering of the chart's colours (scikit-fuzzy): ``cmeans`` on a seeded
   subsample of pixels in CIE Lab, then ``cmeans_predict`` to give every pixel its memberships.
   A chart has few distinct colours, so memberships are predicted once per distinct colour and
   looked up per pixel: the result is the same as predicting every pixel, at a fraction of the
   cost;
2. each cluster is classed by the nearest reference chart colour (:data:`PALETTE`: the S-52 day
   colours and the NOAA paper-chart colours; ``land_colours`` adds the user's own), as land,
   water, drying (intertidal), no-data or ink (text, symbols, lines);
3. Otsu binarisation (OpenCV) of the land membership (or of the chromatic Lab b* channel, or
   of plain grey), or a fixed threshold such as the paper's 100;
4. ink: ink on land joins the land; ink in water is clutter (text, soundings, lines: it becomes
   water) or a hazard (structures, piles, piers: obstacles at their footprint), decided by the
   shape of its strokes (:mod:`usvtool.chart.ink`); then land specks and water holes smaller
   than ``min_area`` pixels are removed (connected components). Hazards are kept whatever their
   size: a pile is small.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import cv2
import numpy as np

from usvtool.chart import ink as ink_rule
from usvtool.chart.colours import colour_index
from usvtool.errors import UsvError

LAND, WATER, DRYING, NODATA, INK = "land", "water", "drying", "nodata", "ink"

#: Reference chart colours (RGB) and their class: S-52 day palette and NOAA paper RNC colours.
PALETTE: list[tuple[tuple[int, int, int], str]] = [
    ((201, 185, 122), LAND),  # S-52 LANDA
    ((244, 232, 193), LAND),  # RNC land (buff)
    ((214, 219, 201), LAND),  # RNC marsh / vegetated land
    ((212, 234, 238), WATER),  # S-52 DEPDW
    ((186, 213, 225), WATER),  # S-52 DEPMD
    ((152, 197, 242), WATER),  # S-52 DEPMS
    ((115, 182, 239), WATER),  # S-52 DEPVS
    ((209, 221, 239), WATER),  # RNC shallow water (blue)
    ((255, 255, 255), WATER),  # RNC deep water (white paper)
    ((131, 178, 149), DRYING),  # S-52 DEPIT
    ((150, 176, 155), DRYING),  # RNC foreshore (green)
    ((163, 180, 183), NODATA),  # S-52 NODTA
    ((0, 0, 0), INK),  # text, soundings
    ((82, 90, 92), INK),  # S-52 CSTLN
    ((114, 114, 114), INK),  # RNC grey linework
    ((219, 73, 150), INK),  # RNC magenta
]

CHANNELS = ("membership", "chromatic", "grey")
#: Ink clusters darker than this CIE L* are the chart's black linework (structures are drawn in
#: it; grey contours and magenta aids and limits are lighter).
DARK = 35.0


@dataclass
class Segmentation:
    """Pixel-level result of :func:`segment`."""

    land: np.ndarray  # bool (H, W): land after binarisation and clutter removal
    blocked: np.ndarray  # bool (H, W): land, drying, no-data, ink hazard or outside the chart
    hazard: np.ndarray  # bool (H, W): ink in water standing for a structure (ink.resolve)
    threshold: float  # binarisation threshold on the 0..255 channel
    clusters: list[dict] = field(default_factory=list)  # centre RGB, class, pixel share
    timings: dict[str, float] = field(default_factory=dict)


def segment(
    image: np.ndarray | tuple[np.ndarray, np.ndarray],
    valid: np.ndarray | None = None,
    *,
    clusters: int = 8,
    land_colours: list[tuple[int, int, int]] | None = None,
    channel: str = "membership",
    threshold: float | None = None,
    min_area: int = 16,
    ink: str = "auto",
    sample: int | None = 20000,
    seed: int = 0,
    m: float = 2.0,
) -> Segmentation:
    """Segment a chart image into land and water.

    ``image`` is an RGB array (H, W, 3 uint8) or, as raster sources give it, ``(index,
    palette)``: colour indices (H, W) into distinct colours (n, 3 uint8)
    (:mod:`usvtool.chart.colours`). ``valid`` marks the pixels inside the chart (default: all).
    ``threshold`` (0..255) replaces Otsu's; ``min_area`` is in pixels; ``ink`` is the ink rule
    (``auto``, ``clutter`` or ``obstacle``, see :mod:`usvtool.chart.ink`). ``sample`` pixels
    are clustered; ``None`` clusters every pixel (the slow reference the benchmark compares
    against). Raises :class:`UsvError` when the image holds no water or no land.
    """
    if channel not in CHANNELS:
        raise ValueError(f"channel must be one of {CHANNELS}")
    if ink not in ink_rule.MODES:
        raise ValueError(f"ink must be one of {ink_rule.MODES}")
    timings: dict[str, float] = {}
    t = time.perf_counter()
    index, colours_rgb = image if isinstance(image, tuple) else colour_index(image)
    valid = np.ones(index.shape, bool) if valid is None else valid
    if not valid.any():
        raise UsvError("the chart has no pixels inside its valid area")
    valid_index = index[valid]
    counts = _counts(index, valid, len(colours_rgb))
    if np.count_nonzero(counts) < 2:
        raise UsvError("the chart has a single colour: no land/water contrast to segment")
    colours_lab = _lab(colours_rgb)
    timings["colours"] = time.perf_counter() - t

    t = time.perf_counter()
    rng = np.random.default_rng(seed)
    n_clusters = int(min(clusters, np.count_nonzero(counts)))
    if sample is None or sample >= valid_index.size:
        picks = valid_index
    else:
        picks = valid_index[rng.integers(0, valid_index.size, sample)]
    centres, u = _fuzzy_cmeans(colours_lab, picks, n_clusters, m, rng)
    timings["fcm"] = time.perf_counter() - t

    t = time.perf_counter()
    cluster_class = _classify(centres, land_colours or [])
    is_land = np.array([c == LAND for c in cluster_class])
    colour_class = np.asarray(cluster_class)[np.argmax(u, axis=0)]
    membership = u[is_land].sum(axis=0)  # land membership per distinct colour
    chan_colour, thr_colour_side = _channel(channel, membership, colours_rgb, is_land, u)
    chan = chan_colour[index]
    if threshold is None:
        thr, _ = cv2.threshold(
            chan[valid].reshape(-1, 1), 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU
        )
    else:
        thr = float(threshold)
    land = (chan > thr) if thr_colour_side else (chan <= thr)
    del chan
    land &= valid
    timings["binarise"] = time.perf_counter() - t

    t = time.perf_counter()
    inked = (colour_class == INK)[index] & valid
    layers = np.argmax(u, axis=0).astype(np.uint8)[index]  # each pixel's colour cluster
    dark = [k for k in range(n_clusters) if cluster_class[k] == INK and centres[k, 0] < DARK]
    land, hazard = ink_rule.resolve(inked, land, ink, layers, dark)
    land = _remove_small(land, min_area) & valid
    other = np.isin(colour_class, (DRYING, NODATA))[index]
    other = _remove_small(other & ~land & valid, min_area)
    hazard &= valid & ~land
    blocked = land | other | hazard | ~valid
    timings["clutter"] = time.perf_counter() - t

    share = np.bincount(np.argmax(u, axis=0), weights=counts, minlength=n_clusters)
    info = [
        {
            "rgb": [int(v) for v in _rgb(centres[k : k + 1])[0]],
            "class": cluster_class[k],
            "share": round(float(share[k] / share.sum()), 4),
        }
        for k in range(n_clusters)
    ]
    if not land.any():
        raise UsvError(
            "found no land in the chart: give its land colour with --land-colour R,G,B"
        )
    if blocked[valid].all():
        raise UsvError("found no navigable water in the chart")
    return Segmentation(land, blocked, hazard, float(thr), info, timings)


def _fuzzy_cmeans(colours_lab, picks, c, m, rng):
    """Cluster the sampled pixels (``cmeans``), then predict all distinct colours.

    The initial partition is drawn from ``rng`` (scikit-fuzzy's own ``seed`` would reseed
    NumPy's global generator).
    """
    import skfuzzy

    data = colours_lab[picks].T  # (3, S)
    init = rng.random((c, data.shape[1]))
    init /= init.sum(axis=0)
    centres, *_ = skfuzzy.cmeans(data, c, m, error=1e-5, maxiter=300, init=init)
    u, *_ = skfuzzy.cmeans_predict(colours_lab.T, centres, m, error=1e-5, maxiter=300)
    return centres, u


def _classify(centres_lab: np.ndarray, land_colours) -> list[str]:
    """Class of each cluster centre: that of the nearest reference colour in Lab."""
    refs = [(rgb, cls) for rgb, cls in PALETTE] + [(tuple(c), LAND) for c in land_colours]
    ref_lab = _lab(np.array([r for r, _ in refs], np.uint8))
    d = np.linalg.norm(centres_lab[:, None, :] - ref_lab[None, :, :], axis=2)
    return [refs[j][1] for j in np.argmin(d, axis=1)]


def _channel(channel, membership, colours_rgb, is_land, u):
    """The 0..255 channel per distinct colour, and whether land lies above the threshold."""
    if channel == "membership":
        return np.round(membership * 255).astype(np.uint8), True
    if channel == "chromatic":  # Lab b*: yellow-brown land high, blue water low
        b = _lab(colours_rgb.astype(np.uint8))[:, 2]
        return np.clip(np.round(b + 128), 0, 255).astype(np.uint8), True
    grey = _grey(colours_rgb)
    # land is on the side of the threshold where the land clusters' grey lies
    weights = u[is_land].sum(axis=0)
    land_grey = np.average(grey, weights=weights + 1e-12)
    water_grey = np.average(grey, weights=(1 - weights) + 1e-12)
    return grey, bool(land_grey > water_grey)


def _counts(index: np.ndarray, valid: np.ndarray, n: int) -> np.ndarray:
    """Pixels of each colour inside the chart. 8-bit indices use OpenCV's histogram (NumPy's
    ``bincount`` first widens them to 64 bits, ten times slower), over bands of rows of at most
    2^24 pixels, which its float32 counts hold exactly."""
    if index.dtype != np.uint8:
        return np.bincount(index[valid], minlength=n)
    rows = max(1, (1 << 24) // index.shape[1])
    total = np.zeros(n, np.int64)
    for r in range(0, index.shape[0], rows):
        band = np.s_[r : r + rows]
        hist = cv2.calcHist([index[band]], [0], valid[band].view(np.uint8), [256], [0, 256])
        total += hist.ravel()[:n].astype(np.int64)
    return total


def _remove_small(mask: np.ndarray, min_area: int) -> np.ndarray:
    """Drop components of ``mask`` and fill holes in it smaller than ``min_area`` pixels.

    The work is done on the box of ``mask`` grown by ``ceil(sqrt(min_area))`` pixels: every
    component of ``mask`` lies inside it, and every background component reaching the box's
    edge joins the background around it, whose corner blocks alone hold ``min_area`` pixels.
    """
    if min_area <= 1 or not mask.any():
        return mask
    x, y, w, h = cv2.boundingRect(mask.view(np.uint8))
    m = int(np.ceil(np.sqrt(min_area)))
    box = np.s_[max(0, y - m) : y + h + m, max(0, x - m) : x + w + m]
    out = mask.copy()
    part = out[box]
    for value in (True, False):
        n, labels, area = _components((part == value).view(np.uint8))
        flip = area < min_area
        flip[0] = False
        if flip.any():
            part[flip[labels]] = not value
    return out


def _components(mask: np.ndarray):
    """(n, labels, area) of the 8-connected components of a 0/1 mask (:func:`ink.label`); the
    areas of 16-bit labels by OpenCV's histogram, several times faster than a statistics pass
    (float counts, exact up to 2^24 pixels, far above any threshold they are compared with)."""
    n, labels = ink_rule.label(mask)
    if labels.dtype == np.uint16:
        return n, labels, cv2.calcHist([labels], [0], None, [n], [0, n]).ravel()
    return n, labels, np.bincount(labels.ravel(), minlength=n)


def _lab(rgb: np.ndarray) -> np.ndarray:
    """CIE Lab (OpenCV's 8-bit scaling undone) of an (n, 3) uint8 RGB array."""
    lab = cv2.cvtColor(rgb.reshape(-1, 1, 3), cv2.COLOR_RGB2LAB).reshape(-1, 3).astype(float)
    return lab * [100 / 255, 1, 1] - [0, 128, 128]


def _rgb(lab: np.ndarray) -> np.ndarray:
    scaled = (lab + [0, 128, 128]) / [100 / 255, 1, 1]
    arr = np.clip(np.round(scaled), 0, 255).astype(np.uint8).reshape(-1, 1, 3)
    return cv2.cvtColor(arr, cv2.COLOR_LAB2RGB).reshape(-1, 3)


def _grey(colours_rgb: np.ndarray) -> np.ndarray:
    arr = colours_rgb.astype(np.uint8).reshape(-1, 1, 3)
    return cv2.cvtColor(arr, cv2.COLOR_RGB2GRAY).reshape(-1)
