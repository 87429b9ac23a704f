"""One group of both tables compared: its change, its tolerance and its class
(:mod:`usvtool.report.regression`)."""

from __future__ import annotations

from dataclasses import asdict, dataclass

from usvtool.report.regression.sides import Group, Side
from usvtool.report.regression.tolerances import LOWER, NONE, Tolerances
from usvtool.results import TIMING_METRICS

#: The classes, in the order the reports list them.
CLASSES = ("invalid", "regressed", "missing", "improved", "new", "changed", "ok")
FAILING = ("invalid", "regressed", "missing")


@dataclass(frozen=True)
class Comparison:
    """One group of both tables: each side's figure (None: absent) over ``n`` jobs, how many of
    the current values are ``invalid``, the change, the tolerance ``allowed`` and the class
    (:mod:`usvtool.report.regression`)."""

    kind: str
    case: str
    method: str
    metric: str
    timing: bool
    better: str
    aggregate: str
    base: float | str | None
    head: float | str | None
    n_base: int
    n_head: int
    invalid: int
    change: float | None
    relative_change: float | None
    relative: float
    absolute: float
    allowed: float | None
    status: str
    counted: bool

    @property
    def label(self) -> str:
        return f"{self.kind}/{self.case}/{self.method}/{self.metric}"

    def to_dict(self) -> dict:
        data = asdict(self)
        data["class"] = data.pop("status")
        return data


def compare_group(group: Group, base: Side, head: Side, tolerances: Tolerances,
                  kind: str | None) -> Comparison:  # fmt: skip
    metric = group[3]
    rule = tolerances.rule(metric)
    timing = metric in TIMING_METRICS
    b, h = base.figure(group, kind), head.figure(group, kind)
    change = relative_change = allowed = None
    if h is not None and h.invalid:
        status = "invalid"
    elif b is None or h is None:
        status = "new" if b is None else "missing"
    elif isinstance(b.value, str) or isinstance(h.value, str):
        status = "ok" if b.value == h.value else "changed"
    else:
        change = _significant(h.value - b.value)
        relative_change = _significant(change / abs(b.value)) if b.value else None
        allowed = _significant(max(rule.relative * abs(b.value), rule.absolute))
        status = _classify(rule.better, change, allowed)
    return Comparison(
        *group, timing=timing, better=rule.better, aggregate=(b or h).aggregate,
        base=None if b is None else b.value, head=None if h is None else h.value,
        n_base=0 if b is None else b.n, n_head=0 if h is None else h.n,
        invalid=0 if h is None else h.invalid, change=change,
        relative_change=relative_change, relative=rule.relative, absolute=rule.absolute,
        allowed=allowed, status=status,
        counted=not timing or tolerances.count_timings,
    )  # fmt: skip


def _significant(x: float) -> float:
    """``x`` to 12 significant digits, so that a change equal to the tolerance in the files'
    decimals is equal here too (``0.714 - 0.7`` and ``0.02 * 0.7`` are both 0.014)."""
    return float(f"{x:.12g}")


def _classify(better: str, change: float, allowed: float) -> str:
    if abs(change) <= allowed:
        return "ok"
    if better == NONE:
        return "changed"
    worse = change > 0 if better == LOWER else change < 0
    return "regressed" if worse else "improved"
