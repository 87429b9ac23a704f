"""COLREGs verdicts of a finished run: its encounters and, per encounter, the rules of its role.

The offline evaluation of a run (the simulation's events JSON): the run latched at once
(:func:`usvtool.sim.tracking.latch_series` on :func:`usvtool.encounter.assess`), then, per
encounter, the first manoeuvre on the sampled own track (:mod:`usvtool.sim.manoeuvres`), its
:class:`Facts` and the rules of its role (:data:`ROLE_RULES`).

Ship domain: the 7 L x 3 L ellipse of :func:`usvtool.encounter.in_domain`. *Domain intrusion*
is the time during which some target is inside (:func:`intrusion_time`, trapezoidal on the
samples).

Rules (:data:`ROLE_RULES`: one row per rule, each a small named test of the encounter's facts
that says whether the rule fails; ``r`` the range, ``r_on`` at onset, ``r_crit`` the critical
range, default ``CRITICAL_RANGE_LENGTHS`` = 10 own lengths)

============================  =========================  ==========================================
role (classes)                rule                       fails when
============================  =========================  ==========================================
give-way (head-on, crossing   ``rule16-no-action``       no manoeuvre from onset to the CPA
give-way, overtaking)         ``rule8-readily-apparent`` it changes course by less than 30°
                                                         (``APPARENT_COURSE_DEG``) and cuts speed
                                                         by less than 50 %
                              ``rule16-in-time``         it starts at ``r < 0.5 r_on``, or at
                                                         ``r < r_crit`` (waived when
                                                         ``r_on < r_crit``)
                              ``rule8-safe-distance``    the target enters the own domain
                              (overtaking:
                              ``rule13-keep-clear``)
head-on                       ``rule14-starboard``       the manoeuvre is no starboard alteration
                              ``rule14-port-to-port``    the target is not on the own port side
                                                         at the CPA
crossing give-way             ``rule15-ahead``           the own ship crosses the target's
                                                         heading line ahead of her bow
stand-on (crossing stand-on,  ``rule17-keep-course-      while ``r ≥ r_crit`` the heading leaves
overtaken)                    speed``                    its onset value by more than 10° or the
                                                         speed by more than 10 %
                              ``rule17b-no-action``      the target enters the own domain and no
                                                         manoeuvre starts once ``r < r_crit``
crossing stand-on             ``rule17c-port-turn``      that manoeuvre is to port
============================  =========================  ==========================================

A Rule 2 departure record of the controller within the encounter excuses the side and stand-on
rules (``excusable`` in the table, :data:`EXCUSABLE`), never Rules 8, 16, 13(a) or 17(b).
Sources, and the readings of the papers, are in docs/colregs.md.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from usvtool import measures
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
    Situation,
    assess,
    in_domain,
)
from usvtool.sim.manoeuvres import (
    MANOEUVRE_COURSE_DEG,
    MANOEUVRE_SPEED_FRACTION,
    MANOEUVRE_WINDOW_S,
    SPEED_FLOOR,
    Manoeuvre,
    Track,
)
from usvtool.sim.tracking import RISK_HORIZON_S, latch_series, onset_distance
from usvtool.trace import Trace

#: Offsets (m) from a target's heading line below this are on it (for ahead/astern crossings).
LINE_EPS = 1e-6
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


# ----------------------------------------------------------------------------- the facts


@dataclass(frozen=True)
class Facts:
    """What the rules of one encounter look at: its latched class ``code``, the range to the
    target at every sample ``rng``, the onset and CPA samples, the critical range, the own
    ``track``, where the target is at the CPA (``passing_side``), where the own ship crosses
    the target's heading line (``crossing``: ``ahead``, ``astern`` or None) and whether the
    target entered the own domain (``intruded``)."""

    code: int
    rng: np.ndarray
    on: int
    i_cpa: int
    r_crit: float
    track: Track
    passing_side: str
    crossing: str | None
    intruded: bool

    @property
    def r_on(self) -> float:
        return float(self.rng[self.on])

    @cached_property
    def manoeuvre(self) -> Manoeuvre | None:
        """The first manoeuvre from the onset to the CPA."""
        return self.track.manoeuvre(self.on, self.i_cpa)

    @cached_property
    def i_crit(self) -> int:
        """The first sample from the onset closer than the critical range (past the CPA: none
        before it)."""
        below = np.flatnonzero(self.rng[self.on : self.i_cpa + 1] < self.r_crit)
        return self.on + int(below[0]) if below.size else self.i_cpa + 1

    @cached_property
    def late_manoeuvre(self) -> Manoeuvre | None:
        """The first manoeuvre once within the critical range, before the CPA."""
        if self.i_crit > self.i_cpa:
            return None
        return self.track.manoeuvre(self.i_crit, self.i_cpa)


# ----------------------------------------------------------------------------- the rules
# Each takes an encounter's facts and says whether the rule fails.


def no_action(f: Facts) -> bool:
    return f.manoeuvre is None


def not_readily_apparent(f: Facts) -> bool:
    m = f.manoeuvre
    if m is None:
        return False
    slowed = m.speed is not None and m.speed <= -APPARENT_SPEED_FRACTION
    return not (abs(m.course) >= APPARENT_COURSE_DEG or slowed)


def not_in_time(f: Facts) -> bool:
    m = f.manoeuvre
    if m is None:
        return False
    r = float(f.rng[m.start])
    return not (r >= TIMELY_RANGE_FRACTION * f.r_on and (r >= f.r_crit or f.r_on < f.r_crit))


def target_in_domain(f: Facts) -> bool:
    return f.intruded


def no_starboard_alteration(f: Facts) -> bool:
    return f.manoeuvre is None or f.manoeuvre.side != "starboard"


def not_port_to_port(f: Facts) -> bool:
    return f.passing_side != "port"


def crosses_ahead(f: Facts) -> bool:
    return f.crossing == "ahead"


def course_or_speed_not_kept(f: Facts) -> bool:
    if f.i_crit <= f.on:  # within the critical range from the onset: nothing to keep
        return False
    dh, dv = f.track.deviation(f.on, f.i_crit)
    speed = f.track.v[f.on]
    return dh > STAND_ON_COURSE_DEG or dv > STAND_ON_SPEED_FRACTION * max(speed, SPEED_FLOOR)


def no_action_in_extremis(f: Facts) -> bool:
    return f.late_manoeuvre is None and f.intruded


def turns_to_port_in_extremis(f: Facts) -> bool:
    m = f.late_manoeuvre
    return m is not None and m.course <= -MANOEUVRE_COURSE_DEG


class Rule(NamedTuple):
    """One row of the rule table: the rule's id (as ``failed_rules`` lists it), the test that
    says it fails, and whether a Rule 2 departure record excuses it."""

    id: str
    fails: Callable[[Facts], bool]
    excusable: bool = False


_GIVE_WAY = (
    Rule(NO_ACTION, no_action),
    Rule(APPARENT, not_readily_apparent),
    Rule(IN_TIME, not_in_time),
)
_STAND_ON = (
    Rule(STAND_ON, course_or_speed_not_kept, excusable=True),
    Rule(IN_EXTREMIS, no_action_in_extremis),
)
#: The rules of each role (by latched class), in the order a verdict lists its failures.
ROLE_RULES: dict[int, tuple[Rule, ...]] = {
    HEAD_ON: (
        *_GIVE_WAY,
        Rule(SAFE_DISTANCE, target_in_domain),
        Rule(STARBOARD_TURN, no_starboard_alteration, excusable=True),
        Rule(PORT_TO_PORT, not_port_to_port, excusable=True),
    ),
    CROSSING_GIVE_WAY: (
        *_GIVE_WAY,
        Rule(SAFE_DISTANCE, target_in_domain),
        Rule(NOT_AHEAD, crosses_ahead, excusable=True),
    ),
    OVERTAKING: (*_GIVE_WAY, Rule(KEEP_CLEAR, target_in_domain)),
    CROSSING_STAND_ON: (*_STAND_ON, Rule(NOT_PORT, turns_to_port_in_extremis, excusable=True)),
    OVERTAKEN: _STAND_ON,
}
#: The rules a Rule 2 departure record excuses.
EXCUSABLE = frozenset(r.id for rules in ROLE_RULES.values() for r in rules if r.excusable)


def judge(facts: Facts, departed: bool) -> tuple[list[str], list[str]]:
    """The rules of the encounter's role that fail: ``(failed, excused)``, the excused ones
    those a Rule 2 departure (``departed``) excuses."""
    failing = [r for r in ROLE_RULES[facts.code] if r.fails(facts)]
    excused = [r.id for r in failing if departed and r.excusable]
    return [r.id for r in failing if r.id not in excused], excused


# ----------------------------------------------------------------------------- evaluation


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


def evaluate(
    trace: Trace,
    lengths,
    rule2=None,
    *,
    risk_distance=None,
    horizon_s: float = RISK_HORIZON_S,
    clear_distance=None,
    release_distance=np.inf,
    critical_range=None,
) -> dict:
    """Encounters, manoeuvres and verdicts of a finished run, as plain JSON-ready data.

    ``trace``: the run, the own ship first, then its ``k`` targets (indexed from 0 in the
    events); ``lengths``: the ships' lengths in the trace's order, the own ship's first (the
    targets' only feed ``own_in_target_domain_s``). ``rule2`` lists the controller's Rule 2
    departure records ``{"t", "target", "reason"}`` (target = index). Defaults:
    ``risk_distance`` = the domain's semi-major axis ``3.5 L``, ``clear_distance`` =
    ``risk_distance``, ``critical_range`` = ``10 L``.

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
    :func:`usvtool.measures.run_distances` (``closest_distance_m`` to any target,
    ``average_distance_m`` to the nearest target over the steps with a latched encounter),
    ``domain_intrusion_s`` (some target inside); distances to 1 mm.
    ``thresholds`` echoes the values used (an infinite ``release_distance`` is null);
    ``unmatched_rule2`` the records that fall in no encounter of their target.
    """
    lengths = np.asarray(lengths, float)
    if lengths.shape != (len(trace.ships),):
        raise ValueError(f"{lengths.size} lengths for the {len(trace.ships)} ships of the trace")
    length = float(lengths[0])
    risk = onset_distance(length) if risk_distance is None else risk_distance
    r_crit = CRITICAL_RANGE_LENGTHS * length if critical_range is None else float(critical_range)
    run = _Run.of(trace, lengths, r_crit)
    sit = run.sit
    latched = latch_series(sit.cls, sit.dcpa, sit.tcpa, sit.range, risk, horizon_s,
                           clear_distance, release_distance)  # fmt: skip
    records = _Records(rule2)
    events = [e for j in range(sit.cls.shape[1]) for e in run.events(j, latched[:, j], records)]
    return {
        "events": events,
        "figures": run.figures(latched),
        "thresholds": _thresholds(
            risk, horizon_s, clear_distance, release_distance, r_crit, length
        ),
        "unmatched_rule2": records.unmatched(),
    }


@dataclass(frozen=True)
class _Run:
    """A run as the verdicts see it: the samples, the own and the targets' positions, their
    situations (:func:`usvtool.encounter.assess`), who is inside whose domain, the own track."""

    t: np.ndarray
    own_xy: np.ndarray
    target_xy: np.ndarray
    target_heading: np.ndarray
    sit: Situation
    inside: np.ndarray
    own_inside: np.ndarray
    track: Track
    r_crit: float

    @classmethod
    def of(cls, trace: Trace, lengths: np.ndarray, r_crit: float) -> _Run:
        """The run of ``trace``, its ships of ``lengths`` (own first)."""
        own_xy = np.stack([trace.x[:, 0], trace.y[:, 0]], axis=-1)
        own_h, own_v = trace.heading[:, 0], trace.speed[:, 0]
        txy = np.stack([trace.x[:, 1:], trace.y[:, 1:]], axis=-1)
        th, tv = trace.heading[:, 1:], trace.speed[:, 1:]
        return cls(
            t=trace.t,
            own_xy=own_xy,
            target_xy=txy,
            target_heading=th,
            sit=assess(own_xy[:, None], own_h[:, None], own_v[:, None], txy, th, tv),
            inside=in_domain(own_xy[:, None], own_h[:, None], txy, lengths[0]),
            own_inside=in_domain(txy, th, own_xy[:, None], lengths[1:]),
            track=Track(trace.t, own_h, own_v),
            r_crit=r_crit,
        )

    def events(self, j: int, latched: np.ndarray, records: _Records) -> list[dict]:
        """The events of target ``j`` from its latched codes: one per encounter, each with the
        Rule 2 records within it; one of class ``none`` when it had none."""
        spans = _spans(latched)
        if not spans:
            return [_no_encounter(j, self.sit.range[:, j])]
        last = len(self.t) - 1
        return [self.event(j, int(latched[on]), on, off,
                           records.take(j, self.t[on], self.t[min(off, last)]))
                for on, off in spans]  # fmt: skip

    def figures(self, latched: np.ndarray) -> dict:
        """The run's distance figures (:func:`usvtool.measures.run_distances`, over the steps
        with a latched encounter) and its domain intrusion, to 1 mm and 1 ms."""
        own, targets = self.own_xy, self.target_xy
        distances = measures.run_distances(own[:, 0], own[:, 1], targets[..., 0], targets[..., 1],
                                          (latched != NONE).any(axis=1))  # fmt: skip
        return {
            **{name: _num(value) for name, value in distances.items()},
            "domain_intrusion_s": _num(
                intrusion_time(self.t, self.inside) if self.inside.shape[1] else 0.0
            ),
        }

    def event(self, j: int, code: int, on: int, off: int, rule2: list[dict]) -> dict:
        """The event and verdict of target ``j``'s encounter of class ``code`` latched from
        sample ``on`` to before ``off`` (``off`` = n: to the end)."""
        t, rng = self.t, self.sit.range[:, j]
        window = slice(on, off)
        i_cpa = on + int(np.argmin(rng[window]))
        crossing = _crossing(self.own_xy[window], self.target_xy[window, j],
                             self.target_heading[window, j])  # fmt: skip
        facts = Facts(code, rng, on, i_cpa, self.r_crit, self.track,
                      _side(float(self.sit.beta[i_cpa, j])), crossing,
                      bool(self.inside[window, j].any()))  # fmt: skip
        failed, excused = judge(facts, bool(rule2))
        m = facts.manoeuvre
        return {
            "target": j,
            "class": CLASS_NAMES[code],
            "onset_s": _num(t[on]),
            "onset_range_m": _num(facts.r_on),
            "released_s": _num(t[off]) if off < len(t) else None,
            "cpa_time_s": _num(t[i_cpa]),
            "closest_distance_m": _num(rng[i_cpa]),
            "passing_side": facts.passing_side,
            "crossing": crossing,
            "first_manoeuvre": None if m is None else {
                "t": _num(t[m.start]),
                "side": m.side,
                "course_change_deg": _num(m.course),
                "speed_change": _num(m.speed, 4),
                "range_m": _num(rng[m.start]),
            },
            "domain_intrusion_s": _num(intrusion_time(t[window], self.inside[window, j])),
            "own_in_target_domain_s": _num(intrusion_time(t[window], self.own_inside[window, j])),
            "rule2_departure": rule2 or None,
            "compliant": not failed,
            "failed_rules": failed,
            "excused_rules": excused,
        }  # fmt: skip


class _Records:
    """The controller's Rule 2 departure records, each handed to the encounters it falls in."""

    def __init__(self, records):
        self.records = [dict(r) for r in (records or [])]
        self.matched = [False] * len(self.records)

    def take(self, j: int, start: float, end: float) -> list[dict]:
        """The records of target ``j`` at a time in ``[start, end]``."""
        mine = [q for q, r in enumerate(self.records) if _within(r, j, start, end)]
        for q in mine:
            self.matched[q] = True
        return [self.records[q] for q in mine]

    def unmatched(self) -> list[dict]:
        """The records that fell in no encounter of their target."""
        return [r for r, m in zip(self.records, self.matched, strict=True) if not m]


def _spans(latched: np.ndarray) -> list[tuple[int, int]]:
    """The encounters of one target's latched codes: ``(onset, first sample after)`` pairs."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], (latched != NONE).astype(int), [0]])))
    return [(int(on), int(off)) for on, off in edges.reshape(-1, 2)]


def _within(record: dict, j: int, start: float, end: float) -> bool:
    """Whether a Rule 2 record is of target ``j`` at a time in ``[start, end]``."""
    return int(record.get("target", -1)) == j and start <= float(record.get("t", np.nan)) <= end


def _thresholds(risk, horizon_s, clear_distance, release_distance, r_crit, length) -> dict:
    """The values the evaluation used (an infinite ``release_distance`` is null)."""
    return {
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


def _side(beta: float) -> str:
    """The side of the own ship a target at relative bearing ``beta`` is on."""
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
