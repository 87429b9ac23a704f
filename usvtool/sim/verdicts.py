"""COLREGs verdicts of a finished run: its encounters, the own ship's manoeuvres and the rules.

The offline evaluation of a run (the simulation's events JSON): the run latched at once
(:func:`usvtool.sim.tracking.latch_series` on :func:`usvtool.encounter.assess`), then, per
encounter, the manoeuvre on the sampled own track and the verdict.

Ship domain: the 7 L x 3 L ellipse of :func:`usvtool.encounter.in_domain`. *Domain intrusion*
is the time during which some target is inside (:func:`intrusion_time`, trapezoidal on the
samples).

Manoeuvre (on the sampled own track, :func:`evaluate`)
    A manoeuvre is detected at the first sample ``i`` (from the encounter's onset) from which
    the heading changes by at least ``MANOEUVRE_COURSE_DEG`` (5°), or the speed by at least
    ``MANOEUVRE_SPEED_FRACTION`` (10 %) of the speed at ``i`` (at least ``SPEED_FLOOR`` m/s),
    within the following ``MANOEUVRE_WINDOW_S`` (10 s). It starts at the last sample before the
    threshold is crossed whose heading is within ``MANOEUVRE_START_DEG`` (1°) and speed within
    ``MANOEUVRE_START_FRACTION`` (2 %) of those at ``i`` (so a fast turn is not dated up to 10 s
    early). Its course change is the signed heading deviation from ``i`` of largest magnitude
    until the CPA (positive = starboard), its speed change the signed relative speed deviation of
    largest magnitude; its side is starboard/port when the course change is at least 5° either
    way, else none (a speed manoeuvre).

Verdicts (:func:`evaluate`, per encounter; ``r`` the range, ``r_on`` at onset, ``r_crit`` the
critical range, default ``CRITICAL_RANGE_LENGTHS`` = 10 own lengths)
    Give-way roles (head-on, crossing-give-way, overtaking) fail ``rule16-no-action`` without a
    manoeuvre before the CPA; ``rule8-readily-apparent`` unless it changes course by at least
    ``APPARENT_COURSE_DEG`` (30°) or cuts speed by at least ``APPARENT_SPEED_FRACTION`` (50 %);
    ``rule16-in-time`` unless it starts at ``r ≥ TIMELY_RANGE_FRACTION · r_on`` (half) and
    ``r ≥ r_crit`` (waived when ``r_on < r_crit``); ``rule8-safe-distance`` (overtaking:
    ``rule13-keep-clear``) if the target enters the own domain. Head-on also fails
    ``rule14-starboard`` unless the manoeuvre is a starboard alteration, and
    ``rule14-port-to-port`` unless the target is on the own port side at the CPA. Crossing
    give-way fails ``rule15-ahead`` if the own ship crosses the target's heading line ahead of
    her bow. Stand-on roles (crossing-stand-on, overtaken) fail ``rule17-keep-course-speed`` if,
    while ``r ≥ r_crit``, the heading leaves its onset value by more than
    ``STAND_ON_COURSE_DEG`` (10°) or the speed by more than ``STAND_ON_SPEED_FRACTION`` (10 %);
    ``rule17b-no-action`` if the target enters the own domain and no manoeuvre starts once
    ``r < r_crit``; crossing-stand-on fails ``rule17c-port-turn`` if that manoeuvre is to port.
    A Rule 2 departure record of the controller within the encounter excuses the side and
    stand-on rules (:data:`EXCUSABLE`), never Rules 8, 16, 13(a) or 17(b). Sources, and the
    readings of the papers, are in docs/colregs.md.
"""

from __future__ import annotations

import numpy as np

from usvtool import metrics
from usvtool.encounter import (
    CLASS_NAMES,
    CROSSING_GIVE_WAY,
    CROSSING_STAND_ON,
    DOMAIN_LENGTH_FACTOR,
    DOMAIN_WIDTH_FACTOR,
    HEAD_ON,
    HEAD_ON_BEARING_DEG,
    NONE,
    OVERTAKEN,
    OVERTAKING,
    STERN_SECTOR_DEG,
    assess,
    in_domain,
)
from usvtool.sim.tracking import RISK_HORIZON_S, latch_series, onset_distance

#: Offsets (m) from a target's heading line below this are on it (for ahead/astern crossings).
LINE_EPS = 1e-6
#: Manoeuvre detection on the sampled track.
MANOEUVRE_COURSE_DEG = 5.0
MANOEUVRE_WINDOW_S = 10.0
MANOEUVRE_SPEED_FRACTION = 0.1
MANOEUVRE_START_DEG = 1.0
MANOEUVRE_START_FRACTION = 0.02
SPEED_FLOOR = 0.01  # m/s: speed thresholds are relative to at least this
#: Rule 8(b) "readily apparent": a course change of at least 30° or a speed reduction to half.
APPARENT_COURSE_DEG = 30.0
APPARENT_SPEED_FRACTION = 0.5
#: Rule 16 "early": the give-way manoeuvre starts before the range halves from the onset...
TIMELY_RANGE_FRACTION = 0.5
#: ... and before the critical range, default 10 own ship lengths (Rule 17(a)(ii)/(b)).
CRITICAL_RANGE_LENGTHS = 10.0
#: Rule 17(a)(i): the stand-on vessel keeps her course within 10° and speed within 10 %.
STAND_ON_COURSE_DEG = 10.0
STAND_ON_SPEED_FRACTION = 0.1

NO_ACTION = "rule16-no-action"
APPARENT = "rule8-readily-apparent"
IN_TIME = "rule16-in-time"
SAFE_DISTANCE = "rule8-safe-distance"
KEEP_CLEAR = "rule13-keep-clear"
STARBOARD_TURN = "rule14-starboard"
PORT_TO_PORT = "rule14-port-to-port"
NOT_AHEAD = "rule15-ahead"
STAND_ON = "rule17-keep-course-speed"
IN_EXTREMIS = "rule17b-no-action"
NOT_PORT = "rule17c-port-turn"
#: Every rule a verdict can fail, and those a Rule 2 departure record excuses.
RULES = (
    NO_ACTION,
    APPARENT,
    IN_TIME,
    SAFE_DISTANCE,
    KEEP_CLEAR,
    STARBOARD_TURN,
    PORT_TO_PORT,
    NOT_AHEAD,
    STAND_ON,
    IN_EXTREMIS,
    NOT_PORT,
)
EXCUSABLE = frozenset({STARBOARD_TURN, PORT_TO_PORT, NOT_AHEAD, STAND_ON, NOT_PORT})


def intrusion_time(t, inside) -> float:
    """Seconds during which ``inside`` (``(n,)``, or ``(n, k)``: any target) holds, counting
    each sample interval by the trapezoid rule (half an interval when one end is inside).

    >>> intrusion_time([0.0, 1.0, 2.0, 3.0], [False, True, True, False])
    2.0
    """
    inside = np.asarray(inside, bool)
    if inside.ndim > 1:
        inside = inside.any(axis=tuple(range(1, inside.ndim)))
    t = np.asarray(t, float)
    if len(t) < 2:
        return 0.0
    return float((np.diff(t) * (inside[1:].astype(float) + inside[:-1]) / 2).sum())


# ----------------------------------------------------------------------------- evaluation


def _range_extrema(a: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """Max and min of ``a[lo_i … hi_i]`` (inclusive, ``lo ≤ hi``) for all ``i``: sparse table."""
    n = len(a)
    tmax, tmin = [a], [a]
    width = 1
    while 2 * width <= n:
        m, s = tmax[-1], tmin[-1]
        tmax.append(np.concatenate([np.maximum(m[:-width], m[width:]), m[-width:]]))
        tmin.append(np.concatenate([np.minimum(s[:-width], s[width:]), s[-width:]]))
        width *= 2
    level = np.floor(np.log2(hi - lo + 1)).astype(int)
    tmax, tmin = np.array(tmax), np.array(tmin)
    right = hi - (1 << level) + 1
    return (
        np.maximum(tmax[level, lo], tmax[level, right]),
        np.minimum(tmin[level, lo], tmin[level, right]),
    )


class _Track:
    """The own ship's sampled track with its manoeuvre flags (module docstring)."""

    def __init__(self, t, heading, speed):
        self.t = t
        self.h = np.degrees(np.unwrap(np.radians(heading)))
        self.v = speed
        n = len(t)
        self.end = np.searchsorted(t, t + MANOEUVRE_WINDOW_S, side="right") - 1
        self.thr = MANOEUVRE_SPEED_FRACTION * np.maximum(speed, SPEED_FLOOR)
        lo = np.minimum(np.arange(n) + 1, n - 1)
        hi = np.maximum(self.end, lo)
        valid = self.end > np.arange(n)
        hmax, hmin = _range_extrema(self.h, lo, hi)
        vmax, vmin = _range_extrema(self.v, lo, hi)
        dev_h = np.maximum(hmax - self.h, self.h - hmin)
        dev_v = np.maximum(vmax - self.v, self.v - vmin)
        self.flag = valid & ((dev_h >= MANOEUVRE_COURSE_DEG) | (dev_v >= self.thr))

    def manoeuvre(self, first: int, last: int, extent: int):
        """The first manoeuvre detected at a sample in ``[first, last]``, its extent measured up
        to sample ``extent``: ``(start index, course change deg, speed change or None)``."""
        hits = np.flatnonzero(self.flag[first : last + 1])
        if not hits.size:
            return None
        i = first + int(hits[0])
        h0, v0 = self.h[i], self.v[i]
        win = slice(i + 1, self.end[i] + 1)
        over = (np.abs(self.h[win] - h0) >= MANOEUVRE_COURSE_DEG) | (
            np.abs(self.v[win] - v0) >= self.thr[i]
        )
        cross = i + 1 + int(np.argmax(over))
        seg = slice(i, cross)
        v_tol = MANOEUVRE_START_FRACTION * max(v0, SPEED_FLOOR)
        calm = np.abs(self.h[seg] - h0) <= MANOEUVRE_START_DEG
        calm &= np.abs(self.v[seg] - v0) <= v_tol
        start = i + int(np.flatnonzero(calm)[-1])
        span = slice(start, max(extent, cross) + 1)
        dh = self.h[span] - h0
        dv = self.v[span] - v0
        course = float(dh[np.argmax(np.abs(dh))])
        speed = float(dv[np.argmax(np.abs(dv))] / v0) if v0 > 0 else None
        return start, course, speed


def _side(beta: float) -> str:
    s, c = np.sin(np.radians(beta)), np.cos(np.radians(beta))
    if abs(s) > 1e-12:
        return "starboard" if s > 0 else "port"
    return "ahead" if c > 0 else "astern"


def _crossing(own_xy, target_xy, target_heading) -> str | None:
    """Whether the own ship first crosses the target's heading line ahead of or astern of her."""
    d = own_xy - target_xy
    h = np.radians(target_heading)
    along = d[:, 0] * np.sin(h) + d[:, 1] * np.cos(h)
    lateral = d[:, 0] * np.cos(h) - d[:, 1] * np.sin(h)
    lateral = np.where(np.abs(lateral) < LINE_EPS, 0.0, lateral)  # on the line: rounding
    # a side change from a nonzero lateral offset (starting on the line is not a crossing)
    flips = np.flatnonzero((lateral[:-1] != 0) & (lateral[:-1] * lateral[1:] <= 0))
    if not flips.size:
        return None
    i = int(flips[0])
    f = lateral[i] / (lateral[i] - lateral[i + 1])
    return "ahead" if along[i] + f * (along[i + 1] - along[i]) > 0 else "astern"


def _num(x, digits: int = 3):
    if x is None or not np.isfinite(x):
        return None
    return round(float(x), digits)


def evaluate(
    t,
    own_x,
    own_y,
    own_heading,
    own_speed,
    target_x,
    target_y,
    target_heading,
    target_speed,
    own_length: float,
    target_length=None,
    rule2=None,
    *,
    risk_distance=None,
    horizon_s: float = RISK_HORIZON_S,
    clear_distance=None,
    release_distance=np.inf,
    critical_range=None,
) -> dict:
    """Encounters, manoeuvres and verdicts of a finished run, as plain JSON-ready data.

    ``t`` and the own ship's arrays are ``(n,)``; the targets' are ``(n, k)`` (or ``(n,)`` for
    one target); ``target_length`` (scalar or ``(k,)``) only feeds ``own_in_target_domain_s``.
    ``rule2`` lists the controller's Rule 2 departure records ``{"t", "target", "reason"}``
    (target = index). Defaults: ``risk_distance`` = the domain's semi-major axis ``3.5 L``,
    ``clear_distance`` = ``risk_distance``, ``critical_range`` = ``10 L``.

    Returns ``{"events": [...], "figures": {...}, "thresholds": {...}, "unmatched_rule2":
    [...]}``. Each event is one encounter (a target without one gets a single event of class
    ``none``, ``compliant`` None): ``target``, ``class``, ``onset_s``, ``onset_range_m``,
    ``released_s``, ``cpa_time_s``, ``closest_distance_m``, ``passing_side`` (the side of the
    own ship the target is on at the CPA), ``crossing`` (where the own ship first passes from
    one side of the target's heading line to the other between onset and release: ``ahead`` of
    her bow, ``astern``, or None), ``first_manoeuvre`` (``t``, ``side``, ``course_change_deg``,
    ``speed_change``, ``range_m``, or None), ``domain_intrusion_s``, ``own_in_target_domain_s``,
    ``rule2_departure`` (the records in the encounter, or None), ``compliant``, ``failed_rules``
    and ``excused_rules`` (failures excused by a Rule 2 record). ``figures``:
    :func:`usvtool.metrics.run_distances` (``closest_distance_m`` to any target,
    ``average_distance_m`` to the nearest target over the steps with a latched encounter),
    ``domain_intrusion_s`` (some target inside); distances to 1 mm.
    ``thresholds`` echoes the values used (an infinite ``release_distance`` is null);
    ``unmatched_rule2`` the records that fall in no encounter of their target.
    """
    t = np.asarray(t, float)
    n = len(t)
    own_h = np.asarray(own_heading, float)
    own_v = np.asarray(own_speed, float)
    own_xy = np.stack([np.asarray(own_x, float), np.asarray(own_y, float)], axis=-1)
    tx, ty, th, tv = (
        np.asarray(a, float).reshape(n, -1)
        for a in (target_x, target_y, target_heading, target_speed)
    )
    k = tx.shape[1]
    txy = np.stack([tx, ty], axis=-1)
    length = float(own_length)
    t_len = np.broadcast_to(
        np.asarray(length if target_length is None else target_length, float), (k,)
    )
    risk = onset_distance(length) if risk_distance is None else risk_distance
    r_crit = CRITICAL_RANGE_LENGTHS * length if critical_range is None else float(critical_range)
    sit = assess(own_xy[:, None], own_h[:, None], own_v[:, None], txy, th, tv)
    latched = latch_series(
        sit.cls, sit.dcpa, sit.tcpa, sit.range, risk, horizon_s, clear_distance, release_distance
    )
    inside = in_domain(own_xy[:, None], own_h[:, None], txy, length)
    own_inside = in_domain(txy, th, own_xy[:, None], t_len)
    track = _Track(t, own_h, own_v)
    records = [dict(r) for r in (rule2 or [])]
    matched = [False] * len(records)
    events = []
    for j in range(k):
        col = latched[:, j]
        edges = np.flatnonzero(np.diff(np.concatenate([[0], (col != NONE).astype(int), [0]])))
        if not edges.size:
            events.append(_no_encounter(j, sit.range[:, j]))
            continue
        for on, off in edges.reshape(-1, 2):
            last = off - 1
            window = slice(on, last + 1)
            i_cpa = on + int(np.argmin(sit.range[window, j]))
            mine = [
                q
                for q, r in enumerate(records)
                if int(r.get("target", -1)) == j
                and t[on] <= float(r.get("t", np.nan)) <= t[min(off, n - 1)]
            ]
            for q in mine:
                matched[q] = True
            event = _verdict(
                j,
                int(col[on]),
                t,
                on,
                last,
                off < n,
                i_cpa,
                sit,
                track,
                inside[:, j],
                own_inside[:, j],
                _crossing(own_xy[window], txy[window, j], th[window, j]),
                r_crit,
                [records[q] for q in mine],
            )
            events.append(event)
    distances = metrics.run_distances(own_xy[:, 0], own_xy[:, 1], tx, ty,
                                      (latched != NONE).any(axis=1))  # fmt: skip
    figures = {
        **{name: _num(value) for name, value in distances.items()},
        "domain_intrusion_s": _num(intrusion_time(t, inside) if k else 0.0),
    }
    thresholds = {
        "risk_distance_m": _num(float(np.max(risk))),
        "horizon_s": horizon_s,
        "clear_distance_m": _num(float(np.max(risk if clear_distance is None else clear_distance))),
        "release_distance_m": _num(float(np.max(release_distance))),
        "critical_range_m": _num(r_crit),
        "head_on_bearing_deg": HEAD_ON_BEARING_DEG,
        "stern_sector_deg": list(STERN_SECTOR_DEG),
        "domain_axes_m": [DOMAIN_LENGTH_FACTOR * length, DOMAIN_WIDTH_FACTOR * length],
        "manoeuvre": {
            "course_deg": MANOEUVRE_COURSE_DEG,
            "window_s": MANOEUVRE_WINDOW_S,
            "speed_fraction": MANOEUVRE_SPEED_FRACTION,
        },
        "apparent": {"course_deg": APPARENT_COURSE_DEG, "speed_reduction": APPARENT_SPEED_FRACTION},
        "timely_range_fraction": TIMELY_RANGE_FRACTION,
        "stand_on": {"course_deg": STAND_ON_COURSE_DEG, "speed_fraction": STAND_ON_SPEED_FRACTION},
    }
    unmatched = [r for r, m in zip(records, matched, strict=True) if not m]
    return {
        "events": events,
        "figures": figures,
        "thresholds": thresholds,
        "unmatched_rule2": unmatched,
    }


def _no_encounter(j: int, rng: np.ndarray) -> dict:
    return {
        "target": j,
        "class": "none",
        "onset_s": None,
        "onset_range_m": None,
        "released_s": None,
        "cpa_time_s": None,
        "closest_distance_m": _num(rng.min()) if len(rng) else None,
        "passing_side": None,
        "crossing": None,
        "first_manoeuvre": None,
        "domain_intrusion_s": None,
        "own_in_target_domain_s": None,
        "rule2_departure": None,
        "compliant": None,
        "failed_rules": [],
        "excused_rules": [],
    }


def _verdict(
    j, code, t, on, last, released, i_cpa, sit, track, inside, own_inside, crossing, r_crit, rule2
) -> dict:
    """One encounter's event and verdict (the rules are listed in docs/colregs.md)."""
    rng = sit.range[:, j]
    window = slice(on, last + 1)
    r_on = float(rng[on])
    side = _side(float(sit.beta[i_cpa, j]))
    man = track.manoeuvre(on, i_cpa, i_cpa)
    first = None
    if man is not None:
        s, course, speed = man
        first = {
            "t": _num(t[s]),
            "side": "starboard"
            if course >= MANOEUVRE_COURSE_DEG
            else "port"
            if course <= -MANOEUVRE_COURSE_DEG
            else None,
            "course_change_deg": _num(course),
            "speed_change": _num(speed, 4),
            "range_m": _num(rng[s]),
        }
    intruded = bool(inside[window].any())
    failed = []
    if code in (HEAD_ON, CROSSING_GIVE_WAY, OVERTAKING):
        if man is None:
            failed.append(NO_ACTION)
        else:
            s, course, speed = man
            apparent = abs(course) >= APPARENT_COURSE_DEG or (
                speed is not None and speed <= -APPARENT_SPEED_FRACTION
            )
            if not apparent:
                failed.append(APPARENT)
            r_man = float(rng[s])
            timely = r_man >= TIMELY_RANGE_FRACTION * r_on and (r_man >= r_crit or r_on < r_crit)
            if not timely:
                failed.append(IN_TIME)
        if intruded:
            failed.append(KEEP_CLEAR if code == OVERTAKING else SAFE_DISTANCE)
        if code == HEAD_ON:
            if first is None or first["side"] != "starboard":
                failed.append(STARBOARD_TURN)
            if side != "port":
                failed.append(PORT_TO_PORT)
        if code == CROSSING_GIVE_WAY and crossing == "ahead":
            failed.append(NOT_AHEAD)
    elif code in (CROSSING_STAND_ON, OVERTAKEN):
        below = np.flatnonzero(rng[on : i_cpa + 1] < r_crit)
        i_crit = on + int(below[0]) if below.size else i_cpa + 1
        if i_crit > on:
            keep = slice(on, i_crit)
            dh = np.abs(track.h[keep] - track.h[on]).max()
            dv = np.abs(track.v[keep] - track.v[on]).max()
            if dh > STAND_ON_COURSE_DEG or dv > STAND_ON_SPEED_FRACTION * max(
                track.v[on], SPEED_FLOOR
            ):
                failed.append(STAND_ON)
        late = track.manoeuvre(i_crit, i_cpa, i_cpa) if i_crit <= i_cpa else None
        if late is None and intruded:
            failed.append(IN_EXTREMIS)
        if code == CROSSING_STAND_ON and late is not None and late[1] <= -MANOEUVRE_COURSE_DEG:
            failed.append(NOT_PORT)
    excused = [r for r in failed if rule2 and r in EXCUSABLE]
    failed = [r for r in failed if r not in excused]
    return {
        "target": j,
        "class": CLASS_NAMES[code],
        "onset_s": _num(t[on]),
        "onset_range_m": _num(r_on),
        "released_s": _num(t[last + 1]) if released else None,
        "cpa_time_s": _num(t[i_cpa]),
        "closest_distance_m": _num(rng[i_cpa]),
        "passing_side": side,
        "crossing": crossing,
        "first_manoeuvre": first,
        "domain_intrusion_s": _num(intrusion_time(t[window], inside[window])),
        "own_in_target_domain_s": _num(intrusion_time(t[window], own_inside[window])),
        "rule2_departure": rule2 or None,
        "compliant": not failed,
        "failed_rules": failed,
        "excused_rules": excused,
    }
