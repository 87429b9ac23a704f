"""The regression report's rules: each metric's better direction and tolerance, and the
tolerances file that changes them (:mod:`usvtool.report.regression`).

A group is within its tolerance when ``|change| <= max(relative * |base|, absolute)``; a metric
with no rule (:data:`INFO`) is informational. The tolerances file (YAML)::

    count_timings: false
    metrics:
      length_m: {relative: 0.05}          # the other fields keep their defaults
      my_metric: {better: higher, relative: 0.01, absolute: 0.1}
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from usvtool.errors import UsvError

LOWER, HIGHER, NONE = "lower", "higher", "none"


@dataclass(frozen=True)
class Rule:
    """A metric's better direction (``lower``, ``higher`` or ``none``: informational) and its
    tolerance, ``max(relative * |base|, absolute)``."""

    better: str = NONE
    relative: float = 0.0
    absolute: float = 0.0


INFO = Rule()
RULES: dict[str, Rule] = {
    # routes (usvtool metrics' ROUTE_COLUMNS) and the same metrics of runs
    "length_m": Rule(LOWER, 0.02, 0.01),
    "length_ratio": Rule(LOWER, 0.02, 1e-4),
    "turns": Rule(LOWER, 0.10, 0.5),
    "mot": Rule(LOWER, 0.05, 0.01),
    "fitness": Rule(LOWER, 0.02, 0.01),
    "collision_free": Rule(HIGHER),
    "attempt": INFO,
    # runs (RUN_COLUMNS)
    "arrived": Rule(HIGHER),
    "collision": Rule(LOWER),
    "controller_failed": Rule(LOWER),
    "arrival_time_s": Rule(LOWER, 0.02, 0.1),
    "closest_distance_m": Rule(HIGHER, 0.02, 0.01),
    "average_distance_m": Rule(HIGHER, 0.02, 0.01),
    "domain_intrusion_s": Rule(LOWER, 0.05, 0.1),
    "encounters": INFO,
    "judged": INFO,
    "compliant": Rule(HIGHER),
    "compliant_excused": INFO,
    "noncompliant": Rule(LOWER),
    "not_judged": INFO,
    "failed_rules": INFO,
    "excused_rules": INFO,
    "reference_controller": INFO,
    "closest_distance_rate": Rule(HIGHER, 0.05, 0.01),
    "average_distance_rate": Rule(HIGHER, 0.05, 0.01),
    # functions
    "final_cost": Rule(LOWER, 0.05, 1e-6),
    # timings (timings.csv): reported, counted only with count_timings
    "wall_time_s": Rule(LOWER, 0.25, 0.05),
    "planning_time_s": Rule(LOWER, 0.25, 0.05),
    # the identity columns of usvtool metrics, should a table carry them as metrics
    **dict.fromkeys(("chart", "algorithm", "run", "scenario", "controller", "seed"), INFO),
}


@dataclass(frozen=True)
class Tolerances:
    """The rules in force and whether timings count; ``path`` the file they came from."""

    rules: dict[str, Rule] = field(default_factory=lambda: dict(RULES))
    count_timings: bool = False
    path: str | None = None

    def rule(self, metric: str) -> Rule:
        return self.rules.get(metric, INFO)


def load_tolerances(path: str | None) -> Tolerances:
    """The defaults (:data:`RULES`) updated from the YAML file ``path`` (None: the defaults)."""
    if path is None:
        return Tolerances()
    from usvtool.yamlfile import read_yaml

    data = read_yaml(path)
    data = {} if data is None else data
    if not isinstance(data, dict):
        raise UsvError(f"{path}: must be a mapping with count_timings and metrics")
    unknown = sorted(set(map(str, data)) - {"count_timings", "metrics"})
    if unknown:
        raise UsvError(f"{path}: unknown key {unknown[0]!r} (expected count_timings, metrics)")
    count_timings = data.get("count_timings", False)
    if not isinstance(count_timings, bool):
        raise UsvError(f"{path}: count_timings: must be true or false")
    metrics = data.get("metrics") or {}
    if not isinstance(metrics, dict):
        raise UsvError(f"{path}: metrics: must be a mapping of metric names")
    rules = dict(RULES)
    for name, spec in metrics.items():
        rules[str(name)] = _rule(path, f"metrics.{name}", spec, rules.get(str(name), INFO))
    return Tolerances(rules, count_timings, str(path))


def _rule(path, where: str, spec, default: Rule) -> Rule:
    if not isinstance(spec, dict):
        raise UsvError(f"{path}: {where}: must be a mapping (better, relative, absolute)")
    unknown = sorted(set(map(str, spec)) - {"better", "relative", "absolute"})
    if unknown:
        raise UsvError(f"{path}: {where}: unknown key {unknown[0]!r} "
                       "(expected better, relative, absolute)")  # fmt: skip
    better = spec.get("better", default.better)
    if better not in (LOWER, HIGHER, NONE):
        raise UsvError(f"{path}: {where}.better: {better!r} is not lower, higher or none")
    values = {}
    for key in ("relative", "absolute"):
        value = spec.get(key, getattr(default, key))
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise UsvError(f"{path}: {where}.{key}: {value!r} is not a number")
        if not math.isfinite(value) or value < 0:
            raise UsvError(f"{path}: {where}.{key}: {value!r} must be a finite number >= 0")
        values[key] = float(value)
    return Rule(better, **values)
