"""The part "Against the field's baselines" (usvtool/report/sections/baselines.py) and the
summary's line on it, on a hand-made results table: which groups it covers, each controller's
outcomes (a controller's failure a failure), its medians and its paired comparisons with vo and
sbmpc, the effects and p worked out by hand."""

from __future__ import annotations

import pytest

from usvtool.errors import UsvError
from usvtool.report.data import ENDING, Results, load
from usvtool.report.sections import SECTIONS, baselines, summary
from usvtool.results import Row, write_results

SCENES = range(6)


def _results(tmp_path, rows):
    """The rows as a results table (each run's ``arrived`` True unless given), loaded."""
    said = {(r[0], r[5]) for r in rows}
    ends = {r[:5]: ENDING[r[1]] for r in rows if r[1] in ENDING}
    rows = [*rows, *((*job, metric, "True") for job, metric in ends.items()
                     if (job[0], metric) not in said)]  # fmt: skip
    write_results(tmp_path / "metrics.csv", [Row(*r) for r in rows])
    return load([tmp_path / "metrics.csv"], ("ccdwa", "udwa", "vo", "sbmpc"))


def _run(case, method, **metrics):
    key = f"{case}-{method}"
    return [(key, "runs", case, method, 1, m, str(v)) for m, v in metrics.items()]


def _scene(i):
    return f"emergency/head-on/s{i:03d}"


COMPLIANT = {"compliant": 2, "compliant_excused": 0, "noncompliant": 0, "not_judged": 0}


@pytest.fixture
def results(tmp_path):
    rows = []
    for i in SCENES:
        # vo: arrives at 100 + i s, 20 + i m from the nearest target; sbmpc 10 s later and
        # 20 m further off
        rows += _run(_scene(i), "vo", arrival_time_s=100 + i, closest_distance_m=20 + i)
        rows += _run(_scene(i), "sbmpc", arrival_time_s=110 + i, closest_distance_m=40 + i)
        # udwa: 5 s after vo, 10 m further off; its last scene's run collided
        if i < 5:
            rows += _run(_scene(i), "udwa", arrival_time_s=105 + i, closest_distance_m=30 + i,
                         **COMPLIANT)  # fmt: skip
        else:
            rows += _run(_scene(i), "udwa", arrived=False, collision="ts1",
                         closest_distance_m=1.0, compliant=0, compliant_excused=0,
                         noncompliant=0, not_judged=2)  # fmt: skip
        # a plugin's controller: its program failed in the first scene (not arrived)
        if i == 0:
            rows += _run(_scene(i), "mine", arrived=False, controller_failed=True,
                         closest_distance_m=90.0)  # fmt: skip
        else:
            rows += _run(_scene(i), "mine", arrival_time_s=90 + i, closest_distance_m=25 + i)
    for case in ("imazu/01/s000", "imazu/02/s000"):  # too few for a comparison
        rows += _run(case, "vo", arrival_time_s=300, closest_distance_m=13)
        rows += _run(case, "udwa", arrival_time_s=301, closest_distance_m=33)
    # a family without a baseline, and a bundled scenario: not in the part
    rows += _run("wind/halves/s000", "udwa", arrival_time_s=50)
    rows += _run("emergency-head-on", "vo", arrival_time_s=70)
    return _results(tmp_path, rows)


def texts(table) -> list[list[str]]:
    return [[c.text for c in row] for row in table.rows]


def test_the_groups_are_the_families_where_a_baseline_ran(results):
    found = baselines.standings(results)
    assert [g.name for g in found] == ["emergency", "imazu"]
    assert found[0].baselines == ("vo", "sbmpc") and found[1].baselines == ("vo",)
    # every controller that ran there, the report's order, the plugin's after
    assert [s.method for s in found[0].standings] == ["udwa", "vo", "sbmpc", "mine"]
    assert baselines.standings(results) is found  # computed once


def test_each_controllers_outcomes_count_every_failure(results):
    outcomes, against, every = baselines.section(results).tables()
    assert outcomes.columns == [
        "group", "controller", "runs", "arrived", "collided", "did not arrive", "compliant",
        "excused only", "non-compliant", "not judged", "controller failed"]  # fmt: skip
    rows = texts(outcomes)
    assert [r[:2] for r in rows] == [
        ["emergency", "udwa"], ["", "vo (baseline)"], ["", "sbmpc (baseline)"], ["", "mine"],
        ["imazu", "udwa"], ["", "vo (baseline)"]]  # fmt: skip
    # udwa: 5 arrived, 1 collided (its 2 encounters not judged)
    assert rows[0][2:] == ["6", "5", "1", "0", "10", "0", "0", "2", "0"]
    # the plugin's failed program: did not arrive, and counted as a controller failure
    assert rows[3][2:6] == ["6", "5", "0", "1"] and rows[3][-1] == "1"
    # the medians over the runs that arrived without collision: udwa 105..109 -> 107 (IQR
    # 108 - 106), 30..34 -> 32; mine without its failed run's 90 m: 91..95, 26..30; vo
    # 100..105 -> 102.5 (IQR 103.75 - 101.25)
    rows = [r[2:4] for r in texts(against)]
    assert rows[0] == ["107.0 (2.0)", "32.0 (2.0)"]  # udwa
    assert rows[3] == ["93.0 (2.0)", "28.0 (2.0)"]  # mine
    assert rows[1][0] == "102.5 (2.5)"  # vo
    # sbmpc did not run the imazu cases; 2 paired runs are too few for a comparison
    assert texts(against)[4][4:] == ["-", "-", "did not run", "did not run"]
    assert texts(against)[5][4:] == ["itself", "itself", "did not run", "did not run"]
    assert every.placement == "appendix" and outcomes.placement == against.placement == "main"


def test_the_comparisons_with_each_baseline_by_hand(results):
    every = baselines.section(results).tables()[-1]
    got = {(r[1], r[2], r[3]): r for r in texts(every)}
    assert {r[0] for r in texts(every)} == {"emergency"}  # imazu: 2 runs a side, left out
    # udwa against vo, arrival: 5 s later in 5 scenes and a collision (the worst): every pair
    # worse, r = -1, the interval the point, exact p of 6 pairs all one sign 2 / 2^6; udwa's
    # median (IQR) over 105..109 and the collision (the worst): 107.5 (108.75 - 106.25)
    row = got[("udwa", "vo", "arrival_time_s")]
    assert row[4:] == ["6/6 (1/0)", "108 (2.5)", "102 (2.5)", "W", "r -1.00 [-1.00, -1.00]",
                       f"{2 / 64:.2g}", "worse"]  # fmt: skip
    # closest: 10 m further in 5 scenes (signed ranks tied at 3: W+ 15), the collision the
    # worst (rank 6: W- 6): r = (15 - 6) / 21; p 34/64 by the sign flips' distribution
    row = got[("udwa", "vo", "closest_distance_m")]
    assert row[8].startswith(f"r {9 / 21:+.2f} [") and row[-1] == "n.s."
    assert float(row[9]) > 0.05
    # against sbmpc: 5 s earlier but the collision (r +9/21, n.s.); 10 m closer (worse)
    assert got[("udwa", "sbmpc", "arrival_time_s")][-1] == "n.s."
    assert got[("udwa", "sbmpc", "closest_distance_m")][-1] == "worse"
    # the baselines against each other, both ways
    assert got[("vo", "sbmpc", "arrival_time_s")][-1] == "better"
    assert got[("sbmpc", "vo", "closest_distance_m")][-1] == "better"
    assert ("vo", "vo", "arrival_time_s") not in got
    # the failed program counts as the worst: 5 scenes better by 10 s, one failure
    row = got[("mine", "vo", "arrival_time_s")]
    assert row[4] == "6/6 (1/0)" and row[8].startswith(f"r {9 / 21:+.2f}")
    # the main table gives the same comparisons' outcomes and effects
    against = baselines.section(results).tables()[1]
    assert against.columns[4:] == ["against vo: arrival", "against vo: closest",
                                   "against sbmpc: arrival", "against sbmpc: closest"]
    rows = {r[1]: r[4:] for r in texts(against)[:4]}
    assert rows["udwa"] == ["worse, r -1.00", f"n.s., r {9 / 21:+.2f}",
                            f"n.s., r {9 / 21:+.2f}", "worse, r -1.00"]  # fmt: skip
    assert rows["vo (baseline)"] == ["itself", "itself", "better, r +1.00", "worse, r -1.00"]


def test_the_summary_counts_each_controllers_wins_and_losses(results):
    line = summary.against_baselines(results)
    # udwa: worse in arrival (vo) and closest (sbmpc); vo better in arrival, worse in closest
    # against sbmpc, sbmpc the mirror; mine worse in closest against sbmpc
    assert ("emergency: udwa 0/2 of 4, vo 1/1 of 2, sbmpc 1/1 of 2, mine 0/1 of 4; "
            "imazu: too few paired runs.") in line
    assert line in summary.section(results).paragraphs


def test_the_part_follows_the_imazu_section_and_is_left_out_without_baselines(results):
    names = [m.__name__.rsplit(".", 1)[1] for m in SECTIONS]
    assert names.index("baselines") == names.index("imazu") + 1
    without = Results([j for j in results.jobs if j.method not in baselines.BASELINES], [])
    assert baselines.section(without) is None and summary.against_baselines(without) == ""


def test_a_controller_failure_that_says_it_arrived_is_refused(tmp_path):
    rows = [r for i in SCENES for r in _run(_scene(i), "vo", arrival_time_s=1)]
    rows += _run(_scene(0), "udwa", arrival_time_s=1, controller_failed=True)
    with pytest.raises(UsvError, match="its controller failed, yet its arrived row says True"):
        baselines.section(_results(tmp_path, rows))
