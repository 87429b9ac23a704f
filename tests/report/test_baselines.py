"""The part "Against the field's baselines" (usvtool/report/sections/baselines.py) and the
summary's line on it, on a hand-made results table: which groups it covers, each controller's
outcomes (a controller's failure a failure), its medians over the measured runs and its paired
comparisons with vo and sbmpc (the failures by exact McNemar, the metrics on the pairs where
both runs measured them), the effects and p worked out by hand."""

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
    # the medians over the measured runs (a run that collided or whose controller failed
    # measures nothing): udwa 105..109 -> 107 (IQR 108 - 106), its collided run's 1 m left
    # out: 30..34 -> 32; mine without its failed program's 90 m: 91..95, 26..30; vo 100..105
    # -> 102.5 (IQR 103.75 - 101.25)
    rows = [r[2:4] for r in texts(against)]
    assert rows[0] == ["107.0 (2.0)", "32.0 (2.0)"]  # udwa
    assert rows[4] == ["93.0 (2.0)", "28.0 (2.0)"]  # mine, after its row against sbmpc
    assert rows[2][0] == "102.5 (2.5)"  # vo
    # sbmpc did not run the imazu cases: no row against it; 2 paired runs are too few for a
    # comparison; vo alone there has no other baseline
    assert texts(against)[6][1:] == ["udwa", "301.0 (0.0)", "33.0 (0.0)", "vo", "-", "-", "-"]
    assert texts(against)[7][1:] == ["vo (baseline)", "300.0 (0.0)", "13.0 (0.0)", "-", "-",
                                     "-", "-"]  # fmt: skip
    assert every.placement == "appendix" and outcomes.placement == against.placement == "main"


def test_the_comparisons_with_each_baseline_by_hand(results):
    every = baselines.section(results).tables()[-1]
    assert every.columns == [
        "group", "controller", "baseline", "metric", "medians (IQR); runs entered",
        "effect [95 %]; change %", "test: p (uncorrected), rank effect [95 %]", "failures",
        "outcome"]  # fmt: skip
    got = {(r[1], r[2], r[3]): r for r in texts(every)}
    assert {r[0] for r in texts(every)} == {"emergency"}  # imazu: 2 runs a side, left out
    # udwa against vo, arrival: the collided scene measures nothing and leaves the test: 5
    # pairs, udwa 5 s later in each: r = -1, its bootstrap interval the point; exact p of 5
    # pairs all one sign 2 / 2^5 = 0.0625, not significant. Medians over the 5 pairs: 105..109
    # -> 107 (IQR 2), 100..104 -> 102 (2). The shift +5 s: with 5 pairs no 95 %
    # distribution-free interval exists (the smallest two-sided p is 1/16), so it is
    # unbounded; the medians' change -(107 - 102) / 102 = -4.9 %. The failures: udwa's one
    # collision against none, one discordant pair: McNemar p = 1
    row = got[("udwa", "vo", "arrival_time_s")]
    assert row[4] == "107 (2) vs 102 (2); 5 of 6 pairs measured"
    assert row[5].startswith("shift 5 s [-inf, inf]; -4.9 % [")
    assert row[6] == f"Wilcoxon signed-rank p {2 / 32:.2g}, r -1.00 [-1.00, -1.00]"
    assert row[7:] == ["failed 1/6 vs 0/6, McNemar p 1", "n.s."]
    # closest: the collided run's 1 m left out as well: 10 m further in the 5 pairs, r +1,
    # p 2/32, n.s.; change (32 - 22) / 22 = +45.5 %
    row = got[("udwa", "vo", "closest_distance_m")]
    assert row[4] == "32 (2) vs 22 (2); 5 of 6 pairs measured"
    assert row[5].startswith("shift 10 m [-inf, inf]; +45.5 % [")
    assert row[6].startswith(f"Wilcoxon signed-rank p {2 / 32:.2g}, r 1.00")
    assert row[-1] == "n.s."
    # against sbmpc: 5 s earlier, 10 m closer in the same 5 pairs: both n.s. (p 2/32)
    assert got[("udwa", "sbmpc", "arrival_time_s")][-1] == "n.s."
    assert got[("udwa", "sbmpc", "closest_distance_m")][-1] == "n.s."
    # the baselines against each other, both ways: 6 pairs all one sign, p = 2/64 = 0.031,
    # shift 10 s [10, 10] (6 pairs reach a 95 % interval: 2/64 < 0.05); no run failed
    row = got[("vo", "sbmpc", "arrival_time_s")]
    assert row[4:] == ["102 (2.5) vs 112 (2.5); 6 of 6 pairs measured",
                       row[5], f"Wilcoxon signed-rank p {2 / 64:.2g}, r 1.00 [1.00, 1.00]",
                       "-", "better"]  # fmt: skip
    assert row[5].startswith("shift -10 s [-10, -10]; +8.9 % [")  # (112.5 - 102.5) / 112.5
    assert got[("sbmpc", "vo", "closest_distance_m")][-1] == "better"
    assert got[("vo", "sbmpc", "closest_distance_m")][-1] == "worse"
    assert ("vo", "vo", "arrival_time_s") not in got
    # the failed program measures nothing: 5 pairs 10 s earlier (r +1, p 2/32, n.s.), its
    # failure against none (McNemar p 1)
    row = got[("mine", "vo", "arrival_time_s")]
    assert row[4] == "93 (2) vs 103 (2); 5 of 6 pairs measured"
    assert row[6].startswith("Wilcoxon signed-rank p 0.062, r 1.00")
    assert row[7:] == ["failed 1/6 vs 0/6, McNemar p 1", "n.s."]
    # the main table gives the same comparisons in short: the outcome, the shift in units with
    # the medians' change, r; the failures beside, a row per baseline
    against = baselines.section(results).tables()[1]
    assert against.columns == ["group", "controller", "arrival (s): median (IQR)",
                               "closest (m): median (IQR)", "against", "arrival", "closest",
                               "failures"]  # fmt: skip
    rows = [r[4:] for r in texts(against)]
    assert rows[0] == ["vo", "n.s., +5 s (-4.9 %), r -1.00", "n.s., +10 m (+45.5 %), r +1.00",
                       "failed 1/6 vs 0/6, McNemar p 1"]  # udwa  # fmt: skip
    # udwa against sbmpc: (112 - 107) / 112 = +4.5 %, (32 - 42) / 42 = -23.8 %
    assert rows[1] == ["sbmpc", "n.s., -5 s (+4.5 %), r +1.00",
                       "n.s., -10 m (-23.8 %), r -1.00", "failed 1/6 vs 0/6, McNemar p 1"]
    # vo against sbmpc over all 6: (112.5 - 102.5) / 112.5 = +8.9 %, (22.5 - 42.5) / 42.5
    assert rows[2] == ["sbmpc", "better, -10 s (+8.9 %), r +1.00",
                       "worse, -20 m (-47.1 %), r -1.00", "none failed"]  # fmt: skip
    cells = against.rows[2]
    assert (cells[5].css, cells[6].css) == ("holds", "fails")


def test_failing_every_run_is_worse_with_nothing_measured(tmp_path):
    # crash collides in each of vo's 6 scenes: no pair measures either metric, but its 6
    # failures against none are 6 discordant pairs all one way: McNemar's exact p = 2 / 2^6
    rows = []
    for i in SCENES:
        rows += _run(_scene(i), "vo", arrival_time_s=100 + i, closest_distance_m=20 + i)
        rows += _run(_scene(i), "crash", arrived=False, collision="ts1", closest_distance_m=0.5)
    (found,) = baselines.standings(_results(tmp_path, rows))
    crash = next(s for s in found.standings if s.method == "crash")
    assert baselines.record(crash) == (0, 2, 0, 2)
    tests = {m: t for _, m, t in crash.tests}
    assert tests["arrival_time_s"].statistic is None
    assert tests["arrival_time_s"].failures.p == pytest.approx(2 / 64)
    row = next(r for r in baselines.against_table([found]).rows if r[1].text == "crash")
    assert [c.text for c in row[2:]] == ["-", "-", "vo", "worse", "worse",
                                         f"failed 6/6 vs 0/6, McNemar p {2 / 64:.2g}"]
    assert row[-1].css == "fails"


def test_the_summary_counts_each_controllers_wins_and_losses(results):
    line = summary.against_baselines(results)
    # udwa and mine: every comparison n.s. (5 measured pairs: p 2/32; the one failure: p 1);
    # vo better in arrival, worse in closest against sbmpc, sbmpc the mirror
    assert ("emergency: udwa 0/0 of 4, vo 1/1 of 2, sbmpc 1/1 of 2, mine 0/0 of 4; "
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


def test_the_part_says_whose_rules_judge_and_why_no_published_judge_is_beside_them(results):
    from pathlib import Path

    part = baselines.section(results)
    assert baselines.JUDGES in part.paragraphs
    root = Path(__file__).parents[2]
    # the docs it points to say the same: neither published judge built, the monitor refused
    assert "neither judge is implemented" in (root / "docs" / "judges.md").read_text()
    row = next(line for line in (root / "docs" / "design-changes.md").read_text().splitlines()
               if "commonocean-rules" in line)
    assert "does not install beside them" in row and "ours alone" in row
