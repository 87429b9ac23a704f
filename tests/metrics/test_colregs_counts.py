"""The COLREGs columns of a run row (usvtool/metrics/tabulate.py, docs/colregs.md "Counting"):
each encounter in exactly one of compliant, compliant_excused, noncompliant and not_judged;
every encounter of a run that did not arrive or collided not judged, never compliant."""

from __future__ import annotations

import numpy as np
import pytest

from usvtool.metrics import RUN_COLUMNS, measure
from usvtool.metrics.tabulate import colregs_counts, verdict
from usvtool.trace import Trace, write_events, write_trace


def encounter(target, compliant, failed=(), excused=(), cls="head-on") -> dict:
    return {"target": target, "class": cls, "onset_s": 1.0, "released_s": 3.0,
            "compliant": compliant, "failed_rules": list(failed),
            "excused_rules": list(excused)}  # fmt: skip


#: A plain pass, one excused only (Rule 14 departed from), one failed with an excused rule
#: beside its failure, a target without an encounter (class none: not counted).
ENCOUNTERS = [
    encounter(0, True),
    encounter(1, True, excused=["rule14-starboard", "rule14-port-to-port"]),
    encounter(2, False, failed=["rule8-readily-apparent"], excused=["rule15-ahead"],
              cls="crossing-give-way"),
    {**encounter(3, None), "class": "none", "onset_s": None, "released_s": None},
]  # fmt: skip


def test_an_arrived_run_splits_its_encounters_four_ways():
    counts = colregs_counts(ENCOUNTERS, completed=True)
    assert counts == {"judged": 3, "compliant": 1, "compliant_excused": 1, "noncompliant": 1,
                      "not_judged": 0, "failed_rules": ["rule8-readily-apparent"],
                      "excused_rules": ["rule14-port-to-port", "rule14-starboard",
                                        "rule15-ahead"]}  # fmt: skip


def test_an_excused_departure_is_not_compliant():
    assert verdict(ENCOUNTERS[1], completed=True) == "compliant_excused"
    assert verdict(ENCOUNTERS[0], completed=True) == "compliant"
    assert verdict(ENCOUNTERS[2], completed=True) == "noncompliant"


def test_an_encounter_without_a_verdict_is_not_judged():
    assert verdict(encounter(0, None), completed=True) == "not_judged"
    counts = colregs_counts([encounter(0, None), encounter(1, True)], completed=True)
    assert (counts["judged"], counts["compliant"], counts["not_judged"]) == (1, 1, 1)


def test_every_encounter_of_a_run_that_failed_is_not_judged():
    counts = colregs_counts(ENCOUNTERS, completed=False)
    assert counts == {"judged": 0, "compliant": 0, "compliant_excused": 0, "noncompliant": 0,
                      "not_judged": 3, "failed_rules": [], "excused_rules": []}  # fmt: skip


def head_on_trace() -> Trace:
    """Own ship north along x = 0 at 1 m/s for 4 s; the target at x = 3 southbound."""
    t = np.arange(5.0)
    own = [[0.0, ti, 0.0, 1.0, 0.0] for ti in t]
    tgt = [[3.0, 4.0 - ti, 180.0, 1.0, 0.0] for ti in t]
    return Trace.from_states(t, ["own", "target"], np.stack([own, tgt], axis=1))


@pytest.mark.parametrize(("arrived", "collision", "expected"), [
    (True, None, (1, 1, 0, 0, 0)),
    (False, None, (0, 0, 0, 0, 1)),  # did not arrive: a failure, its encounter not judged
    (False, "target", (0, 0, 0, 0, 1)),  # collided
    (True, "map", (0, 0, 0, 0, 1)),  # arrived but touched the map: a failure all the same
])  # fmt: skip
def test_the_run_row_counts_by_the_runs_outcome(tmp_path, arrived, collision, expected):
    write_trace(tmp_path / "r.csv", head_on_trace())
    run = {"scenario": "s", "controller": "udwa", "seed": 1, "arrived": arrived,
           "collision": collision, "dt": 1.0}  # fmt: skip
    write_events(tmp_path / "r.json", {"encounters": [ENCOUNTERS[1]], "run": run})
    result = measure([tmp_path / "r.csv"])
    (row,) = result.rows
    names = ("judged", "compliant_excused", "compliant", "noncompliant", "not_judged")
    assert tuple(row[n] for n in names) == expected
    assert row["encounters"] == 1
    header, line = result.to_csv().splitlines()
    cells = dict(zip(header.split(","), line.split(","), strict=True))
    assert cells["excused_rules"] == ("rule14-port-to-port;rule14-starboard" if expected[0]
                                      else "")  # fmt: skip
    assert RUN_COLUMNS.index("judged") < RUN_COLUMNS.index("not_judged")
