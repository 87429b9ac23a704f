"""The encounter contract: the ship domain, by hand and against a rotation done in the test."""

from __future__ import annotations

import math

import numpy as np

from usvtool import encounter

L = 10.0  # semi-axes 35 m along, 15 m across


def test_domain_semi_axes():
    assert encounter.domain_semi_axes(L) == (35.0, 15.0)
    assert encounter.domain_semi_axes(np.array([2.0, 4.0]))[1].tolist() == [3.0, 6.0]


def test_domain_ellipse_is_exactly_one_at_the_axis_tips():
    # heading north, then east: the four tips of the ellipse are on its edge, a hair out is out
    for ux, uy in ((0.0, 1.0), (1.0, 0.0)):
        tips = np.array([(35 * ux, 35 * uy), (-35 * ux, -35 * uy), (15 * uy, -15 * ux),
                         (-15 * uy, 15 * ux)])  # fmt: skip
        assert encounter.domain_ellipse(tips[:, 0], tips[:, 1], ux, uy, L).tolist() == [1.0] * 4
        out = encounter.domain_ellipse(tips[:, 0] * 1.001, tips[:, 1] * 1.001, ux, uy, L)
        assert (out > 1).all()


def test_domain_ellipse_against_a_rotation():
    rng = np.random.default_rng(3)
    d = rng.uniform(-60, 60, (200, 2))
    heading = rng.uniform(0, 360, 200)  # compass
    h = np.radians(heading)
    # rotate each offset into the ship's frame: along her heading (sin h, cos h), across to
    # starboard (cos h, -sin h)
    along = d[:, 0] * np.sin(h) + d[:, 1] * np.cos(h)
    across = d[:, 0] * np.cos(h) - d[:, 1] * np.sin(h)
    want = (along / 35) ** 2 + (across / 15) ** 2
    got = encounter.domain_ellipse(d[:, 0], d[:, 1], np.sin(h), np.cos(h), L)
    np.testing.assert_allclose(got, want, rtol=1e-12)
    assert (encounter.in_domain((0.0, 0.0), heading, d, L) == (want <= 1)).all()


def test_in_domain_of_one_target_and_per_ship_lengths():
    assert bool(encounter.in_domain((0, 0), 0.0, (3, 4), L))
    # a point 20 m ahead: inside a 10 m ship's domain (35 m), outside a 5 m one's (17.5 m)
    ahead = (20 * math.sin(math.radians(30)), 20 * math.cos(math.radians(30)))
    assert encounter.in_domain((0, 0), 30.0, [ahead, ahead], np.array([10.0, 5.0])).tolist() == [
        True,
        False,
    ]
