"""Decimation of a ship's track to a stated error bound, for the HTML player.

Ramer-Douglas-Peucker in space-time (the "top-down time-ratio" form of Meratnia and de By,
2004): a track of samples ``(t, x, y, heading)`` keeps its first and last samples; between two
kept samples the position is the linear interpolation in time and the heading the interpolation
along the shorter arc; the sample whose synchronised error is largest (its distance to where
the interpolation puts the ship at its own time, over ``tol_m``, or its heading's difference
over ``tol_deg``, whichever ratio is larger) is kept when that ratio exceeds 1, and both halves
are split again. So at every sample time of the trace, the decimated track is within ``tol_m``
metres of the recorded position and within ``tol_deg`` degrees of the recorded heading, a bound
checked against the full trace (tests/report/test_animate.py).

>>> t = np.arange(5.0)
>>> keep(t, t * 2.0, np.zeros(5), np.zeros(5), 0.1, 1.0).tolist()  # a straight run: its ends
[0, 4]
>>> keep(t, t, np.array([0, 0, 1.0, 0, 0]), np.zeros(5), 0.1, 1.0).tolist()
[0, 1, 2, 3, 4]
"""

from __future__ import annotations

import numpy as np


def keep(t, x, y, heading, tol_m: float, tol_deg: float) -> np.ndarray:
    """Indices (sorted) of the samples kept (module docstring); ``t`` strictly increasing."""
    t, x, y, h = (np.asarray(a, float) for a in (t, x, y, heading))
    n = t.size
    if n <= 2:
        return np.arange(n)
    kept = np.zeros(n, bool)
    kept[[0, n - 1]] = True
    stack = [(0, n - 1)]
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            continue
        f = (t[i + 1:j] - t[i]) / (t[j] - t[i])
        ex = x[i + 1:j] - (x[i] + f * (x[j] - x[i]))
        ey = y[i + 1:j] - (y[i] + f * (y[j] - y[i]))
        ratio = np.hypot(ex, ey) / tol_m
        turn = _wrap180(h[j] - h[i])
        eh = np.abs(_wrap180(h[i + 1:j] - (h[i] + f * turn))) / tol_deg
        np.maximum(ratio, eh, out=ratio)
        m = int(np.argmax(ratio))
        if ratio[m] > 1.0:
            m += i + 1
            kept[m] = True
            stack.append((i, m))
            stack.append((m, j))
    return np.flatnonzero(kept)


def interpolate(tk, xk, yk, hk, t):
    """The decimated track (key samples ``tk, xk, yk, hk``) at times ``t``: positions linear in
    time, the heading along the shorter arc (compass degrees in [0, 360)), as the player does."""
    tk, xk, yk, hk, t = (np.asarray(a, float) for a in (tk, xk, yk, hk, t))
    if tk.size == 1:
        shape = np.shape(t)
        return np.full(shape, xk[0]), np.full(shape, yk[0]), np.full(shape, hk[0] % 360.0)
    i = np.clip(np.searchsorted(tk, t, side="right") - 1, 0, tk.size - 2)
    f = np.clip((t - tk[i]) / (tk[i + 1] - tk[i]), 0.0, 1.0)
    x = xk[i] + f * (xk[i + 1] - xk[i])
    y = yk[i] + f * (yk[i + 1] - yk[i])
    h = (hk[i] + f * _wrap180(hk[i + 1] - hk[i])) % 360.0
    return x, y, h


def _wrap180(a):
    return (np.asarray(a, float) + 180.0) % 360.0 - 180.0
