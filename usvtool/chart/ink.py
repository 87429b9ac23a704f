"""Ink on raster charts: clutter or hazard, decided by the shape of the strokes.

Paper charts draw in ink (black, grey, magenta) two kinds of things over the water: *clutter*
(text, soundings, graticule, leader and contour lines, dashed limits), which says nothing about
the water under it, and *hazards* (structures, platforms, piles, dolphins, piers, jetties), which
stand in it. The ISSA paper's pipeline (section 3) has no notion of either; this module is
usvtool's rule, written by hand because no library classifies chart symbols.

Definitions (all lengths in pixels of the chart image, measured on the chart itself, so the rule
follows the chart's own drawing rather than one chart's resolution; the ink's colour layers only
keep touching symbols of different inks apart and tell black structures from magenta lines):

- *ink side*: an ink pixel belongs to the class (land or water) of its nearest non-ink pixel
  (Euclidean; ties go to land). *Ink in water* is the ink whose nearest non-ink pixel is water.
- *ordinary stroke width* ``w``: twice the median, over the ridge pixels of all ink (local maxima
  of the distance transform inside the ink), of the distance to the nearest non-ink pixel, at
  least 2. Text and linework dominate a chart's ink, so ``w`` is the width of its ordinary
  strokes.
- *ring symbols* (piles, dolphins drawn as small circles) are filled first: a background hole
  (4-connected) enclosed by ink in water is filled when it is small (area at most
  ``pi (1.5 w)^2``), round (bounding box of aspect at most 1.5, at least half filled) and its
  ring is a component of its own, round outside too: its stroke ``s``, the median of the four
  margins between the hole's box and its own (one side may be cut short, one carry a tick), is
  at most ``1.5 w``, its box is at most ``2 (s + max(1, s / 3))`` larger than the hole's each
  way and of aspect at most 1.25. So the loops of 4, 6, 9, b, d, p and q (a tail or stem on
  one side) and the elongated hole of 0 stay open; ink of another colour layer touching the
  ring is cut off first (a pile ring on a grey contour).
- *solids*: the parts of the filled ink in water at least ``2 w + 1`` thick (a morphological
  opening by a disc of that diameter) whose area ``A`` is at most ``1.35 pi R^2``, ``R`` their
  largest inscribed radius (a disc gives 1, a square 1.27, a bar of aspect L/T about 1.27 L/T):
  structures, platforms, filled dots and filled rings; or that taper, like a triangle or a
  teardrop (a wreck's hull, a light's flare): area at most ``4 pi R^2`` and at most a tenth of
  it at ``0.75 R`` or deeper (a bar's deep core is a strip along its length, a quarter of it for
  long bars; a tapering shape's is a small copy of itself, 1/16). Bars (dashes) are not solids,
  and neither is a part whose ``R`` is under 1.05 times the opening disc's radius: where the
  strokes of a glyph meet (the apex of an M, the crossing of a 4), that disc just fits.
- *structures drawn as strokes*: the parts at least ``w + 1`` thick (an opening) that come
  within ``w + 1/2`` of land, the *shore band* (piers, jetties, groins running out from the
  shore), or that stand free as long straight bars of dark ink (detached piers and
  breakwaters): at least ``25 w`` across (box diagonal ``D``), holding between 0.75 and 1 times
  ``D 2 R`` of ink, in a layer the caller names dark (``dark_layers``; all ink when no layers
  are given). Charts draw structures in black, ranges and limits in magenta: on 11361_4 thick
  magenta range lines cross the river, and without the darkness test they became walls. A
  stroke from the shore must *run out* from it: some of it at least :data:`PIER_REACH` of its
  box's diagonal from the land. Roads and rails drawn along a creek's bank do not; they are
  clutter, but still join the hazards in the line-crossing groups below.
- *dock networks* drawn in ordinary strokes (marina finger piers): the ink of one colour layer
  outside the shore band, cut where layers meet, in 8-connected networks that come within
  ``2 w + 3/2`` of land, are at least ``20 w`` across (box diagonal ``D``), hold at least
  ``3.5 D w`` of ink and fill at least a twentieth of their box. A comb of fingers as long as
  their spacing along a spine holds about ``2 L w`` along its own length ``L`` and more with
  longer fingers; a single line holds ``D w``; the shore-attached networks of the bundled
  charts that are not docks hold at most 3.3 ``D w`` (a contour with digits and piers in Lake
  Wesley, before the layers were cut apart), and a chart-wide graticule fills a hundredth of its
  box. The marinas of SanDiego_2 hold 4.4 to 9.5.
- hazards are these, with the solids and the structures grown back by half a stroke inside the
  ink (the opening rounds corners off). Everything else in water (strokes of ordinary width,
  bold labels, dashes) is clutter and becomes water.
- *light ink*: with colour layers given, a structure (from the shore or free) is of dark ink,
  and a solid of light ink neither tapers nor reaches the shore band (a light's magenta flare,
  the piece of a magenta dash that a narrow channel leaves).
- *lines crossing water* are clutter however long, straight or thick (graticule, river-mile,
  leader, cable and pipeline lines, limits, ranges, bridges): the hazards are grouped (pixels
  within ``2 w + 1`` of each other); a group grown by the shore band and by the ink in water
  within another ``w + 1`` of it (a line's thin tips) that cuts a 4-connected piece of the water
  of its box, grown by ``10 w`` (:data:`LINE_MARGIN`), into two or more pieces reaching the
  box's edge is a line. A pier is attached at one end and ends in water: the water flows round
  it. A line becomes water with its ends at the banks (the ink within ``w + 3/2`` of it, which
  the nearest-pixel rule gave to the land and which would block a narrow channel's bank cells).

Modes: ``auto`` (the rule above; bridges are passable), ``auto+bridges`` (the same, but the
groups of dark ink that cross water stay hazards: bridges, and black graticule or mile lines
with them), ``clutter`` (every ink pixel takes the class of its nearest
non-ink pixel: the first version's rule) and ``obstacle`` (every ink pixel in water is a hazard:
the conservative choice).

Known limits: docs/preprocess.md, Ink.
"""

from __future__ import annotations

import cv2
import numpy as np

MODES = ("auto", "auto+bridges", "clutter", "obstacle")
BAND = 1024  # image rows per step where a whole-image temporary is not needed
REACH = 64  # rows a band is grown by on each side for the ink's distances (see _sides)
#: Solids are at least this many ordinary stroke widths thick, and their area is at most
#: SOLID_AREA times their inscribed disc ``pi R^2``.
SOLID_WIDTH = 2.0
SOLID_AREA = 1.35
#: Tapered solids (a wreck's hull, a light's flare): area up to TAPERED_AREA inscribed discs, and
#: at most CORE_SHARE of it at CORE_DEPTH of the largest inscribed radius or deeper. A bar's
#: core is a strip along its length (share 0.25 (1 - 0.75 T / L)), a disc's, a square's or a
#: triangle's a small copy of itself (share 1/16).
TAPERED_AREA = 4.0
#: A solid's inscribed radius is at least this many times the opening disc's radius: blobs where
#: a glyph's strokes meet hold that disc and barely more (44 of the 72 blobs of generated text
#: at 0.89-0.99, the rest at 1.11-1.13 and kept; the bold letters of 12205_2 at 0.90); symbols
#: hold more (1.11 for the smallest generated pile ring, 1.20 and up for the labelled solids).
SOLID_DEPTH = 1.05
CORE_DEPTH = 0.75
CORE_SHARE = 0.1
#: Dock networks: thin-stroked ink of one layer, attached to land (within 2 w + 3/2), at least
#: DOCK_EXTENT strokes across (its box's diagonal), holding at least DOCK_INK times as much ink
#: as a single stroke along that diagonal, and filling at least DOCK_FILL of its box.
DOCK_EXTENT = 20.0
DOCK_INK = 3.5
DOCK_FILL = 0.05
#: A free-standing thick stroke is a structure (a detached pier, jetty or breakwater) when it is
#: of dark ink, at least BAR_LENGTH strokes long and a straight bar: its ink between BAR_FILL
#: times its length times its thickness.
BAR_LENGTH = 25.0
BAR_FILL = (0.75, 1.0)
#: A stroke from the shore is a structure (a pier, jetty, groin) when some of it lies at least
#: PIER_REACH times its box's diagonal from the land; a road or rail along a bank does not.
PIER_REACH = 0.25
#: A structure candidate is a line crossing water when it cuts water that reaches this many
#: ordinary strokes beyond its box on two sides.
LINE_MARGIN = 10.0
#: Holes filled as ring symbols: largest area in units of ``w^2``, and shape limits.
RING_HOLE_AREA = 2.25 * np.pi  # pi (1.5 w)^2: a disc three strokes across
RING_HOLE_ASPECT = 1.5
RING_HOLE_FILL = 0.5
#: ... and the ring around it as round outside (the loops of b, d, p, q stand on a stem), its
#: stroke at most RING_STROKE ordinary widths (the pile rings of 12205_2: 1.4).
RING_ASPECT = 1.25
RING_STROKE = 1.5


def land_side(ink: np.ndarray, land: np.ndarray) -> np.ndarray:
    """Ink pixels whose nearest non-ink pixel is land (ties go to land).

    >>> ink = np.zeros((1, 7), bool); ink[0, 1:6] = True
    >>> land = np.zeros((1, 7), bool); land[0, 0] = True
    >>> land_side(ink, land).astype(int).tolist()
    [[0, 1, 1, 1, 0, 0, 0]]
    """
    return _sides(ink, land)[0]


def stroke_width(ink: np.ndarray, dist: np.ndarray | None = None) -> float:
    """The chart's ordinary stroke width ``w`` in pixels (see the module docstring); ``dist``
    is the ink's distance transform when the caller has it.

    >>> ink = np.zeros((20, 20), bool); ink[5:8, 2:18] = True  # one stroke 3 pixels wide
    >>> stroke_width(ink)
    4.0
    """
    if not ink.any():
        return 2.0
    dist = _distance(ink) if dist is None else dist
    return _width(_ridge(dist, slice(0, dist.shape[0])))


def _ridge(dist: np.ndarray, inner: slice) -> np.ndarray:
    """The distances at the ridge pixels (local maxima of ``dist``, 8-neighbours) of the rows
    ``inner`` of ``dist``, whose other rows are neighbours only."""
    ridge = cv2.compare(dist, cv2.dilate(dist, np.ones((3, 3), np.uint8)), cv2.CMP_GE)
    ridge &= cv2.compare(dist, 0, cv2.CMP_GT)
    return dist[inner][ridge[inner] > 0]


def _width(ridges: np.ndarray) -> float:
    return max(2.0, 2.0 * float(np.median(ridges))) if ridges.size else 2.0


def resolve(
    ink: np.ndarray,
    land: np.ndarray,
    mode: str = "auto",
    layers: np.ndarray | None = None,
    dark_layers: list[int] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Land after the ink is resolved, and the ink hazards in water, by ``mode``.

    ``ink`` marks the ink pixels, ``land`` the land pixels among the others (its value on ink
    pixels is ignored). Returns ``(land, hazard)``: ink on the land side joins the land; the
    ``hazard`` pixels are ink in water that stands for a structure (none with ``clutter``, all
    ink in water with ``obstacle``). ``layers`` (H, W) gives each ink pixel its ink colour, an
    integer below 255 (black linework, grey contours, magenta aids are separate layers of a
    chart), and ``dark_layers`` the layers of black linework; without them all ink is one dark
    layer.

    >>> ink = np.zeros((30, 30), bool); ink[10:19, 10:19] = True  # a solid square in water
    >>> ink[24:26, 5:25] = True  # and a stroke of text, 2 pixels wide
    >>> land = np.zeros((30, 30), bool); land[:, :3] = True
    >>> new_land, hazard = resolve(ink, land)
    >>> int(hazard.sum()), int(hazard[10:19, 10:19].sum()), int(new_land.sum())
    (81, 81, 90)
    >>> int(resolve(ink, land, "clutter")[1].sum())
    0
    """
    if mode not in MODES:
        raise ValueError(f"ink mode must be one of {MODES}")
    on_land, w = _sides(ink, land, width=mode.startswith("auto"))
    land = (land & ~ink) | on_land
    wet = ink & ~on_land
    del on_land
    if mode == "clutter" or not wet.any():
        return land, np.zeros_like(ink)
    if mode == "obstacle":
        return land, wet
    shore = _around(land, w + 0.5)  # the shore band
    separate = _cut_layers(wet, layers)  # a grey contour touching a black pier: two symbols
    hazard = _docks(separate, wet, land, shore, w)
    filled = (wet | _round_holes(wet, separate, w)).view(np.uint8)
    del separate
    dark = None if layers is None or dark_layers is None else np.isin(layers, dark_layers)
    parts = _solids(filled, SOLID_WIDTH * w + 1, shore, dark)
    piers, along = _structures(filled, shore, land, w, dark)
    cv2.bitwise_or(parts, piers, dst=parts)
    # an opening rounds corners off: grow back by half a stroke, inside the ink
    hazard |= _grown(parts, filled, w)
    along = _grown(along, filled, w) & ~hazard
    lines, bridges = _crossings(hazard | along, land, wet, w,
                                dark if mode == "auto+bridges" else None)  # fmt: skip
    hazard |= along & bridges  # a bridge's span along a bank is the bridge's
    if lines.any():
        hazard &= ~lines
        # a line's ends at the banks are nearer land than water: over the water all the same
        land &= ~cv2.bitwise_and(_around(lines, w + 1.5), ink.view(np.uint8)).view(bool)
    return land, hazard


def _grown(parts: np.ndarray, filled: np.ndarray, w: float) -> np.ndarray:
    """``parts`` grown back by half a stroke inside the ink ``filled`` (bool)."""
    return cv2.bitwise_and(_around(parts, (w + 1) / 2), filled).view(bool)


def _crossings(
    candidates: np.ndarray, land: np.ndarray, wet: np.ndarray, w: float, bridges
) -> tuple[np.ndarray, np.ndarray]:
    """(lines, kept bridges): the hazard ``candidates`` that are lines crossing water (bool):
    the groups of them (their pixels within twice the shore band of each other) that, grown by
    a shore band and by the ``wet`` ink within another ``w + 1`` (the rest of a line, too thin
    to be a candidate), cut a piece of the water of their box, grown by :data:`LINE_MARGIN`
    strokes, into two or more pieces that reach the box's edge. ``bridges``: the dark ink,
    whose crossing groups stay (a bridge is drawn in black) and are returned second, or None.
    """
    reach = _around(candidates, w + 0.5)
    n, labels, at, label_at = _label(reach, 8)
    del reach
    out, kept = np.zeros_like(candidates), np.zeros_like(candidates)
    if n == 1:
        return out, kept
    _, left, top, box_w, box_h = _boxes(n, at, label_at, land.shape[1])
    margin = int(np.ceil(LINE_MARGIN * w))
    rows, cols = land.shape
    line = np.zeros(n, bool)
    for k in range(1, n):
        box = np.s_[max(0, top[k] - margin) : min(rows, top[k] + box_h[k] + margin),
                    max(0, left[k] - margin) : min(cols, left[k] + box_w[k] + margin)]  # fmt: skip
        group = labels[box] == k
        group |= wet[box] & _around(group, w + 1).view(bool)
        line[k] = _cuts(land[box], group)
    if bridges is not None and line.any():
        ink_at = candidates.ravel()[at]
        dark_share = np.bincount(label_at, weights=ink_at & bridges.ravel()[at], minlength=n)
        bridge = line & (dark_share > 0.5 * np.bincount(label_at, weights=ink_at, minlength=n))
        kept.ravel()[at] = bridge[label_at]
        line &= ~bridge
    out.ravel()[at] = line[label_at]
    return out & candidates, kept & candidates


def _cuts(land: np.ndarray, group: np.ndarray) -> bool:
    """Whether ``group`` cuts a 4-connected piece of the water ``~land`` into two or more
    pieces that reach the edge of the image.

    >>> land = np.zeros((5, 9), bool); land[[0, -1]] = True
    >>> line = np.zeros_like(land); line[1:4, 4] = True  # bank to bank
    >>> _cuts(land, line), _cuts(land, line & (np.arange(5)[:, None] < 3))  # and one short
    (True, False)
    """
    _, before = label(~land, 4)
    _, after = label(~(land | group), 4)
    edge = np.s_[[0, -1], :], np.s_[:, [0, -1]]
    pieces = np.concatenate([after[e].ravel() for e in edge])
    water = np.concatenate([before[e].ravel() for e in edge])
    pieces, first = np.unique(pieces, return_index=True)
    water = water[first[pieces > 0]]
    return water.size > np.unique(water).size


def _cut_layers(wet: np.ndarray, layers: np.ndarray | None) -> np.ndarray:
    """``wet`` less the pixels next to ``wet`` ink of another layer (8-neighbours), so that
    symbols of different inks touching each other are labelled apart. Layer numbers below 255.
    """
    if layers is None:
        return wet
    layers = layers.astype(np.uint8, copy=False)
    tag = cv2.add(layers, 1, mask=wet.view(np.uint8), dst=np.zeros_like(layers))
    mixed = cv2.dilate(tag, np.ones((3, 3), np.uint8))
    tag[~wet] = 255
    cv2.compare(mixed, cv2.erode(tag, np.ones((3, 3), np.uint8)), cv2.CMP_NE, dst=mixed)
    del tag
    out = wet.copy()
    out[mixed > 0] = False
    return out


def _docks(
    separate: np.ndarray, wet: np.ndarray, land: np.ndarray, shore: np.ndarray, w: float
) -> np.ndarray:
    """Dock networks drawn in ordinary strokes (marina finger piers): see the module docstring.

    ``separate`` is the ink in water cut where layers meet (:func:`_cut_layers`); its ink in
    the shore band is set aside too (the coastline's own stroke would join every network
    along the shore).
    """
    core = cv2.bitwise_and(separate.view(np.uint8), cv2.compare(shore, 0, cv2.CMP_EQ)).view(bool)
    n, labels, at, label_at = _label(core, 8)
    near = _around(land, 2 * w + 1.5)
    cv2.bitwise_and(near, core.view(np.uint8), dst=near)
    attached = np.zeros(n, bool)
    attached[labels.ravel()[np.flatnonzero(near)]] = True
    del near, labels
    area, _, _, bw, bh = _boxes(n, at, label_at, core.shape[1])
    extent = np.hypot(bw, bh)
    dock = attached & (extent >= DOCK_EXTENT * w) & (area >= DOCK_INK * extent * w)
    dock &= area >= DOCK_FILL * bw * bh
    dock[0] = False
    body = np.zeros_like(wet)
    if not dock.any():
        return body
    body.ravel()[at] = dock[label_at]
    # the pier roots in the shore band and the pixels set aside where layers meet
    roots = _around(body, w + 1.5).view(bool)
    roots &= wet
    roots &= ~core
    return body | roots


def _sides(ink: np.ndarray, land: np.ndarray, width: bool = False) -> tuple[np.ndarray, float]:
    """(ink on the land side, the chart's stroke width when ``width`` is asked for, else 2).

    The distance to the nearest non-ink pixel and the distance to the nearest non-ink land
    pixel, two exact Euclidean transforms: an ink pixel is on the land side when the two are
    equal. The same answer as one transform with labels, but for ties, at a fraction of the time
    and memory. Both are computed in bands of rows grown by :data:`REACH` rows, kept at the ink
    pixels only: a distance up to ``REACH`` is exact in its band (its nearest pixel lies within
    that many rows), and a distance to land beyond it is beyond the distance to water too;
    should some ink lie deeper than ``REACH`` inside its strokes, the whole image is done at
    once.
    """
    if not ink.any() or ink.all():
        return np.zeros_like(ink), 2.0
    at = np.flatnonzero(ink)
    dry = ~(land & ~ink)  # zero on the non-ink land
    on_land_at = np.empty(at.size, bool)
    ridges = []
    for grown, own, inside, where in _bands(at, ink.shape, REACH):
        dist = _distance(ink[grown])
        if width:
            ridges.append(_ridge(dist, own))
        dist_at = dist.ravel()[where]
        if dist_at.size and dist_at.max() > REACH:  # ink deeper than the bands reach
            dist = _distance(ink)
            on_land = np.zeros_like(ink)
            on_land.ravel()[at] = _distance(dry).ravel()[at] <= dist.ravel()[at]
            return on_land, stroke_width(ink, dist) if width else 2.0
        on_land_at[inside] = _distance(dry[grown]).ravel()[where] <= dist_at
    on_land = np.zeros_like(ink)
    on_land.ravel()[at] = on_land_at
    return on_land, _width(np.concatenate(ridges)) if width else 2.0


def _solids(
    filled: np.ndarray, width: float, shore: np.ndarray, dark: np.ndarray | None = None
) -> np.ndarray:
    """The parts of ``filled`` at least ``width`` thick (a morphological opening) whose area is
    at most ``SOLID_AREA`` times their inscribed disc: discs, squares, blobs, not bars; or that
    taper (uint8 0/1). With ``dark`` ink given, the solids of light ink neither taper nor
    reach the ``shore`` band: a light's magenta flare, and the piece of a magenta dash that
    a narrow channel leaves, are no symbols standing in the water."""
    thick = _open(filled, width)
    n, labels, at, label_at = _label(thick, 8)  # the thick pixels: a small share of the chart
    if n == 1:
        return thick
    area = _boxes(n, at, label_at, thick.shape[1])[0]
    dist_at = _distance_at(thick.view(bool), at)
    radius = _max_by_label(dist_at, label_at, n)
    disc = np.pi * np.square(radius)
    deep = label_at[dist_at >= CORE_DEPTH * radius[label_at]]
    core_share = np.bincount(deep, minlength=n) / np.maximum(area, 1)
    tapered = (area <= TAPERED_AREA * disc) & (core_share <= CORE_SHARE)
    if dark is not None:
        light = np.bincount(label_at, weights=dark.ravel()[at], minlength=n) <= 0.5 * area
        tapered &= ~light
        ashore = np.zeros(n, bool)
        ashore[labels.ravel()[np.flatnonzero(cv2.bitwise_and(thick, shore))]] = True
    # deeper than the opening's own disc: where the strokes of a glyph meet, that disc just fits
    deep_enough = radius >= SOLID_DEPTH * np.ceil(width) / 2
    solid = ((area <= SOLID_AREA * disc) | tapered) & deep_enough
    if dark is not None:
        solid &= ~(light & ashore)
    solid[0] = False
    out = np.zeros_like(thick)
    out.ravel()[at] = solid[label_at]
    return out


def _structures(
    filled: np.ndarray, shore: np.ndarray, land: np.ndarray, w: float, dark: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """(structures, strokes along a bank), uint8 0/1: the parts of ``filled`` at least ``w + 1``
    thick that reach the ``shore`` band and run out from it (piers, jetties, groins), or that
    stand free as long straight bars of dark ink; and the parts that reach the shore band but
    run along it (:func:`_runs_out`)."""
    strokes = _open(filled, w + 1)
    n, labels, at, label_at = _label(strokes, 8)
    attached = np.zeros(n, bool)
    attached[labels.ravel()[np.flatnonzero(cv2.bitwise_and(strokes, shore))]] = True
    area, left, top, bw, bh = _boxes(n, at, label_at, strokes.shape[1])
    extent = np.hypot(bw, bh)
    long_ = ~attached & (extent >= BAR_LENGTH * w)
    if dark is not None:  # structures are drawn in dark ink
        dark_ink = np.bincount(label_at, weights=dark.ravel()[at], minlength=n) > 0.5 * area
        attached &= dark_ink
        long_ &= dark_ink
    for k in np.flatnonzero(long_):  # few candidates: each one's thickness on its own box
        box = np.s_[top[k] : top[k] + bh[k], left[k] : left[k] + bw[k]]
        radius = _distance(np.pad(labels[box] == k, 1)).max()
        long_[k] = BAR_FILL[0] <= area[k] / (extent[k] * 2 * radius) <= BAR_FILL[1]
    out = attached & _runs_out(labels, land, attached, (left, top, bw, bh))
    along = attached & ~out
    out |= long_
    out[0] = along[0] = False
    kept, bank = np.zeros_like(strokes), np.zeros_like(strokes)
    kept.ravel()[at], bank.ravel()[at] = out[label_at], along[label_at]
    return kept, bank


def _runs_out(labels: np.ndarray, land: np.ndarray, which: np.ndarray, boxes) -> np.ndarray:
    """Whether each labelled stroke of ``which`` runs out from the shore: some of it lies at
    least :data:`PIER_REACH` times its box's diagonal from the land. A pier, a jetty or a
    groin runs out about as far as it is long (a T-head or an oblique pier, more than a
    quarter of it); a road or a rail drawn along a creek's bank runs as long as the bank and stays
    within its own width of it. Each stroke's distance to land is taken on its box grown by
    that share of the diagonal, which holds every land pixel that near."""
    left, top, bw, bh = boxes
    rows, cols = land.shape
    out = np.zeros(which.size, bool)
    for k in np.flatnonzero(which):
        need = PIER_REACH * np.hypot(bw[k], bh[k])
        g = int(np.ceil(need)) + 1
        box = np.s_[max(0, top[k] - g) : min(rows, top[k] + bh[k] + g),
                    max(0, left[k] - g) : min(cols, left[k] + bw[k] + g)]  # fmt: skip
        dist = _distance(~land[box])
        out[k] = dist[labels[box] == k].max() >= need
    return out


def _round_holes(wet: np.ndarray, separate: np.ndarray, w: float) -> np.ndarray:
    """Ring symbols' insides: small, round background holes in ``wet`` ink whose ring is a
    component of its own in ``separate`` (the ink cut where layers meet), round outside too (not
    the loop of a 6, 9, 4 or p, whose tail makes its box larger).

    The background reachable from the chart's edge is flood-filled first, so only the holes
    (a small share of the chart) are labelled.
    """
    cols = wet.shape[1]
    edge = cv2.copyMakeBorder(wet.view(np.uint8), 1, 1, 1, 1, cv2.BORDER_CONSTANT, value=0)
    cv2.floodFill(edge, None, (0, 0), 1, flags=4)
    n, _, at, label_at = _label(edge[1:-1, 1:-1] == 0, 4)  # the holes' pixels suffice
    del edge
    if n == 1:
        return np.zeros_like(wet)
    area, x, y, bw, bh = _boxes(n, at, label_at, cols)
    ring = np.maximum(bw, bh) <= RING_HOLE_ASPECT * np.minimum(bw, bh)
    ring &= (area >= RING_HOLE_FILL * bw * bh) & (area <= RING_HOLE_AREA * w * w)
    ring[0] = False
    holes = np.flatnonzero(ring)
    if holes.size:
        # the ring: the ink components just outside the hole's box at the middle of each side
        # (a ring cut where a foreign ink touches it comes in pieces: their boxes are united)
        n_ink, ink_labels, ink_at, ink_label_at = _label(separate, 8)
        hx, hy, hw, hh = x[holes], y[holes], bw[holes], bh[holes]
        mx, my = hx + hw // 2, hy + hh // 2
        sides = np.stack([  # holes lie inside the image: their sides too
            ink_labels[hy - 1, mx], ink_labels[hy + hh, mx],
            ink_labels[my, hx - 1], ink_labels[my, hx + hw],
        ])  # fmt: skip
        del ink_labels
        keep = np.isin(ink_label_at, sides[sides > 0])
        _, left, top, box_w, box_h = _boxes(n_ink, ink_at[keep], ink_label_at[keep], cols)
        found = sides > 0
        big = np.iinfo(np.int64).max
        x0 = np.where(found, left[sides], big).min(axis=0)
        y0 = np.where(found, top[sides], big).min(axis=0)
        x1 = np.where(found, left[sides] + box_w[sides], -1).max(axis=0)
        y1 = np.where(found, top[sides] + box_h[sides], -1).max(axis=0)
        ring_w, ring_h = x1 - x0, y1 - y0
        # the ring's own stroke: the median of its four sides' widths (one side may be cut
        # short where a foreign ink touched it, one may carry a tick); a ring adds at most that
        # and a third of it (a pixel at least) on each side, a glyph's tail or a line running on
        # adds more
        stroke = np.median([hx - x0, x1 - hx - hw, hy - y0, y1 - hy - hh], axis=0)
        grown = 2 * (stroke + np.maximum(1, stroke / 3))
        ring[holes] = (
            found.any(axis=0)
            & (stroke <= RING_STROKE * w)
            & (ring_w <= hw + grown)
            & (ring_h <= hh + grown)
            & (np.maximum(ring_w, ring_h) <= RING_ASPECT * np.minimum(ring_w, ring_h))
        )
    out = np.zeros_like(wet)
    out.ravel()[at] = ring[label_at]
    return out


def label(mask: np.ndarray, connectivity: int = 8) -> tuple[int, np.ndarray]:
    """(n, labels) of OpenCV's labelling of a boolean or 0/1 ``mask``, without its statistics
    pass (several times the labelling's cost on a chart), in 16-bit labels when there are fewer
    than 65 536 components (half the memory; OpenCV refuses an overflow, then 32-bit ones).

    >>> n, labels = label(np.array([[1, 0, 1], [0, 0, 1]], bool))
    >>> n, labels.dtype.name, labels.tolist()
    (3, 'uint16', [[1, 0, 2], [0, 0, 2]])
    """
    mask = mask.view(np.uint8)
    try:
        return cv2.connectedComponents(mask, None, connectivity, cv2.CV_16U)
    except cv2.error:
        return cv2.connectedComponents(mask, None, connectivity, cv2.CV_32S)


def _label(mask: np.ndarray, connectivity: int):
    """(n, labels, at, label_at): :func:`label`, the flat positions of the labelled pixels and
    their labels."""
    n, labels = label(mask, connectivity)
    at = np.flatnonzero(mask)  # a boolean scan, much faster than one of the int32 labels
    return n, labels, at, labels.ravel()[at]


def _boxes(n: int, at: np.ndarray, label_at: np.ndarray, width: int):
    """(area, left, top, box width, box height) of labels 0..n-1 from their pixels' flat
    positions ``at`` in an image ``width`` wide (zeros for labels without pixels).

    >>> _boxes(3, np.array([1, 2, 5, 8]), np.array([1, 1, 2, 2]), 3)[0].tolist()
    [0, 2, 2]
    """
    area, left, top, box_w, box_h = (np.zeros(n, np.int64) for _ in range(5))
    if at.size:
        rows, cols = np.divmod(at, width)
        order = np.argsort(label_at, kind="stable")
        ids, starts = np.unique(label_at[order], return_index=True)
        area[ids] = np.diff(np.append(starts, order.size))
        r, c = rows[order], cols[order]
        left[ids], top[ids] = np.minimum.reduceat(c, starts), np.minimum.reduceat(r, starts)
        box_w[ids] = np.maximum.reduceat(c, starts) - left[ids] + 1
        box_h[ids] = np.maximum.reduceat(r, starts) - top[ids] + 1
    return area, left, top, box_w, box_h


def _max_by_label(values: np.ndarray, labels: np.ndarray, n: int) -> np.ndarray:
    """The largest value of each label 0..n-1 (0 where a label has none).

    >>> _max_by_label(np.array([3.0, 1.0, 2.0, 5.0]), np.array([2, 1, 2, 1]), 4).tolist()
    [0.0, 5.0, 3.0, 0.0]
    """
    out = np.zeros(n)
    if values.size:
        order = np.argsort(labels, kind="stable")
        ids, starts = np.unique(labels[order], return_index=True)
        out[ids] = np.maximum.reduceat(values[order], starts)
    return out


def _bands(at: np.ndarray, shape: tuple[int, int], reach: int):
    """For each band of :data:`BAND` rows: (its rows grown by ``reach`` on each side, its own
    rows within the grown ones, the slice of the increasing flat positions ``at`` in the band,
    and those positions within the grown band)."""
    rows, cols = shape
    for r in range(0, rows, BAND):
        top, end = max(0, r - reach), min(rows, r + BAND)
        inside = slice(*np.searchsorted(at, [r * cols, end * cols]))
        yield (slice(top, min(rows, end + reach)), slice(r - top, end - top), inside,
               at[inside] - top * cols)  # fmt: skip


def _distance_at(mask: np.ndarray, at: np.ndarray, reach: int = REACH) -> np.ndarray:
    """:func:`_distance` at the increasing flat positions ``at``, computed in bands of rows
    grown by ``reach`` rows on each side, without a whole-image float array: a distance under
    ``reach`` found in a band is exact (its nearest background pixel lies within that many
    rows); should one reach it, the whole image is done at once. (Growing the bands by the
    tallest component's height instead made each band the whole image on a chart framed by a
    thick neatline: 22 s on 12205_1.)
    """
    out = np.empty(at.size, np.float32)
    for grown, _, inside, where in _bands(at, mask.shape, reach):
        if where.size:
            out[inside] = _distance(mask[grown]).ravel()[where]
            if out[inside].max() >= reach:
                return _distance(mask).ravel()[at]
    return out


def _distance(mask: np.ndarray) -> np.ndarray:
    """Exact Euclidean distance from each ``True`` pixel to the nearest ``False`` one."""
    return cv2.distanceTransform(mask.view(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)


def _open(mask: np.ndarray, diameter: float) -> np.ndarray:
    """The morphological opening of ``mask`` by :func:`_disc` of ``diameter`` (uint8 0/1): the
    union of the discs inside it. An even-sized disc has no centre pixel, so the dilation takes
    the erosion's anchor mirrored; with one anchor for both (OpenCV's ``MORPH_OPEN``) the result
    moves by a pixel and is not inside ``mask``.

    >>> bar = np.zeros((9, 9), np.uint8); bar[2:7, 2:6] = 1  # 5 rows by 4 columns
    >>> bool((_open(bar, 4) <= bar).all()), int(_open(bar, 4).sum()), int(_open(bar, 5).sum())
    (True, 16, 0)
    >>> ellipse = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (4, 4))
    >>> bool((cv2.morphologyEx(bar, cv2.MORPH_OPEN, ellipse) <= bar).all())
    False
    """
    disc = _disc(diameter)
    a = (len(disc) - 1) // 2
    thin = cv2.erode(mask.view(np.uint8), disc, anchor=(a, a))
    return cv2.dilate(thin, disc, anchor=(len(disc) - 1 - a,) * 2)


def _around(mask: np.ndarray, radius: float) -> np.ndarray:
    """The pixels within ``radius`` of ``mask`` (uint8 0/1): a dilation by the pixels at most
    ``radius`` from a centre pixel, so that it grows every side alike."""
    r = int(radius)
    y, x = np.mgrid[-r : r + 1, -r : r + 1]
    return cv2.dilate(mask.view(np.uint8), (np.hypot(x, y) <= radius).astype(np.uint8))


def _disc(diameter: float) -> np.ndarray:
    """The pixels of a disc of ``diameter`` (rounded up, at least 2) on a square of that size:
    those whose centres lie within half of it of the square's centre. OpenCV's ellipse element
    is no disc (a single pixel at each tip; the even sizes lopsided), and an opening by it cut
    the corners of small squares deeper than a disc would.

    >>> _disc(4).tolist()
    [[0, 1, 1, 0], [1, 1, 1, 1], [1, 1, 1, 1], [0, 1, 1, 0]]
    """
    d = max(2, int(np.ceil(diameter)))
    y, x = np.mgrid[:d, :d] - (d - 1) / 2
    return (np.hypot(x, y) <= d / 2).astype(np.uint8)
