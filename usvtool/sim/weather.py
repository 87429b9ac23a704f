"""Wind and waves, and the speed they cost a ship: UDWA eq. 5 and Table 2 (paper ``004_*``).

Directions are where the wind or the waves come FROM. Users and files give them in compass
degrees (0 = from the north, 90 = from the east, clockwise); the API below takes and returns
mathematical radians (counter-clockwise from +x = east) of that from-direction, like the
headings of :mod:`usvtool.sim.vessel`: ``wind_from == heading`` is a head wind. Speeds are m/s
(eq. 5 works in knots inside :func:`attainable_speed`), wave heights metres.

A :class:`Weather` gives the :class:`Conditions` at map points: :func:`uniform` everywhere the
same, :func:`read_weather` a field raster (docs/vessel.md says how bands are recognised).

>>> int(beaufort(5.0)), float(wave_height(5.0))  # force 3, 0.6 m (Table 2)
(3, 0.6)
>>> round(float(attainable_speed(5.0, 0.0, 7.0, 0.0, 1.0, 0.0, 20.0)), 4)  # head sea, m/s
4.4345
"""

from __future__ import annotations

import functools
import math
import numbers
import os
from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from usvtool.angles import compass_to_math, wrap_pi
from usvtool.errors import UsvError
from usvtool.wind import read_wind_field

KNOT = 1852.0 / 3600.0  # m/s

# WMO Beaufort scale (WMO-No. 8, Guide to Instruments and Methods of Observation; WMO-No. 558):
# the upper limits of forces 0..11 in m/s (speeds reported to 0.1 m/s; force 12 is >= 32.7).
BEAUFORT_UPPER = (0.2, 1.5, 3.3, 5.4, 7.9, 10.7, 13.8, 17.1, 20.7, 24.4, 28.4, 32.6)
# A continuous speed takes the force of its value rounded to 0.1 m/s: the boundaries lie half-way
# between one force's upper limit and the next one's lower limit.
_BEAUFORT_EDGES = np.array(
    [0.25, 1.55, 3.35, 5.45, 7.95, 10.75, 13.85, 17.15, 20.75, 24.45, 28.45, 32.65]
)
# Wave height (m) by force. Forces 0-4: UDWA Table 2 (its force 4 is "5.5-7.0 m/s", cut at its
# simulation's 7 m/s maximum). Forces 5-12: not in the paper, the WMO "probable height of
# waves" that Table 2 itself follows (0.1, 0.2, 0.6, 1.0 m for forces 1-4).
WAVE_HEIGHTS = (0.0, 0.1, 0.2, 0.6, 1.0, 2.0, 3.0, 4.0, 5.5, 7.0, 9.0, 11.5, 14.0)
_WAVE_HEIGHTS = np.array(WAVE_HEIGHTS)


def beaufort(wind_speed) -> np.ndarray:
    """WMO Beaufort force (0-12) of wind speeds in m/s (finite, >= 0).

    >>> beaufort([0.2, 0.3, 1.5, 1.6, 5.4, 5.5, 7.9, 8.0, 40.0]).tolist()
    [0, 1, 1, 2, 3, 4, 4, 5, 12]
    """
    return np.searchsorted(_BEAUFORT_EDGES, np.asarray(wind_speed, float), side="right")


def wave_height(wind_speed) -> np.ndarray:
    """Wave height (m) raised by a wind (m/s): UDWA Table 2 by Beaufort force (forces above 4
    from the WMO table, see :data:`WAVE_HEIGHTS`).

    >>> wave_height([0.0, 1.0, 2.0, 4.0, 6.0]).tolist()
    [0.0, 0.1, 0.2, 0.6, 1.0]
    """
    return _WAVE_HEIGHTS[beaufort(wind_speed)]


_table_wave_height = wave_height  # for the functions whose wave_height argument hides it


def off_bow(direction_from, heading) -> np.ndarray:
    """The angle (radians, in ``[0, π]``) between where something comes from and the heading:
    0 dead ahead (head wind, head sea), π dead astern (following)."""
    return np.abs(wrap_pi(np.asarray(direction_from, float) - np.asarray(heading, float)))


def attainable_speed(
    v, heading, wind_speed, wind_from, wave_height=None, wave_from=None, displacement=None
) -> np.ndarray:
    """The speed (m/s) a ship making ``v`` m/s in calm water makes in wind and waves: eq. 5.

    ``V_a = V - (1.08 h - 0.126 q h + 2.77e-3 F cos ε)(1 - 2.33e-7 Δ V)`` with ``V, V_a`` in
    knots, ``h`` the wave height (m), ``q`` the angle (radians, 0 to π) between the waves'
    from-direction and the heading, ``F`` the wind speed (m/s), ``ε`` the same angle for the
    wind and ``Δ`` the tonnage (t; the paper says deadweight, :class:`Vessel` ``deadweight``;
    None counts as 0, which changes ``V_a`` by less than 1e-4 for a 20 t boat). So a head sea
    (``q = 0``) costs ``1.08 h`` knots and a following one (``q = π``) ``0.68 h``. The result is
    at least 0, and 0 for ``v <= 0``. Defaults: ``wave_height`` from the wind (:func:`wave_height`),
    ``wave_from`` the wind's. Angles are mathematical radians; all arguments broadcast.
    """
    wind_speed = np.asarray(wind_speed, float)
    h = _table_wave_height(wind_speed) if wave_height is None else wave_height
    h = np.asarray(h, float)
    wave_from = wind_from if wave_from is None else wave_from
    q = off_bow(wave_from, heading)
    eps = off_bow(wind_from, heading)
    dwt = 0.0 if displacement is None else float(displacement)
    knots = np.asarray(v, float) / KNOT
    loss = (1.08 * h - 0.126 * q * h + 2.77e-3 * wind_speed * np.cos(eps)) * (
        1 - 2.33e-7 * dwt * knots
    )
    return np.where(knots > 0, np.maximum(knots - loss, 0.0), 0.0) * KNOT


class Conditions(NamedTuple):
    """Wind and waves at some points: arrays of one shape (m/s, math radians from, m)."""

    wind_speed: np.ndarray
    wind_from: np.ndarray
    wave_height: np.ndarray
    wave_from: np.ndarray


class Weather(ABC):
    """A source of wind and waves over the map."""

    @abstractmethod
    def at(self, x, y) -> Conditions:
        """The conditions at map points ``(x, y)`` (arrays broadcast together)."""

    def attainable_speed(self, v, heading, x, y, displacement=None) -> np.ndarray:
        """:func:`attainable_speed` with the conditions at ``(x, y)``."""
        return attainable_speed(v, heading, *self.at(x, y), displacement)


@dataclass(frozen=True)
class UniformWeather(Weather):
    """The same wind and waves everywhere (SI, math radians; build it with :func:`uniform`)."""

    wind_speed: float
    wind_from: float
    wave_height: float
    wave_from: float

    def at(self, x, y) -> Conditions:
        shape = np.broadcast_shapes(np.shape(x), np.shape(y))
        return Conditions(*(np.full(shape, float(a)) for a in self._values()))

    def _values(self):
        return self.wind_speed, self.wind_from, self.wave_height, self.wave_from


CALM = UniformWeather(0.0, 0.0, 0.0, 0.0)


def uniform(
    wind_speed: float,
    wind_from: float,
    wave_height: float | None = None,
    wave_from: float | None = None,
    where: str = "weather",
) -> UniformWeather:
    """Uniform weather from user values: speeds m/s, directions-from compass degrees.

    Without ``wave_height`` the waves are Table 2's for the wind; without ``wave_from`` they come
    with the wind.

    >>> w = uniform(6.0, 90.0)  # force 4 from the east
    >>> w.wave_height, round(w.wind_from, 9), round(w.wave_from, 9)
    (1.0, 0.0, 0.0)
    """
    _number(where, "wind_speed", wind_speed, nonnegative=True)
    _number(where, "wind_from", wind_from)
    if wave_height is None:
        wave_height = float(_table_wave_height(float(wind_speed)))
    _number(where, "wave_height", wave_height, nonnegative=True)
    if wave_from is None:
        wave_from = wind_from
    _number(where, "wave_from", wave_from)
    return UniformWeather(
        float(wind_speed),
        compass_to_math(wind_from),
        float(wave_height),
        compass_to_math(wave_from),
    )


def _number(where: str, name: str, value, nonnegative: bool = False) -> None:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise UsvError(f"{where}: {name} must be a number, not {value!r}")
    if not math.isfinite(value):
        raise UsvError(f"{where}: {name} must be finite, not {value}")
    if nonnegative and value < 0:
        raise UsvError(f"{where}: {name} must be >= 0, not {value}")


@dataclass(frozen=True, eq=False)
class FieldWeather(Weather):
    """Wind and waves from a raster, bilinear between cell centres (see :func:`read_weather`).

    ``layers`` is ``(k, rows, cols)``: the wind's velocity components ``u`` (east) and ``v``
    (north), m/s, in the direction it blows; then, when the raster has them, the wave height
    (m) and the unit vector (x, y) pointing where the waves come from. Components are
    interpolated, not angles, so directions never wrap wrongly.
    """

    layers: np.ndarray
    transform: object  # affine.Affine: (col, row) -> map metres
    has_wave_height: bool
    has_wave_from: bool
    outside: str = "nearest"  # "nearest": the edge cells' values; "calm": no wind, no waves
    crs: object | None = None

    def at(self, x, y) -> Conditions:
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        values = _bilinear(self.layers, ~self.transform, x, y, self.outside == "calm")
        u, v = values[0], values[1]
        speed = np.hypot(u, v)
        wind_from = np.arctan2(-v, -u)
        k = 2
        if self.has_wave_height:
            h, k = values[k], k + 1
        else:
            h = wave_height(speed)
        wave_from = np.arctan2(values[k + 1], values[k]) if self.has_wave_from else wind_from
        return Conditions(speed, wind_from, h, wave_from)

    @cached_property
    def _compiled(self) -> tuple[np.ndarray, np.ndarray]:
        """The layers and the inverse transform's coefficients as the kernel takes them."""
        return np.ascontiguousarray(self.layers, float), np.array((~self.transform)[:6], float)

    def attainable_speed(self, v, heading, x, y, displacement=None) -> np.ndarray:
        """:func:`attainable_speed` with the conditions at ``(x, y)``, in one compiled pass over
        the points (:mod:`usvtool.sim.weather_kernels`: the same bits as :meth:`at` and eq. 5
        in NumPy). Four floats (the own ship's step) give a NumPy float, through the kernel of one
        point; four contiguous float vectors of one size (a step's rollouts) go to the kernel
        as they are."""
        weather_kernels = _weather_kernels()
        dwt = 0.0 if displacement is None else float(displacement)
        if type(v) is type(heading) is type(x) is type(y) is float:
            return np.float64(weather_kernels.field_attainable_speed_one(
                *self._compiled, x, y, v, heading, *self._flags, dwt, KNOT))  # fmt: skip
        if _vectors(v, heading, x, y):
            return weather_kernels.field_attainable_speed(*self._compiled, x, y, v, heading,
                                                          *self._flags, dwt, KNOT)  # fmt: skip
        v, heading, x, y = np.broadcast_arrays(*(np.asarray(a, float) for a in (v, heading, x, y)))
        flat = [np.ravel(a) for a in (x, y, v, heading)]  # contiguous, copied only if need be
        speeds = weather_kernels.field_attainable_speed(*self._compiled, *flat, *self._flags,
                                                        dwt, KNOT)  # fmt: skip
        return speeds.reshape(v.shape)

    @cached_property
    def _flags(self) -> tuple:
        """The kernel's arguments after the points, up to the displacement: calm outside, the
        layers it has, the wave height table."""
        return (self.outside == "calm", self.has_wave_height, self.has_wave_from,
                _BEAUFORT_EDGES, _WAVE_HEIGHTS)  # fmt: skip


@functools.cache
def _weather_kernels():
    """:mod:`usvtool.sim.weather_kernels`, imported at the first call (numba's import) and then
    at the cost of a cached call, not an import's, every step."""
    from usvtool.sim import weather_kernels

    return weather_kernels


def _vectors(*arrays) -> bool:
    """Every one of ``arrays`` is a contiguous float64 vector, all of one size."""
    size = arrays[0].size if type(arrays[0]) is np.ndarray else -1
    return all(type(a) is np.ndarray and a.dtype == np.float64 and a.ndim == 1
               and a.size == size and a.flags.c_contiguous for a in arrays)  # fmt: skip


def _bilinear(layers: np.ndarray, inverse, x: np.ndarray, y: np.ndarray, calm: bool):
    """Bilinear interpolation of ``layers (k, rows, cols)`` at map points, between cell centres;
    beyond the outermost centres the edge values continue, outside the raster too unless
    ``calm`` (then 0)."""
    _, rows, cols = layers.shape
    a, b, c, d, e, f = inverse[:6]
    col = a * x + b * y + c
    row = d * x + e * y + f
    fc = np.clip(col - 0.5, 0, cols - 1)
    fr = np.clip(row - 0.5, 0, rows - 1)
    c0 = np.minimum(np.floor(fc).astype(np.intp), max(cols - 2, 0))
    r0 = np.minimum(np.floor(fr).astype(np.intp), max(rows - 2, 0))
    tc, tr = fc - c0, fr - r0
    c1, r1 = np.minimum(c0 + 1, cols - 1), np.minimum(r0 + 1, rows - 1)
    top = layers[:, r0, c0] * (1 - tc) + layers[:, r0, c1] * tc
    bottom = layers[:, r1, c0] * (1 - tc) + layers[:, r1, c1] * tc
    out = top * (1 - tr) + bottom * tr
    if calm:
        inside = (col >= 0) & (col <= cols) & (row >= 0) & (row <= rows)
        out = np.where(inside, out, 0.0)
    return out


def read_weather(
    path: str | os.PathLike,
    bands: Sequence[str] | None = None,
    outside: str = "nearest",
    crs=None,
) -> FieldWeather:
    """The wind (and wave) field raster ``path`` (:func:`usvtool.wind.read_wind_field`: bands,
    units, CRS rules), interpolated as :class:`FieldWeather`; ``outside``: ``"nearest"``
    (default) or ``"calm"``. Errors are one line naming the file."""
    if outside not in ("nearest", "calm"):
        raise UsvError(f"{path}: outside must be 'nearest' or 'calm', not {outside!r}")
    field = read_wind_field(path, bands, crs)
    return FieldWeather(field.layers, field.transform, field.has_wave_height,
                        field.has_wave_from, outside, field.crs)  # fmt: skip
