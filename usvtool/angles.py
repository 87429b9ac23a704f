"""Angles: compass degrees and mathematical radians, their conversions and their wrapping.

A contract below the stages: every stage that converts or wraps an angle does it here.

- Compass degrees: files, the command line and the COLREGs classifier (0 = north, 90 = east,
  clockwise; the maritime convention). A heading or bearing is wrapped to ``[0, 360)``
  (:func:`wrap360`), a signed difference to ``(-180, 180]`` (:func:`wrap180`).
- Mathematical radians: the vessel model and the controllers (counter-clockwise from +x =
  east). A heading is wrapped to ``[-pi, pi)`` (:func:`wrap_pi`).

:func:`compass_to_math` and :func:`math_to_compass` are the one place where the two meet. Every
function takes scalars or arrays; the compass conversions and :func:`wrap180` return a Python
float for a scalar, the others a NumPy array (0-d for a scalar).
"""

from __future__ import annotations

import math

import numpy as np


def wrap360(deg) -> np.ndarray:
    """Degrees in ``[0, 360)``; exact for angles already there.

    >>> wrap360([-90.0, 360.0, 725.0, -1e-20]).tolist()
    [270.0, 0.0, 5.0, 0.0]
    """
    a = np.mod(np.asarray(deg, float), 360.0)
    return np.where(a >= 360.0, a - 360.0, a)  # -1e-20 % 360 rounds to 360


def wrap180(deg):
    """Degrees in ``(-180, 180]``; never a negative zero.

    >>> wrap180(190.0), wrap180(-180.0), wrap180(180.0), wrap180(-190.0), wrap180(720.0)
    (-170.0, 180.0, 180.0, 170.0, 0.0)
    """
    a = np.asarray(deg, float)
    out = 180.0 - np.mod(180.0 - a, 360.0)
    out = np.where(out <= -180.0, out + 360.0, out)  # mod may round up to 360
    return _out(out + 0.0)


def wrap_pi(rad) -> np.ndarray:
    """Radians in ``[-pi, pi)``.

    >>> import math
    >>> round(float(wrap_pi(3 * math.pi / 2)), 12) == round(-math.pi / 2, 12)
    True
    >>> float(wrap_pi(math.pi)) == -math.pi
    True
    """
    return (np.asarray(rad, float) + np.pi) % (2 * np.pi) - np.pi


def compass_to_math(deg):
    """Compass degrees (0 = north, clockwise) to mathematical radians in ``(-pi, pi]``
    (counter-clockwise from +x = east). North is pi/2, east 0, south -pi/2 and west pi (not -pi).

    Computed as ``radians(wrap180(90 - deg))``: whole degrees give exact multiples of pi/180.

    >>> import math
    >>> [compass_to_math(d) / math.pi for d in (0.0, 90.0, 180.0, 270.0, 360.0, 45.0)]
    [0.5, 0.0, -0.5, 1.0, 0.5, 0.25]
    >>> compass_to_math(np.array([0.0, 90.0, 180.0, 270.0])).tolist() == [
    ...     math.pi / 2, 0.0, -math.pi / 2, math.pi]
    True
    """
    return _out(np.radians(wrap180(90.0 - np.asarray(deg, float))))


def math_to_compass(rad):
    """Mathematical radians (counter-clockwise from east) to compass degrees in ``[0, 360)``.

    >>> import math
    >>> [math_to_compass(r) for r in (math.pi / 2, 0.0, -math.pi / 2, math.pi, -math.pi)]
    [0.0, 90.0, 180.0, 270.0, 270.0]
    >>> math_to_compass(np.array([3 * math.pi / 2, 2 * math.pi + 1e-12, math.pi / 4])).round(9)
    array([180.,  90.,  45.])
    """
    if isinstance(rad, float):  # one heading, as a run's every step converts: the same
        deg = (90.0 - math.degrees(rad)) % 360.0  # operations in floats (5 us as arrays)
        return (0.0 if deg >= 360.0 else deg) + 0.0
    deg = np.mod(90.0 - np.degrees(np.asarray(rad, float)), 360.0)
    deg = np.where(deg >= 360.0, 0.0, deg)  # mod of a tiny negative rounds to 360
    return _out(deg + 0.0)


def _out(a: np.ndarray):
    """A 0-d result as a Python float, anything else as the array."""
    return float(a) if np.ndim(a) == 0 else a
