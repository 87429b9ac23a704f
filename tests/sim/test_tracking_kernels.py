"""The tracker's compiled step (usvtool/sim/tracking_kernels.py) against the NumPy reference it
stands for: :func:`usvtool.encounter.assess` bit for bit (classes, bearings, ranges, CPA, signed
zeros included) on seeded random geometries and on geometries built to sit exactly on the
classifier's borders (the stern sectors' 112.5 and 247.5 degrees, head-on's 12 and 348, dead
ahead, no relative motion, a target moving neither closer nor away); and the latch and the most
urgent target against :func:`usvtool.sim.tracking.latch_series` and ``np.argmin``."""

import itertools

import numpy as np
import pytest

from usvtool import encounter as enc
from usvtool.sim import tracking
from usvtool.sim import tracking_kernels as kernels

from . import libm

FIELDS = enc.Situation._fields


def compiled(own_xy, own_heading, own_speed, target_xy, target_heading, target_speed):
    """The kernel's :class:`~usvtool.encounter.Situation` of one own ship and ``k`` targets."""
    k = len(target_xy)
    cls, out = np.empty(k, np.int8), np.empty((5, k))
    kernels.assess(float(own_xy[0]), float(own_xy[1]), float(own_heading), float(own_speed),
                   np.ascontiguousarray(target_xy, float), np.ascontiguousarray(target_heading,
                   float), np.ascontiguousarray(target_speed, float), cls, out)  # fmt: skip
    return enc.Situation(cls, *out)


def assert_same_bits(got: enc.Situation, want: enc.Situation) -> None:
    """Every field the same values of the same type: the classes exactly, the floats bit for
    bit (-0.0 is not 0.0) where NumPy's math is the C library's, else within a few ulps
    (tests/sim/libm.py)."""
    assert got.cls.dtype == want.cls.dtype == np.int8
    assert np.array_equal(got.cls, want.cls), np.flatnonzero(got.cls != want.cls)
    for name in FIELDS[1:]:
        libm.assert_close_bits(getattr(got, name), getattr(want, name), name)


def test_random_geometries_give_the_reference_bits():
    rng = np.random.default_rng(24)
    seen = np.zeros(6, int)
    for _ in range(2000):  # 2000 own ships x 8 targets
        k = 8
        own = rng.uniform(-1e3, 1e3, 2)
        h, s = rng.uniform(0, 360), rng.choice([0.0, rng.uniform(0, 12)])
        txy = own + rng.uniform(-600, 600, (k, 2))
        th, ts = rng.uniform(0, 360, k), rng.uniform(0, 12, k)
        ts[rng.random(k) < 0.1] = 0.0
        want = enc.assess(own, h, s, txy, th, ts)
        got = compiled(own, h, s, txy, th, ts)
        assert_same_bits(got, want)
        seen += np.bincount(want.cls, minlength=6)
    assert (seen > 50).all(), seen  # every class, many times (head-on the rarest: 75)


def test_border_geometries_give_the_reference_bits():
    """Targets due north, east, south, west and north-east of the own ship (bearings 0, 90, 180,
    270, 45 exactly), own and target headings on and next to the borders: ``β = 360 - h_o`` and
    ``α`` land exactly on 112.5, 247.5, 12, 348, 0 and one ulp either side."""
    borders = [0.0, 6.0, 12.0, 112.5, 247.5, 348.0, 354.0, 90.0, 180.0, 270.0, 45.0, 135.0]
    headings = sorted({v for b in borders
                       for v in (b, np.nextafter(b, -1.0) % 360.0, np.nextafter(b, 400.0), b + 0.5)}
                      )  # fmt: skip
    directions = [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0), (1.0, 1.0)]
    speeds = [0.0, 1e-10, 2.0, 5.0]
    targets = [(r * dx, r * dy, th, ts) for (dx, dy), r, th, ts in
               itertools.product(directions, (1.0, 250.0), headings, speeds)]  # fmt: skip
    txy = np.array([t[:2] for t in targets])
    th, ts = np.array([t[2] for t in targets]), np.array([t[3] for t in targets])
    counts = np.zeros(6, int)
    on_border = 0
    for h, s in itertools.product(headings, (0.0, 2.0, 5.0)):
        want = enc.assess((0.0, 0.0), h, s, txy, th, ts)
        assert_same_bits(compiled((0.0, 0.0), h, s, txy, th, ts), want)
        counts += np.bincount(want.cls, minlength=6)
        on_border += np.isin(want.beta, (112.5, 247.5, 12.0, 348.0)).sum()
        on_border += np.isin(want.alpha, (112.5, 247.5, 12.0, 348.0)).sum()
    assert (counts > 100).all(), counts
    assert on_border > 10_000  # the borders themselves are hit, not only their neighbours


def test_the_contract_examples():
    # encounter.py's docstring: head-on, give-way, stand-on, overtaking
    got = compiled((0.0, 0.0), 0.0, 4.0, [(0.0, 300.0), (70.0, 80.0), (-80.0, 80.0), (0.0, 90.0)],
                   [180.0, 270.0, 90.0, 0.0], [3.0, 4.0, 4.0, 2.0])  # fmt: skip
    assert got.cls.tolist() == [enc.HEAD_ON, enc.CROSSING_GIVE_WAY, enc.CROSSING_STAND_ON,
                                enc.OVERTAKING]  # fmt: skip
    # classify_angles' docstring: the borders 12 (head-on), 112.5 (overtaking), 247.5 (overtaken)
    codes = [kernels.classify_angles(b, a, True) for b, a in
             ((12.0, 348.0), (12.5, 350.0), (0.0, 112.5), (247.5, 0.0), (0.0, 0.0))]  # fmt: skip
    assert codes == [enc.HEAD_ON, enc.CROSSING_GIVE_WAY, enc.OVERTAKING, enc.OVERTAKEN,
                     enc.HEAD_ON]  # fmt: skip
    assert kernels.classify_angles(0.0, 0.0, False) == enc.NONE
    # the stern sector's border is overtaking, one ulp inside the beam is not
    assert kernels.classify_angles(90.0, np.nextafter(112.5, 0.0), True) == enc.CROSSING_GIVE_WAY
    # wrapped: -1e-20 rounds to 360 under the modulo, and wraps to 0 (dead ahead)
    assert kernels.classify_angles(-1e-20, -0.0, True) == enc.HEAD_ON


def run_series(rng, n: int, k: int):
    """A seeded run: the own ship and ``k`` targets on straight courses through a common area,
    sampled every second: (own xy (n, 2), heading, speed, target xy (n, k, 2), headings (k,),
    speeds (k,))."""
    t = np.arange(n, dtype=float)[:, None]
    own_h, own_v = rng.uniform(0, 360), rng.uniform(1, 6)
    rad = np.radians(own_h)
    own = np.hstack([own_v * np.sin(rad) * t, own_v * np.cos(rad) * t])
    th, tv = rng.uniform(0, 360, k), rng.uniform(0.5, 6, k)
    meet = rng.uniform(0.3, 0.7, k) * n  # each passes the own track near its step `meet`
    at = own[np.minimum(meet.astype(int), n - 1)] + rng.normal(0, 40, (k, 2))
    vel = enc.velocity(th, tv)
    txy = at[None] + vel[None] * (t - meet)[..., None]
    return own, own_h, own_v, txy, th, tv


@pytest.mark.parametrize("seed", range(4))
def test_the_tracker_step_by_step_equals_the_vectorised_reference(seed):
    """EncounterTracker.update on each step (the kernels) against assess over the whole run and
    latch_series (NumPy): the same situations, latched codes, onset times and most urgent
    target at every step."""
    rng = np.random.default_rng(seed)
    n, k, risk = 300, 6, 35.0
    own, h, v, txy, th, tv = run_series(rng, n, k)
    ref = enc.assess(own[:, None], h, v, txy, th[None], tv[None])  # (n, k) arrays
    want = tracking.latch_series(ref.cls, ref.dcpa, ref.tcpa, ref.range, risk)
    tr = tracking.EncounterTracker(k, risk_distance=risk)
    onsets = 0
    for i in range(n):
        s = tr.update(float(i), own[i], h, v, txy[i], th, tv)
        assert_same_bits(s, enc.Situation(*(f[i] for f in ref)))
        assert np.array_equal(tr.latched, want[i])
        started = (want[i] != enc.NONE) & ((want[i - 1] == enc.NONE) if i else True)
        onsets += started.sum()
        for j in np.flatnonzero(started):
            assert tr.onset_t[j] == i
        assert np.isnan(tr.onset_t[want[i] == enc.NONE]).all()
        urgent = (want[i] != enc.NONE) & (ref.tcpa[i] > 0)
        expected = int(np.argmin(np.where(urgent, ref.tcpa[i], np.inf))) if urgent.any() else None
        assert tr.most_urgent() == expected
    assert onsets >= 2


def test_most_urgent_is_numpys_argmin_with_ties_and_infinities():
    rng = np.random.default_rng(5)
    for _ in range(3000):
        k = int(rng.integers(0, 6))
        latched = rng.integers(0, 3, k).astype(np.int8)
        tcpa = rng.choice([-1.0, 0.0, 2.0, 3.0, np.inf, np.nan], k)
        urgent = (latched != enc.NONE) & (tcpa > 0)
        want = int(np.argmin(np.where(urgent, tcpa, np.inf))) if urgent.any() else -1
        assert kernels.most_urgent(latched, tcpa) == want


def test_scalar_and_per_target_arguments():
    """Distances and the targets' headings and speeds: one for all, or one per target; read-only
    and non-contiguous arrays are taken too (copied for the kernels)."""
    tr = tracking.EncounterTracker(2, risk_distance=35.0, release_distance=[np.inf, 500.0])
    heading = np.array([180.0, 0.0, 270.0])[::2]  # not contiguous: 180, 270
    speed = np.broadcast_to(3.0, (2,))  # read-only
    s = tr.update(0.0, (0.0, 0.0), 0.0, 4.0, [(0.0, 300.0), (70.0, 80.0)], heading, speed)
    want = enc.assess((0.0, 0.0), 0.0, 4.0, [(0.0, 300.0), (70.0, 80.0)], [180.0, 270.0], 3.0)
    assert_same_bits(s, want)
    # head-on at dcpa 0 in 300 / 7 s; crossing at dcpa 8 m ((6.4, -4.8)) in 530 / 25 = 21.2 s
    assert tr.latched.tolist() == [enc.HEAD_ON, enc.CROSSING_GIVE_WAY]
    assert s.dcpa.tolist() == pytest.approx([0.0, 8.0], abs=1e-9)  # sin(180 deg) is 1.2e-16
    assert s.tcpa.tolist() == pytest.approx([300 / 7, 21.2])
    assert tr.most_urgent() == 1
    # 600 m off: beyond the second target's release distance only; a new onset the next step
    assert tr.step(1.0, [1, 2], [0.0, 0.0], [40.0, 10.0], 600.0).tolist() == [1, 0]
    assert tr.step(2.0, [1, 2], [0.0, 0.0], [40.0, 10.0], 400.0).tolist() == [1, 2]
    assert tr.onset_t.tolist() == [0.0, 2.0] and tr.most_urgent() == 1
