"""Compiled kernel of the weather lookup (:mod:`usvtool.sim.weather`), with numba.

The velocity critic asks a wind field for the speed every rollout makes good at its end (UDWA
eq. 5 on the conditions interpolated there): some 460 points a control step, where the NumPy
expressions made some 60 small temporaries. :func:`field_attainable_speed` runs them point by
point, repeating each expression operation by operation (the same products, sums, comparisons
and libm calls in the same order, no fused multiply-add: numba contracts none without
``fastmath``), so its speeds are the same bits as NumPy's (tests/sim/test_weather_kernels.py
compares them), in the style of :mod:`usvtool.sim.rollout_kernels`.

Each kernel's signature is compiled, or loaded from numba's cache in ``__pycache__``, at its first
call (:func:`usvtool.lazy_kernels.declared`), not at import. Imported lazily, by
:class:`usvtool.sim.weather.FieldWeather` when it is first asked for speeds, so that reading a
scenario does not import numba."""

from __future__ import annotations

import math

import numpy as np
from numba import types as nt

from usvtool.lazy_kernels import declared

_F = nt.float64
_OPTIONS = {"cache": True, "nogil": True}


@declared(_F(_F), inline="always", **_OPTIONS)
def _off_bow(delta) -> float:
    """:func:`usvtool.sim.weather.off_bow` of ``from - heading``: ``|wrap_pi(delta)|``, as
    :func:`usvtool.angles.wrap_pi` computes it (Python's and NumPy's float ``%`` agree), the
    floor modulo only outside ``(-2 pi, 2 pi)`` and at zero: inside it is ``a`` for a positive
    ``a`` and ``a + 2 pi`` for a negative one, exactly (``fmod`` is exact there)."""
    a = delta + np.pi
    b = 2 * np.pi
    if 0.0 < a < b:
        wrapped = a
    elif -b < a < 0.0:
        wrapped = a + b
    else:
        wrapped = a % b
    return abs(wrapped - np.pi)


_FIELD = (_F[:, :, ::1], _F[::1])  # the layers and the inverse transform's coefficients
_POINT = (_F, _F, _F, _F)  # x, y, v, heading
_REST = (nt.boolean, nt.boolean, nt.boolean, _F[::1], _F[::1], _F, _F)  # flags, tables, dwt, knot


@declared(_F(*_FIELD, *_POINT, *_REST, _F[::1]), inline="always", **_OPTIONS)
def _speed_at(layers, inverse, x, y, v, heading, calm, has_wave_height, has_wave_from, edges,
              heights, dwt, knot, values) -> float:  # fmt: skip
    """:func:`field_attainable_speed` of one point (``values``: scratch of one value per
    layer)."""
    _, rows, cols = layers.shape
    a, b, c, d, e, f = inverse[0], inverse[1], inverse[2], inverse[3], inverse[4], inverse[5]
    c_last, r_last = max(cols - 2, 0), max(rows - 2, 0)
    col = a * x + b * y + c
    row = d * x + e * y + f
    fc = min(max(col - 0.5, 0.0), float(cols - 1))
    fr = min(max(row - 0.5, 0.0), float(rows - 1))
    c0 = min(int(math.floor(fc)), c_last)
    r0 = min(int(math.floor(fr)), r_last)
    tc, tr = fc - c0, fr - r0
    c1, r1 = min(c0 + 1, cols - 1), min(r0 + 1, rows - 1)
    inside = (col >= 0) & (col <= cols) & (row >= 0) & (row <= rows)
    for k in range(layers.shape[0]):
        top = layers[k, r0, c0] * (1 - tc) + layers[k, r0, c1] * tc
        bottom = layers[k, r1, c0] * (1 - tc) + layers[k, r1, c1] * tc
        values[k] = top * (1 - tr) + bottom * tr
        if calm and not inside:
            values[k] = 0.0
    u, w = values[0], values[1]
    speed = np.hypot(u, w)
    wind_from = np.arctan2(-w, -u)
    k = 2
    if has_wave_height:
        h, k = values[k], k + 1
    else:
        force = 0
        while force < edges.size and edges[force] <= speed:  # searchsorted, side="right"
            force += 1
        h = heights[force]
    wave_from = np.arctan2(values[k + 1], values[k]) if has_wave_from else wind_from
    eps = _off_bow(wind_from - heading)
    q = _off_bow(wave_from - heading) if has_wave_from else eps
    knots = v / knot
    loss = (1.08 * h - 0.126 * q * h + 2.77e-3 * speed * np.cos(eps)) * (
        1 - 2.33e-7 * dwt * knots
    )
    made = knots - loss
    return ((made if made >= 0.0 else 0.0) if knots > 0 else 0.0) * knot  # np.maximum


@declared(_F[::1](*_FIELD, _F[::1], _F[::1], _F[::1], _F[::1], *_REST), **_OPTIONS)
def field_attainable_speed(layers, inverse, x, y, v, heading, calm, has_wave_height,
                           has_wave_from, edges, heights, dwt, knot) -> np.ndarray:  # fmt: skip
    """:meth:`usvtool.sim.weather.FieldWeather.attainable_speed` at points ``(x, y)``: the
    bilinear conditions of ``layers (k, rows, cols)`` (``inverse``: the map-to-(col, row)
    affine's six coefficients, ``calm``: 0 outside the raster), the wave height by Beaufort
    force (``edges``, ``heights``: :data:`usvtool.sim.weather.WAVE_HEIGHTS`) unless the layers
    have it, then eq. 5 for speeds ``v`` on headings ``heading`` (``dwt`` t, ``knot`` m/s)."""
    out = np.empty(x.size)
    values = np.empty(layers.shape[0])
    for n in range(x.size):
        out[n] = _speed_at(layers, inverse, x[n], y[n], v[n], heading[n], calm, has_wave_height,
                           has_wave_from, edges, heights, dwt, knot, values)  # fmt: skip
    return out


@declared(_F(*_FIELD, *_POINT, *_REST), **_OPTIONS)
def field_attainable_speed_one(layers, inverse, x, y, v, heading, calm, has_wave_height,
                               has_wave_from, edges, heights, dwt, knot) -> float:  # fmt: skip
    """:func:`field_attainable_speed` of one point, in floats (the own ship's step of a run:
    no arrays to make and box)."""
    values = np.empty(layers.shape[0])
    return _speed_at(layers, inverse, x, y, v, heading, calm, has_wave_height, has_wave_from,
                     edges, heights, dwt, knot, values)  # fmt: skip
