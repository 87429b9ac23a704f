"""What each metric's values must be in a results table (:mod:`usvtool.results`), for the
report and ``compare`` to refuse broken numbers rather than read them as words.

The contract (usvtool/results.py, docs/metrics.md) gives each metric one of three kinds:

- :data:`NUMBERS`: a finite number (``nan``, ``inf`` and words are broken output). A value
  that is unknown (no reference route, no target, no arrival) has no row at all;
- :data:`BOOLEANS`: ``True`` or ``False``;
- :data:`WORDS`: any text (what a ship hit, the rules failed, a name).

A metric the contract does not list has no kind here (:func:`kind` gives None): ``compare``
takes it from the baseline (:func:`inferred`), the report does not read such metrics.

>>> valid(NUMBER, "701.5"), valid(NUMBER, "nan"), valid(BOOLEAN, "1"), valid(WORD, "nan")
(True, False, False, True)
"""

from __future__ import annotations

import math

from usvtool.results import Row

NUMBER, BOOLEAN, WORD = "number", "boolean", "word"
#: Reals and counts of ``usvtool metrics`` (docs/metrics.md), the functions' ``final_cost``
#: and the timings (``timings.csv``).
NUMBERS = frozenset({
    "length_m", "length_ratio", "turns", "mot", "fitness", "planning_time_s", "attempt",
    "arrival_time_s", "closest_distance_m", "average_distance_m", "domain_intrusion_s",
    "encounters", "judged", "compliant", "compliant_excused", "noncompliant", "not_judged",
    "closest_distance_rate", "average_distance_rate",
    "final_cost", "wall_time_s", "seed",
})  # fmt: skip
BOOLEANS = frozenset({"collision_free", "arrived", "controller_failed"})
#: ``collision`` names what was hit (a target's name may be anything, ``12`` or ``nan``).
WORDS = frozenset({"collision", "failed_rules", "excused_rules", "reference_controller",
                   "chart", "algorithm", "run", "scenario", "controller"})  # fmt: skip
#: What :func:`refusal` says each kind must be: (one value, several).
EXPECTED = {NUMBER: ("a finite number", "finite numbers"), BOOLEAN: ("True/False", "True/False")}


def kind(metric: str) -> str | None:
    """The contract's kind of ``metric``; None for a metric it does not list."""
    if metric in NUMBERS:
        return NUMBER
    if metric in BOOLEANS:
        return BOOLEAN
    return WORD if metric in WORDS else None


def valid(expected: str | None, value: str) -> bool:
    """Whether ``value`` is one of ``expected`` (None or words: always)."""
    if expected == BOOLEAN:
        return value in ("True", "False")
    if expected == NUMBER:
        try:
            return math.isfinite(float(value))
        except ValueError:
            return False
    return True


def inferred(rows: list[Row]) -> str | None:
    """The kind of a metric the contract does not list, from its values (the baseline's):
    numbers when every one is a finite number, booleans when every one is True/False."""
    for candidate in (BOOLEAN, NUMBER):
        if rows and all(valid(candidate, r.value) for r in rows):
            return candidate
    return None


def invalid(rows: list[Row]) -> list[tuple[int, Row]]:
    """(line, row) of each row of a table (read in file order) whose value is not of its
    metric's contract kind."""
    return [(line, r) for line, r in enumerate(rows, start=2) if not valid(kind(r.metric), r.value)]


def refusal(path, bad: list[tuple[int, Row]], shown: int = 4) -> str:
    """One line refusing the table ``path`` for its :func:`invalid` rows: how many, which
    metrics (the first ``shown``), the first one's line and value."""
    metrics = sorted({r.metric for _, r in bad})
    several = len(bad) > 1
    expected = " or ".join(EXPECTED[k][several] for k in (NUMBER, BOOLEAN)
                           if any(kind(m) == k for m in metrics))  # fmt: skip
    names = ", ".join(metrics[:shown]) + (f" and {len(metrics) - shown} more"
                                          if len(metrics) > shown else "")  # fmt: skip
    line, first = bad[0]
    value = first.value if len(first.value) <= 20 else first.value[:20] + "…"
    return (
        f"{path}: {len(bad)} value{'s are' if several else ' is'} not {expected} "
        f"({names}); line {line}: {first.metric} {value!r}"
    )
