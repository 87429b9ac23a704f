"""Exact collision checks of many straight segments against the blocked cells of a grid.

Coordinates are continuous cell coordinates ``(x, y) = (col, row)``: cell ``(r, c)`` is the closed
square ``[c, c+1] × [r, r+1]`` (see :meth:`usvtool.grid.Grid.to_cell_coords`).

Definition (what "collides" means everywhere in usvtool)
    A segment collides when it touches a blocked cell (obstacle or margin): it meets the cell's
    closed square, edges and corners included, so a segment that only grazes a corner point, or
    runs along a cell edge, collides. To be immune to floating-point rounding the squares are
    enlarged by ``EPS`` = 1e-9 cell on every side (a segment passing within 1e-9 cell of a
    blocked square collides). Cells outside the grid are not obstacles.

The check (:meth:`SegmentChecker.check`) is exact under that definition and fast:

1. Clearance filter. ``R(p)``, looked up in the cell holding ``p``, is a lower bound on the
   distance from ``p`` to every blocked square: for ``p`` in cell ``c`` and a blocked square of
   centre ``b``, ``dist(p, B) ≥ |p - b| - √2/2 ≥ |c - b| - √2``, so ``R = EDT(c) - √2`` (clipped at
   0) with ``EDT`` the Euclidean distance transform of the cell centres. Each segment is sampled at
   ``n`` points ``p_k`` spaced ``s`` apart. If a sample lies in a blocked cell, the segment
   collides. An interval ``[p_k, p_{k+1}]`` with ``R_k + R_{k+1} > s + 1e-6`` is free: any point
   ``q`` on it has ``|q - p_k| + |q - p_{k+1}| = s``, so ``|q - p_k| < R_k - 5e-7`` or
   ``|q - p_{k+1}| < R_{k+1} - 5e-7``, and ``q`` is farther than 5e-7 > √2·EPS from every blocked
   square.
2. Exact traversal of the remaining intervals (near obstacles only). An interval is cut into
   column strips; in column ``c`` it spans ``y_lo … y_hi`` (interpolated at the enlarged strip
   edges ``x = c - EPS`` and ``c + 1 + EPS``, clipped to its ends) and touches exactly the cells
   of rows ``ceil(y_lo - 1 - EPS) … floor(y_hi + EPS)`` of that column: its supercover, corners
   included. Whether any of them is blocked is one difference of running counts down the
   column, so an interval costs one step per column it crosses, vectorised over all intervals.

The result is the exact answer for the definition above, with no sampling step that can step
over a one-cell obstacle: sampling only ever proves freedom (step 1) or collision (a sample in a
blocked cell), everything else is decided cell by cell.
"""

from __future__ import annotations

import numpy as np

EPS = 1e-9
_MARGIN = 1e-6  # extra clearance the filter demands, >> √2·EPS
_SQRT2 = float(np.sqrt(2.0))


class SegmentChecker:
    """Collision checks of segments against a boolean ``blocked`` mask (row 0 = y 0).

    Segments must lie inside the grid's extent ``[0, width] × [0, height]``.

    >>> blocked = np.zeros((3, 3), bool); blocked[1, 1] = True
    >>> chk = SegmentChecker(blocked)
    >>> a = np.array([[0.5, 0.5], [0.5, 0.5], [0.5, 0.5]])
    >>> b = np.array([[2.5, 0.5], [1.0, 1.0], [2.5, 0.9]])  # clear, corner touch, clear
    >>> chk.collides(a, b).tolist()
    [False, True, False]
    """

    def __init__(self, blocked: np.ndarray, samples: int | None = None):
        blocked = np.asarray(blocked, bool)
        self.height, self.width = h, w = blocked.shape
        # samples along each segment: about one per 20 cells of the grid's size, 4 to 24
        self.samples = samples or int(np.clip(np.ceil(max(h, w) / 20), 4, 24))
        samples = self.samples
        t = np.linspace(0.0, 1.0, samples)
        self._basis = np.vstack([1.0 - t, t])
        self._ones = np.ones(samples)
        if blocked.any():
            from scipy.ndimage import distance_transform_edt

            clear = np.maximum(distance_transform_edt(~blocked) - _SQRT2, 0.0)
        else:
            clear = np.full(blocked.shape, np.inf)
        # one extra row and column (copies of the last ones) hold the points on the far edges
        clear = np.where(blocked, -1.0, clear)
        self._clear = np.pad(clear, ((0, 1), (0, 1)), mode="edge").ravel()
        # running counts of blocked cells down each column, padded so that rows -1 … h and
        # columns -1 … w (outside the grid, never blocked) need no bounds checks:
        # _prefix[i, j] = blocked cells of column j - 1 in rows < i - 1
        down = np.cumsum(blocked, axis=0)
        down = np.vstack([np.zeros((2, w), np.int64), down, down[-1:]])
        self._prefix = np.pad(down, ((0, 0), (1, 1))).ravel()

    def collides(self, a, b) -> np.ndarray:
        """Whether each segment ``a[i] → b[i]`` (arrays ``(k, 2)``) touches a blocked cell."""
        return self.check(a, b)[0]

    def check(self, a, b) -> tuple[np.ndarray, np.ndarray]:
        """``(collides, inside)`` for each segment ``a[i] → b[i]``.

        ``collides`` is exact (module docstring); ``inside`` estimates the length of the segment
        inside blocked cells (the share of samples in blocked cells times the length): a guide
        for penalties, positive only for colliding segments.
        """
        return self.check_unchecked(*self._segments(a, b))

    def check_unchecked(
        self, a: np.ndarray, b: np.ndarray, length: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`check` for float ``(k, 2)`` arrays known to lie inside the grid (no checks);
        ``length`` may give the segments' lengths when the caller has them."""
        k = len(a)
        if length is None:
            length = np.hypot(b[:, 0] - a[:, 0], b[:, 1] - a[:, 1])
        # samples (1 - t) a + t b: x of the k segments then y, as one small matrix product
        xy = np.stack([a.T, b.T], axis=-1).reshape(2 * k, 2) @ self._basis
        x, y = xy[:k], xy[k:]
        cell = y.astype(np.intp)  # truncation: coordinates are >= 0 (up to rounding)
        cell *= self.width + 1
        cell += x.astype(np.intp)
        r = self._clear.take(cell)
        n_in = (r < 0).astype(float) @ self._ones
        hit = n_in > 0
        unsure = r[:, :-1] + r[:, 1:] <= (length / (self.samples - 1) + _MARGIN)[:, None]
        unsure[hit] = False
        i, j = np.divmod(np.flatnonzero(unsure), self.samples - 1)
        if i.size:
            hit[i[self._traverse(x[i, j], y[i, j], x[i, j + 1], y[i, j + 1])]] = True
        return hit, n_in * length / self.samples

    def touches(self, a, b) -> np.ndarray:
        """Exact strip traversal of whole segments, without the filter (step 2 alone)."""
        a, b = self._segments(a, b)
        return self._traverse(a[:, 0], a[:, 1], b[:, 0], b[:, 1])

    def _segments(self, a, b) -> tuple[np.ndarray, np.ndarray]:
        a = np.asarray(a, float).reshape(-1, 2)
        b = np.asarray(b, float).reshape(-1, 2)
        ends = np.concatenate([a, b])
        extent = np.array([self.width, self.height]) + 1e-9
        if ends.size and (ends.min() < -1e-9 or (ends.max(axis=0) > extent).any()):
            raise ValueError("segments must lie inside the grid extent")
        return a, b

    def _traverse(self, x0, y0, x1, y1) -> np.ndarray:
        """Whether each segment touches a blocked cell, column strip by column strip.

        Segments are oriented west to east, with slope ``k = dy/dx`` (0 when ``dx = 0``). In the
        strip of column ``c`` a segment spans ``y`` from ``y0 + k·max(c - EPS - x0, 0)`` to
        ``y1 - k·max(x1 - c - 1 - EPS, 0)``: its enlarged strip clipped to its ends. A north-south
        segment (``k = 0``) thus spans all of ``[y0, y1]``.
        """
        back = x1 < x0
        x0, y0, x1, y1 = np.where(back, (x1, y1, x0, y0), (x0, y0, x1, y1))
        dx = x1 - x0
        slope = np.divide(y1 - y0, dx, out=np.zeros_like(dx), where=dx > 0)
        first = np.ceil(x0 - (1 + EPS))  # columns first … floor(x1 + EPS), -1 … width
        counts = (np.floor(x1 + EPS) - first + 1).astype(np.intp)
        starts = np.cumsum(counts) - counts
        shift = first - starts  # column c = j + shift for the j-th strip overall
        stride = self.width + 2
        per = np.stack([y0, y1, slope, shift - x0, dx - (1 + EPS), shift + (1 + stride)])
        y0, y1, slope, to_c, span, base = np.repeat(per, counts, axis=1)
        j = np.arange(y0.size)
        cx = j + to_c  # c - x0
        ya = y0 + slope * np.maximum(cx - EPS, 0.0)
        yb = y1 - slope * np.maximum(span - cx, 0.0)
        r0 = np.ceil(np.minimum(ya, yb) - (1 + EPS))  # rows r0 … r1, -1 … height
        r1 = np.floor(np.maximum(ya, yb) + EPS)
        base += j  # c + 1 + stride
        above = self._prefix.take((r0 * stride + base).astype(np.intp))
        through = self._prefix.take(((r1 + 1) * stride + base).astype(np.intp))
        return np.logical_or.reduceat(through > above, starts)
