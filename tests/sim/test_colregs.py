"""COLREGs geometry, classes, latching, domain and verdicts on hand-built geometries and tracks.

Expectations are computed by hand (in the comments) or by an independent oracle (dense time
sampling for the CPA, a step-by-step tracker for the vectorised latch). hypothesis is not
installed in this project's environment, so the properties (rotation invariance, role swap) run
on seeded NumPy samples.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from usvtool import angles
from usvtool import encounter as enc
from usvtool.sim import tracking as trk
from usvtool.sim import verdicts as vd
from usvtool.trace import Trace

L = 10.0  # ship length: domain semi-axes 35 m and 15 m, risk distance 35 m, critical range 100 m
DT = 0.1


def names(codes):
    return [enc.CLASS_NAMES[k] for k in np.atleast_1d(codes)]


def at_bearing(origin, bearing_deg, r):
    """The point at compass ``bearing_deg`` and range ``r`` from ``origin``."""
    b = math.radians(bearing_deg)
    return (origin[0] + r * math.sin(b), origin[1] + r * math.cos(b))


# ----------------------------------------------------------------------------- geometry


def test_relative_bearings_and_course_difference():
    own, target = (0.0, 0.0), (100.0, 100.0)
    assert enc.relative_bearing(own, 0.0, target) == pytest.approx(45.0)
    assert enc.relative_bearing(own, 90.0, target) == pytest.approx(315.0)
    assert enc.relative_bearing(target, 200.0, own) == pytest.approx(25.0)  # 225 - 200
    assert enc.relative_bearing(own, 45.0, target) == 0.0
    assert float(enc.course_difference(0.0, 200.0)) == 200.0
    assert float(enc.course_difference(200.0, 0.0)) == 160.0
    # Δψ = 180 + β - α (mod 360) on any geometry
    rng = np.random.default_rng(1)
    p, q = rng.uniform(-500, 500, (2, 50, 2))
    ho, ht = rng.uniform(0, 360, (2, 50))
    beta, alpha = enc.relative_bearing(p, ho, q), enc.relative_bearing(q, ht, p)
    diff = angles.wrap360(180.0 + beta - alpha) - enc.course_difference(ho, ht)
    assert np.abs((diff + 180) % 360 - 180).max() < 1e-9


# The eight encounters of the IWSO-DWA paper, section 5.3 (own ship heading north, y up):
# (own start, own speed, target start, target heading, target speed, class, dcpa, tcpa)
IWSO = [
    ((260, 30), 4, (260, 120), 0, 2, "overtaking", 0.0, 45.0),  # ENV.1 fig. 11
    ((260, 30), 4, (260, 350), 180, 3, "head-on", 0.0, 320 / 7),  # fig. 13
    ((260, 30), 4, (180, 110), 90, 4, "crossing-stand-on", 0.0, 20.0),  # fig. 15, port
    ((260, 30), 4, (330, 110), 270, 4, "crossing-give-way", 5 * math.sqrt(2), 18.75),  # fig. 17
    ((130, 180), 4, (130, 260), 0, 2.5, "overtaking", 0.0, 80 / 1.5),  # ENV.2 fig. 19
    ((130, 180), 4, (130, 350), 180, 2, "head-on", 0.0, 170 / 6),  # fig. 21
    ((130, 180), 4, (75, 260), 90, 3, "crossing-stand-on", 4.0, 19.4),  # fig. 23, port
    ((130, 180), 4, (200, 260), 270, 3, "crossing-give-way", 8.0, 21.2),  # fig. 25
]


@pytest.mark.parametrize("own, v, tgt, th, tv, name, dcpa, tcpa", IWSO)
def test_iwso_encounters_by_hand(own, v, tgt, th, tv, name, dcpa, tcpa):
    # e.g. fig. 25: p = (70, 80), v = (-3, -4): tcpa = 530 / 25 = 21.2, p + v t = (6.4, -4.8)
    s = enc.assess(own, 0.0, v, [tgt], [th], [tv])
    assert names(s.cls) == [name]
    assert s.dcpa[0] == pytest.approx(dcpa, abs=1e-9)
    assert s.tcpa[0] == pytest.approx(tcpa, rel=1e-12)


def test_cpa_by_hand_and_degenerate_cases():
    d, t = enc.cpa([(0.0, 100.0)], [(0.0, -10.0)])  # straight at us: CPA 0 in 10 s
    assert (d[0], t[0]) == (0.0, 10.0)
    d, t = enc.cpa([(30.0, 40.0)], [(0.0, 0.0)])  # no relative motion: now, at the range
    assert (d[0], t[0]) == (50.0, 0.0)
    d, t = enc.cpa([(0.0, 100.0)], [(3.0, 4.0)])  # moving apart: CPA in the past
    assert t[0] == pytest.approx(-16.0) and d[0] == pytest.approx(60.0)  # |(−48, 36)|
    d, t = enc.cpa(np.zeros((2, 3, 2)), np.ones((2, 3, 2)))  # broadcasting over (n, k)
    assert d.shape == t.shape == (2, 3) and not d.any()


def test_cpa_against_dense_time_sampling():
    rng = np.random.default_rng(7)
    p = rng.uniform(-400, 400, (40, 2))
    v = rng.uniform(-8, 8, (40, 2))
    dcpa, tcpa = enc.cpa(p, v)
    times = np.linspace(-400.0, 400.0, 40001)  # 0.02 s apart
    track = p[:, None, :] + times[None, :, None] * v[:, None, :]
    dist = np.hypot(track[..., 0], track[..., 1])
    inside = np.abs(tcpa) < 399
    assert inside.sum() > 30
    best = dist.argmin(axis=1)
    assert np.all(dist.min(axis=1)[inside] >= dcpa[inside] - 1e-9)
    assert np.allclose(dist.min(axis=1)[inside], dcpa[inside], atol=0.15)
    assert np.allclose(times[best][inside], tcpa[inside], atol=0.011)


# ----------------------------------------------------------------------------- classes


@pytest.mark.parametrize(
    "beta, alpha, expected",
    [
        # stern sector of the target: [112.5, 247.5] for α (own overtakes)
        (0.0, 112.5, "overtaking"),
        (0.0, 247.5, "overtaking"),
        (90.0, 112.5 - 1e-9, "crossing-give-way"),
        (270.0, 247.5 + 1e-9, "crossing-stand-on"),
        # own's stern sector: [112.5, 247.5] for β (the target overtakes)
        (112.5, 300.0, "overtaken"),
        (247.5, 60.0, "overtaken"),
        (112.5 - 1e-9, 300.0, "crossing-give-way"),
        (247.5 + 1e-9, 60.0, "crossing-stand-on"),
        # head-on: both |β| and |α| ≤ 12, closed
        (12.0, 348.0, "head-on"),
        (348.0, 12.0, "head-on"),
        (12.0 + 1e-9, 348.0, "crossing-give-way"),
        (348.0 - 1e-9, 12.0, "crossing-stand-on"),
        (0.0, 12.0 + 1e-9, "crossing-give-way"),  # dead ahead, not head-on: starboard
        (0.0, 348.0 - 1e-9, "crossing-give-way"),
        (359.0, 348.0 - 1e-9, "crossing-stand-on"),
        (0.0, 0.0, "head-on"),
        # overtaking wins over overtaken when both sectors hold (impossible while closing)
        (180.0, 180.0, "overtaking"),
    ],
)
def test_sector_borders_exactly(beta, alpha, expected):
    assert names(enc.classify_angles(beta, alpha, True)) == [expected]
    assert names(enc.classify_angles(beta, alpha, False)) == ["none"]


def test_class_names_and_codes():
    assert enc.CLASS_NAMES[enc.NONE] == "none" and enc.CLASS_NAMES[enc.OVERTAKEN] == "overtaken"
    assert len(set(enc.CLASS_NAMES)) == 6
    assert enc.classify_angles([0.0, 90.0], [0.0, 300.0], True).dtype == np.int8


EPS = 1e-6  # degrees: geometric "just inside / just outside"


@pytest.mark.parametrize("offset, expected", [(+EPS, "overtaken"), (-EPS, "crossing-give-way")])
def test_overtaken_border_on_geometry(offset, expected):
    # target 100 m away at β = 112.5 ± ε, heading north at 5 m/s; own north at 2 m/s: closing
    target = at_bearing((0, 0), 112.5 + offset, 100.0)
    s = enc.assess((0, 0), 0.0, 2.0, [target], [0.0], [5.0])
    assert s.beta[0] == pytest.approx(112.5 + offset, abs=1e-10)
    assert names(s.cls) == [expected]


@pytest.mark.parametrize("offset, expected", [(-EPS, "overtaking"), (+EPS, "crossing-give-way")])
def test_overtaking_border_on_geometry(offset, expected):
    # own 100 m from the target at α = 247.5 ∓ ε (her port quarter), both heading north, own
    # faster; outside the sector the target is at β = 67.5 on own's starboard bow
    own = at_bearing((0, 0), 247.5 + offset, 100.0)
    s = enc.assess(own, 0.0, 5.0, [(0.0, 0.0)], [0.0], [2.0])
    assert s.alpha[0] == pytest.approx(247.5 + offset, abs=1e-10)
    assert names(s.cls) == [expected]


@pytest.mark.parametrize("offset, expected", [(-EPS, "head-on"), (+EPS, "crossing-give-way")])
def test_head_on_bearing_border_on_geometry(offset, expected):
    # target at β = 12 ± ε heading straight at own (α = 0)
    b = 12.0 + offset
    target = at_bearing((0, 0), b, 200.0)
    s = enc.assess((0, 0), 0.0, 3.0, [target], [b + 180.0], [3.0])
    assert names(s.cls) == [expected]


@pytest.mark.parametrize("offset, expected", [(-EPS, "head-on"), (+EPS, "crossing-give-way")])
def test_head_on_aspect_border_on_geometry(offset, expected):
    # target dead ahead heading 192 ± ε: own seen from her at α = 348 ∓ ε
    s = enc.assess((0, 0), 0.0, 3.0, [(0.0, 200.0)], [192.0 + offset], [3.0])
    assert s.alpha[0] == pytest.approx(348.0 - offset, abs=1e-10)
    assert names(s.cls) == [expected]


def test_every_class_on_hand_geometry():
    own, h, v = (0.0, 0.0), 30.0, 4.0  # own heading 030: the scene rotated by 30°
    targets = [
        at_bearing(own, 30.0, 300.0),  # dead ahead, reciprocal
        at_bearing(own, 30.0 + 45, 300.0),  # starboard bow, crossing from starboard
        at_bearing(own, 30.0 - 45, 300.0),  # port bow, crossing from port
        at_bearing(own, 30.0, 100.0),  # ahead, same course, slower
        at_bearing(own, 30.0 + 180, 100.0),  # astern, same course, faster
        at_bearing(own, 30.0 + 90, 100.0),  # abeam, heading away east-south-east
    ]
    headings = [210.0, 30.0 - 90, 30.0 + 90, 30.0, 30.0, 120.0]
    speeds = [4.0, 4.0, 4.0, 2.0, 6.0, 4.0]
    got = names(enc.classify(own, h, v, targets, headings, speeds))
    assert got == [
        "head-on",
        "crossing-give-way",
        "crossing-stand-on",
        "overtaking",
        "overtaken",
        "none",
    ]


def test_moving_apart_and_no_relative_motion_are_none():
    # astern of the target but slower, same course: falling behind
    assert names(enc.classify((0, 0), 0.0, 2.0, [(0, 100)], [0.0], [5.0])) == ["none"]
    # abeam, same course and speed: constant range
    assert names(enc.classify((0, 0), 0.0, 4.0, [(50, 0)], [0.0], [4.0])) == ["none"]
    # reciprocal courses but already passed (target astern)
    assert names(enc.classify((0, 0), 0.0, 4.0, [(0, -100)], [180.0], [4.0])) == ["none"]


def test_classify_broadcasts_over_time_and_targets():
    own_xy = np.array([[0.0, 0.0], [0.0, 10.0]])[:, None]  # (n, 1, 2)
    tgt = np.array([[[0.0, 300.0], [200.0, 200.0]], [[0.0, 290.0], [196.0, 200.0]]])
    cls = enc.classify(own_xy, np.zeros((2, 1)), 4.0, tgt, [[180.0, 270.0]], 4.0)
    assert cls.shape == (2, 2)
    assert [names(row) for row in cls] == [["head-on", "crossing-give-way"]] * 2


def _random_scenes(rng, n):
    own = rng.uniform(-300, 300, (n, 2))
    tgt = rng.uniform(-300, 300, (n, 2))
    return (
        own,
        rng.uniform(0, 360, n),
        rng.uniform(0, 8, n),
        tgt,
        rng.uniform(0, 360, n),
        rng.uniform(0, 8, n),
    )


def _near_border(*angles, tol=1e-6):
    borders = np.array(
        [
            0.0,
            360.0,
            *enc.STERN_SECTOR_DEG,
            enc.HEAD_ON_BEARING_DEG,
            360.0 - enc.HEAD_ON_BEARING_DEG,
        ]
    )
    return np.any([np.abs(a[:, None] - borders).min(axis=1) < tol for a in angles], axis=0)


def test_rotating_the_scene_keeps_the_classes():
    rng = np.random.default_rng(11)
    own, ho, vo, tgt, ht, vt = _random_scenes(rng, 4000)
    s = enc.assess(own, ho, vo, tgt, ht, vt)
    p = tgt - own
    v = enc.velocity(ht, vt) - enc.velocity(ho, vo)
    keep = ~_near_border(s.beta, s.alpha) & (np.abs((p * v).sum(axis=1)) > 1e-6)
    for theta in (37.0, 90.0, 211.5, -123.0):
        th = math.radians(theta)  # clockwise rotation about a pivot: bearings grow by theta
        pivot = np.array([55.0, -20.0])

        def rot(xy, th=th, pivot=pivot):
            d = xy - pivot
            return pivot + np.stack(
                [
                    d[:, 0] * math.cos(th) + d[:, 1] * math.sin(th),
                    -d[:, 0] * math.sin(th) + d[:, 1] * math.cos(th),
                ],
                axis=1,
            )

        r = enc.assess(rot(own), ho + theta, vo, rot(tgt), ht + theta, vt)
        assert np.allclose(angles.wrap360(r.beta - s.beta + 180) - 180, 0, atol=1e-9)
        assert np.array_equal(r.cls[keep], s.cls[keep])
    assert len(set(s.cls[keep].tolist())) == 6  # every class was exercised


def test_swapping_roles_on_collision_courses():
    # ships that meet at point C at time T: each class maps to its counterpart
    rng = np.random.default_rng(5)
    n = 4000
    meet = rng.uniform(-200, 200, (n, 2))
    when = rng.uniform(5, 200, n)
    ho, ht = rng.uniform(0, 360, (2, n))
    vo, vt = rng.uniform(0.5, 8, (2, n))
    own = meet - when[:, None] * enc.velocity(ho, vo)
    tgt = meet - when[:, None] * enc.velocity(ht, vt)
    a = enc.assess(own, ho, vo, tgt, ht, vt)
    b = enc.assess(tgt, ht, vt, own, ho, vo)
    assert np.allclose(a.dcpa, 0, atol=1e-6) and np.allclose(a.tcpa, when)
    keep = ~_near_border(a.beta, a.alpha)
    counterpart = np.array(
        [
            enc.NONE,
            enc.HEAD_ON,
            enc.CROSSING_STAND_ON,
            enc.CROSSING_GIVE_WAY,
            enc.OVERTAKEN,
            enc.OVERTAKING,
        ]
    )
    assert not (a.cls == enc.NONE).any()  # collision courses are always closing
    assert np.array_equal(b.cls[keep], counterpart[a.cls[keep]])
    assert len(set(a.cls[keep].tolist())) == 5  # all but none


# ----------------------------------------------------------------------------- latching


def test_class_is_latched_at_onset_and_released_after_passing():
    tr = trk.EncounterTracker(1, risk_distance=35.0)
    own_h, own_v = 0.0, 5.0
    seen, latched = [], []
    for i in range(200):
        t = i * 0.5
        own = (0.0, own_v * t)
        # a target coming head-on; from t = 20 s she swings to 225° (her starboard) and keeps
        # closing, which alone would classify as crossing; she passes at t ≈ 40 s
        if t < 20:
            tgt, th = (0.0, 400.0 - 5.0 * t), 180.0
        else:
            d = t - 20
            tgt = (
                -5.0 * d * math.sin(math.radians(45)),
                300.0 - 5.0 * d * math.cos(math.radians(45)),
            )
            th = 225.0
        s = tr.update(t, own, own_h, own_v, [tgt], [th], [5.0])
        seen.append(int(s.cls[0]))
        latched.append(int(tr.latched[0]))
    assert latched[0] == enc.HEAD_ON and tr.onset_t[0] != tr.onset_t[0]  # released: NaN
    swung = [i for i in range(60, 80) if seen[i] != enc.HEAD_ON]
    assert swung and all(latched[i] == enc.HEAD_ON for i in swung)  # geometry changed, latch kept
    released = latched.index(enc.NONE)
    assert 70 < released < 120  # after the pass (range increasing, beyond 35 m)
    assert all(x == enc.NONE for x in latched[released:])  # moving apart: no new onset


def test_onset_needs_risk_and_horizon():
    tr = trk.EncounterTracker(4, risk_distance=[35.0, 35.0, 35.0, 35.0], horizon_s=120.0)
    out = tr.step(
        0.0, [1, 1, 1, 0], [34.9, 35.0, 10.0, 0.0], [119.0, 10.0, 120.0, 10.0], [500.0] * 4
    )
    assert out.tolist() == [1, 0, 0, 0]  # dcpa < 35 strictly, tcpa < 120 strictly, a class


def test_release_by_distance_and_no_reonset_in_the_same_step():
    tr = trk.EncounterTracker(1, risk_distance=35.0, release_distance=1000.0)
    assert tr.step(0, [2], [0.0], [50.0], [400.0]).tolist() == [2]
    assert tr.step(1, [3], [0.0], [50.0], [1000.5]).tolist() == [0]  # beyond: released ...
    assert tr.step(2, [3], [0.0], [50.0], [900.0]).tolist() == [3]  # ... a new encounter next


def test_most_urgent_is_the_smallest_positive_tcpa():
    tr = trk.EncounterTracker(3, risk_distance=35.0)
    assert tr.most_urgent() is None
    tr.step(0, [1, 2, 0], [0.0, 0.0, 0.0], [30.0, 12.0, 5.0], [300.0, 100.0, 50.0])
    assert tr.most_urgent() == 1  # target 2 has no class, so no encounter


def test_vectorised_latch_equals_the_stepwise_tracker():
    rng = np.random.default_rng(3)
    n, k = 400, 6
    cls = rng.integers(0, 6, (n, k))
    dcpa = rng.uniform(0, 60, (n, k))
    tcpa = rng.uniform(-30, 150, (n, k))
    rng_m = np.abs(200 + np.cumsum(rng.normal(0, 8, (n, k)), axis=0))
    release = np.array([np.inf, 400, np.inf, 250, np.inf, 300])
    got = trk.latch_series(cls, dcpa, tcpa, rng_m, 35.0, 120.0, 20.0, release)
    tr = trk.EncounterTracker(k, 35.0, 120.0, 20.0, release)
    want = np.array([tr.step(i, cls[i], dcpa[i], tcpa[i], rng_m[i]) for i in range(n)])
    assert np.array_equal(got, want)
    assert (np.diff((want != 0).astype(int), axis=0) == 1).sum() > 20  # many encounters


# ----------------------------------------------------------------------------- domain


def test_domain_membership_on_hand_points():
    own = (100.0, 200.0)
    pts = [
        (100, 235),
        (100, 235.01),
        (115, 200),
        (115.01, 200),
        (85, 200),
        (100, 165),
        (110, 220),
        (114, 210),
    ]
    # heading north: semi-axes 35 along y, 15 along x; (10, 20): (20/35)² + (10/15)² = 0.77
    # (14, 10): (10/35)² + (14/15)² = 0.95
    assert enc.in_domain(own, 0.0, pts, L).tolist() == [
        True,
        False,
        True,
        False,
        True,
        True,
        True,
        True,
    ]
    # heading east: the long axis along x; (20, 12) off: (20/35)² + (12/15)² = 0.97 (in),
    # (20, 13) off: (20/35)² + (13/15)² = 1.08 (out)
    pts = [(135, 200), (100, 215), (100, 216), (120, 212), (120, 213)]
    assert enc.in_domain(own, 90.0, pts, L).tolist() == [True, True, False, True, False]
    # heading 045: a point 30 m ahead and 10 m to starboard: (30/35)² + (10/15)² = 1.18 (out);
    # 25 ahead, 10 across: 0.51 + 0.44 = 0.95 (in)
    ahead = np.array([math.sin(math.radians(45)), math.cos(math.radians(45))])
    star = np.array([math.cos(math.radians(45)), -math.sin(math.radians(45))])
    o = np.array(own)
    assert enc.in_domain(
        own, 45.0, [o + 30 * ahead + 10 * star, o + 25 * ahead - 10 * star], L
    ).tolist() == [False, True]


def test_domain_intrusion_time():
    t = np.arange(0.0, 5.1, 1.0)  # 0 … 5
    inside = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0], [0, 0]], bool)
    # any target inside at t = 1, 2, 3: (0.5 + 1 + 1 + 0.5) s
    assert vd.intrusion_time(t, inside) == 3.0
    assert vd.intrusion_time(t, inside[:, 1]) == 2.0


# ----------------------------------------------------------------------------- verdicts

T = np.arange(0.0, 140.0 + DT / 2, DT)


def own_track(h0, v0, turns=(), slow=(), x0=0.0, y0=0.0):
    """Own ship on heading ``h0`` at ``v0``: turns ``(start s, change deg, rate deg/s)`` and speed
    ramps ``(start s, factor, duration s)``; positions integrated step by step."""
    h = np.full_like(T, float(h0))
    for ts, delta, rate in turns:
        h = h + math.copysign(1.0, delta) * np.clip((T - ts) * rate, 0.0, abs(delta))
    v = np.full_like(T, float(v0))
    for ts, factor, dur in slow:
        v = v * (1 + (factor - 1) * np.clip((T - ts) / dur, 0.0, 1.0))
    h = angles.wrap360(h)
    vel = enc.velocity(h, v)
    x = x0 + np.concatenate([[0.0], np.cumsum(vel[:-1, 0] * DT)])
    y = y0 + np.concatenate([[0.0], np.cumsum(vel[:-1, 1] * DT)])
    return x, y, h, v


def straight(x0, y0, h, v, turns=()):
    return own_track(h, v, turns, x0=x0, y0=y0)


def trace_of(own, *targets):
    """The trace of the own ship's and the targets' ``(x, y, heading, speed)`` arrays."""
    ships = (own, *targets)
    x, y, h, v = (np.column_stack([s[i] for s in ships]) for i in range(4))
    names = ["own", *(f"target{j + 1}" for j in range(len(targets)))]
    return Trace(T, names, x, y, h, v, np.zeros_like(x))


def run(own, target, rule2=None, **kw):
    r = vd.evaluate(trace_of(own, target), [L, L], rule2, **kw)
    json.dumps(r, allow_nan=False)  # plain JSON
    return r


HEAD_ON_TARGET = straight(0, 600, 180, 5)  # 600 m ahead, reciprocal: tcpa = 60 s


def test_head_on_clear_starboard_turn_is_compliant():
    r = run(own_track(0, 5, turns=[(5, 40, 10)]), HEAD_ON_TARGET)
    (e,) = r["events"]
    assert e["class"] == "head-on" and e["onset_s"] == 0.0 and e["onset_range_m"] == 600.0
    m = e["first_manoeuvre"]
    assert m["side"] == "starboard" and m["course_change_deg"] == pytest.approx(40.0)
    assert 5.0 <= m["t"] <= 5.1 + 1e-9  # the turn starts at 5 s (within the 1° start tolerance)
    assert m["range_m"] == pytest.approx(600 - 10 * m["t"], abs=0.6)
    assert e["passing_side"] == "port" and e["closest_distance_m"] > 150
    assert e["compliant"] and e["failed_rules"] == [] and e["released_s"] is not None
    assert r["figures"]["domain_intrusion_s"] == 0.0


def test_head_on_port_turn_is_not_compliant():
    r = run(own_track(0, 5, turns=[(5, -40, 10)]), HEAD_ON_TARGET)
    (e,) = r["events"]
    assert e["first_manoeuvre"]["side"] == "port" and e["passing_side"] == "starboard"
    assert not e["compliant"]
    assert e["failed_rules"] == [vd.STARBOARD_TURN, vd.PORT_TO_PORT]


def test_rule2_departure_excuses_the_side_rules_only():
    rec = {"t": 5.0, "target": 0, "reason": "ship on starboard side"}
    other = {"t": 5.0, "target": 3, "reason": "no such target"}
    r = run(own_track(0, 5, turns=[(5, -40, 10)]), HEAD_ON_TARGET, [rec, other])
    (e,) = r["events"]
    assert e["rule2_departure"] == [rec] and r["unmatched_rule2"] == [other]
    assert e["compliant"] and e["excused_rules"] == [vd.STARBOARD_TURN, vd.PORT_TO_PORT]
    # a late small port turn is not excused its Rule 8 / 16 failures
    r = run(own_track(0, 5, turns=[(53, -10, 10)]), HEAD_ON_TARGET, [{**rec, "t": 53.0}])
    (e,) = r["events"]
    assert {vd.APPARENT, vd.IN_TIME} <= set(e["failed_rules"]) and not e["compliant"]


def test_small_course_change_is_not_readily_apparent():
    # 10° to starboard at 5 s: passes port to port ~50 m abeam (outside the 15 m semi-minor axis)
    r = run(own_track(0, 5, turns=[(5, 10, 5)]), HEAD_ON_TARGET)
    (e,) = r["events"]
    assert e["first_manoeuvre"]["course_change_deg"] == pytest.approx(10.0)
    assert e["passing_side"] == "port" and e["domain_intrusion_s"] == 0.0
    assert e["failed_rules"] == [vd.APPARENT]


def test_late_turn_is_not_in_time():
    # turn at 52 s, at a range of 80 m (< critical 100 m and < half the onset range)
    r = run(own_track(0, 5, turns=[(52, 40, 10)]), HEAD_ON_TARGET)
    (e,) = r["events"]
    assert e["first_manoeuvre"]["range_m"] < 100
    assert vd.IN_TIME in e["failed_rules"] and vd.APPARENT not in e["failed_rules"]


def test_no_manoeuvre_head_on():
    r = run(own_track(0, 5), HEAD_ON_TARGET)
    (e,) = r["events"]
    assert e["first_manoeuvre"] is None and e["closest_distance_m"] < 5
    assert e["failed_rules"] == [vd.NO_ACTION, vd.SAFE_DISTANCE, vd.STARBOARD_TURN, vd.PORT_TO_PORT]
    assert e["domain_intrusion_s"] > 0 and r["figures"]["domain_intrusion_s"] > 0


# crossing from port: collision at (0, 400) at t = 100 s unless someone acts; range 566 m
PORT_TARGET = straight(-400, 400, 90, 4)
# crossing from starboard: the same, from the other side
STARBOARD_TARGET = straight(400, 400, 270, 4)


def test_stand_on_that_keeps_course_while_the_other_gives_way_is_compliant():
    target = straight(-400, 400, 90, 4, turns=[(10, 60, 5)])  # she turns to starboard, astern
    r = run(own_track(0, 4), target)
    (e,) = r["events"]
    assert e["class"] == "crossing-stand-on"
    assert e["compliant"] and e["failed_rules"] == []


def test_stand_on_that_turns_while_range_above_critical_is_not_compliant():
    r = run(own_track(0, 4, turns=[(10, 30, 5)]), PORT_TARGET)
    (e,) = r["events"]
    assert e["class"] == "crossing-stand-on" and e["first_manoeuvre"]["range_m"] > 100
    assert vd.STAND_ON in e["failed_rules"] and not e["compliant"]


def test_stand_on_that_slows_early_is_not_compliant():
    r = run(own_track(0, 4, slow=[(10, 0.8, 5)]), PORT_TARGET)  # 20 % slower
    (e,) = r["events"]
    assert vd.STAND_ON in e["failed_rules"]
    assert e["first_manoeuvre"]["speed_change"] == pytest.approx(-0.2)


def test_stand_on_that_never_acts_in_extremis_fails_17b():
    r = run(own_track(0, 4), PORT_TARGET)
    (e,) = r["events"]
    assert e["closest_distance_m"] < 5 and e["failed_rules"] == [vd.IN_EXTREMIS]


def test_stand_on_turning_to_port_in_extremis_fails_17c():
    # range falls below 100 m at t ≈ 82 s; a port turn at 85 s
    r = run(own_track(0, 4, turns=[(85, -40, 10)]), PORT_TARGET)
    (e,) = r["events"]
    assert vd.NOT_PORT in e["failed_rules"] and vd.STAND_ON not in e["failed_rules"]
    r = run(own_track(0, 4, turns=[(85, 40, 10)]), PORT_TARGET)  # starboard: allowed
    (e,) = r["events"]
    assert vd.NOT_PORT not in e["failed_rules"] and vd.STAND_ON not in e["failed_rules"]


def test_give_way_passing_astern_is_compliant():
    r = run(own_track(0, 4, turns=[(5, 60, 10)]), STARBOARD_TARGET)
    (e,) = r["events"]
    assert e["class"] == "crossing-give-way" and e["crossing"] != "ahead"
    assert e["compliant"], e["failed_rules"]


def test_give_way_that_passes_ahead_is_not_compliant():
    # 40° to port at 5 s: own crosses y = 400 at t ≈ 129 s, ~220 m ahead of the target's bow
    r = run(own_track(0, 4, turns=[(5, -40, 10)]), STARBOARD_TARGET)
    (e,) = r["events"]
    assert e["crossing"] == "ahead"
    assert e["failed_rules"] == [vd.NOT_AHEAD]


def test_give_way_by_speed_reduction_is_readily_apparent():
    r = run(own_track(0, 4, slow=[(5, 0.4, 5)]), STARBOARD_TARGET)  # to 40 % of her speed
    (e,) = r["events"]
    m = e["first_manoeuvre"]
    assert m["side"] is None and m["speed_change"] == pytest.approx(-0.6)
    assert e["compliant"], e["failed_rules"]


def test_overtaking_keeps_clear_on_either_side():
    target = straight(0, 200, 0, 2)  # 200 m ahead, slower: tcpa = 66.7 s
    for delta, side in ((-35, "starboard"), (35, "port")):
        r = run(own_track(0, 5, turns=[(5, delta, 10)]), target)
        (e,) = r["events"]
        assert e["class"] == "overtaking" and e["passing_side"] == side
        assert e["compliant"], e["failed_rules"]
    r = run(own_track(0, 5), target)
    (e,) = r["events"]
    assert e["failed_rules"] == [vd.NO_ACTION, vd.KEEP_CLEAR]


def test_crossing_ahead_or_astern_helper():
    # target at the origin heading north; own moving west 50 m ahead / 50 m astern of her
    xs = np.linspace(30, -30, 7)
    ahead = np.column_stack([xs, np.full(7, 50.0)])
    zeros = np.zeros((7, 2))
    assert vd._crossing(ahead, zeros, np.zeros(7)) == "ahead"
    assert vd._crossing(ahead * [1, -1], zeros, np.zeros(7)) == "astern"
    assert vd._crossing(np.column_stack([np.zeros(7), xs]), zeros, np.zeros(7)) is None


def test_targets_without_an_encounter_and_several_targets():
    far = straight(500, -500, 90, 3)  # moving away east, never closing
    own = own_track(0, 5, turns=[(5, 40, 10)])
    r = vd.evaluate(trace_of(own, HEAD_ON_TARGET, far), [L, L, L])
    first, second = r["events"]
    assert first["class"] == "head-on" and first["compliant"]
    assert second == {**second, "target": 1, "class": "none", "compliant": None}
    assert r["figures"]["closest_distance_m"] == pytest.approx(first["closest_distance_m"])


# ----------------------------------------------------------------------------- the rule table


def test_the_rule_table_per_role():
    """The rows of each role, in the order a verdict lists its failures (docs/colregs.md)."""
    give_way = [vd.NO_ACTION, vd.APPARENT, vd.IN_TIME]
    stand_on = [vd.STAND_ON, vd.IN_EXTREMIS]
    ids = {enc.CLASS_NAMES[code]: [r.id for r in rules] for code, rules in vd.ROLE_RULES.items()}
    assert ids == {
        "head-on": [*give_way, vd.SAFE_DISTANCE, vd.STARBOARD_TURN, vd.PORT_TO_PORT],
        "crossing-give-way": [*give_way, vd.SAFE_DISTANCE, vd.NOT_AHEAD],
        "overtaking": [*give_way, vd.KEEP_CLEAR],
        "crossing-stand-on": [*stand_on, vd.NOT_PORT],
        "overtaken": stand_on,
    }
    # Rule 2 excuses the side and stand-on rules, never Rules 8, 16, 13 or 17(b)
    assert vd.EXCUSABLE == {vd.STARBOARD_TURN, vd.PORT_TO_PORT, vd.NOT_AHEAD, vd.STAND_ON,
                            vd.NOT_PORT}  # fmt: skip


# Overtaken: the target 200 m astern at 6 m/s on the own ship's course (3 m/s), 30 m or 5 m to
# starboard: tcpa = 200 / 3 = 66.7 s, dcpa 30 or 5 m (< 35: onset at t = 0); the range falls
# below the critical 100 m at t = 33 s. At 30 m she never enters the own domain (15 m across).
def overtaking_target(offset):
    return straight(offset, -200, 0, 6)


def test_overtaken_that_keeps_course_and_speed_is_compliant():
    (e,) = run(own_track(0, 3), overtaking_target(30))["events"]
    assert e["class"] == "overtaken" and e["onset_s"] == 0.0
    assert e["first_manoeuvre"] is None and e["domain_intrusion_s"] == 0.0
    assert e["compliant"] and e["failed_rules"] == []


def test_overtaken_that_turns_early_fails_17a_unless_rule2():
    own = own_track(0, 3, turns=[(5, 30, 10)])  # at a range of about 185 m
    (e,) = run(own, overtaking_target(30))["events"]
    assert e["class"] == "overtaken" and e["first_manoeuvre"]["range_m"] > 100
    assert e["failed_rules"] == [vd.STAND_ON]
    rec = {"t": 5.0, "target": 0, "reason": "test"}
    (e,) = run(own, overtaking_target(30), [rec])["events"]
    assert e["compliant"] and e["excused_rules"] == [vd.STAND_ON]


def test_overtaken_that_never_acts_while_she_passes_close_fails_17b():
    (e,) = run(own_track(0, 3), overtaking_target(5))["events"]
    assert e["class"] == "overtaken" and e["domain_intrusion_s"] > 0
    assert e["failed_rules"] == [vd.IN_EXTREMIS]


def test_overtaken_turning_to_port_in_extremis_fails_no_port_rule():
    """Rule 17(c) (no port turn for a vessel on her own port side) is the crossing stand-on
    vessel's, not the overtaken one's: a late port turn keeps 17(b) and fails nothing."""
    (e,) = run(own_track(0, 3, turns=[(40, -40, 10)]), overtaking_target(5))["events"]
    assert e["class"] == "overtaken" and e["first_manoeuvre"]["side"] == "port"
    assert e["first_manoeuvre"]["range_m"] < 100
    assert e["failed_rules"] == []


def test_evaluate_takes_one_length_per_ship_of_the_trace():
    with pytest.raises(ValueError, match="1 lengths for the 2 ships"):
        vd.evaluate(trace_of(own_track(0, 5), HEAD_ON_TARGET), [L])
    # the targets' lengths feed only the own ship's time in their domains
    short, long = (vd.evaluate(trace_of(own_track(0, 5), HEAD_ON_TARGET), [L, length])
                   for length in (1.0, 20.0))  # fmt: skip
    (a,), (b,) = short["events"], long["events"]
    assert a["own_in_target_domain_s"] < b["own_in_target_domain_s"]
    assert {**a, "own_in_target_domain_s": 0} == {**b, "own_in_target_domain_s": 0}
