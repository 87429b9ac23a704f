"""Encounters between ships: the ship domain.

A contract below the stages: the simulation's controllers and COLREGs verdicts and the report
use this one domain.

Ship domain (:func:`in_domain`, UDWA paper section 4.1)
    An ellipse centred on the own ship, its major axis ``7 L`` along her heading and its minor
    axis ``3 L`` across (semi-axes 3.5 L and 1.5 L, ``L`` her length). A target (its reference
    point) is inside when ``(a / 3.5 L)² + (c / 1.5 L)² ≤ 1`` (closed), ``a`` and ``c`` its
    along- and across-heading offsets (:func:`domain_ellipse`).
"""

from __future__ import annotations

import numpy as np

#: UDWA section 4.1: the domain's axes, in ship lengths ("seven times ... thrice ...").
DOMAIN_LENGTH_FACTOR = 7.0
DOMAIN_WIDTH_FACTOR = 3.0


def domain_semi_axes(length) -> tuple:
    """The domain's semi-axes ``(along, across)`` of a ship of ``length``: 3.5 L and 1.5 L.

    >>> domain_semi_axes(10.0)
    (35.0, 15.0)
    """
    return 0.5 * DOMAIN_LENGTH_FACTOR * length, 0.5 * DOMAIN_WIDTH_FACTOR * length


def domain_ellipse(dx, dy, ux, uy, length) -> np.ndarray:
    """The domain's quadratic form ``(a / 3.5 L)² + (c / 1.5 L)²`` (≤ 1 inside) of offsets
    ``(dx, dy)`` (target minus own ship, map metres) in the domain of a ship of ``length``
    heading along the unit vector ``(ux, uy)`` (east, north): ``a`` the offset along it, ``c``
    across; ``dx`` and ``dy`` of one shape, ``ux`` and ``uy`` of one shape, broadcasting.

    >>> domain_ellipse([0.0, 15.0, 0.0, 10.0], [35.0, 0.0, -70.0, 0.0], 0.0, 1.0, 10.0).tolist()
    [1.0, 1.0, 4.0, 0.4444444444444444]
    """
    a, b = domain_semi_axes(np.asarray(length, float))
    along = np.asarray(np.multiply(dx, ux), float)  # in place from here (rollouts: 20 x 500)
    along += np.multiply(dy, uy)
    along /= a
    across = np.asarray(np.multiply(dx, uy), float)
    across -= np.multiply(dy, ux)
    across /= b
    np.square(along, out=along)
    along += np.square(across, out=across)
    return along


def in_domain(own_xy, own_heading, target_xy, length) -> np.ndarray:
    """Whether each target is inside the (closed) 7 L × 3 L domain of the own ship at
    ``own_xy`` on compass ``own_heading`` (degrees); positions carry a trailing axis of 2.

    >>> in_domain((0, 0), 90.0, [(35, 0), (0, 15), (0, 15.01), (0, 35)], 10.0).tolist()
    [True, True, False, False]
    """
    d = np.asarray(target_xy, float) - np.asarray(own_xy, float)
    h = np.radians(np.asarray(own_heading, float))
    return domain_ellipse(d[..., 0], d[..., 1], np.sin(h), np.cos(h), length) <= 1.0
