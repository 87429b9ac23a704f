"""The part of the methods that are not the papers' (usvtool/report/sections/other_methods.py)
on hand-made results: which methods get one, their outcomes per group of cases, and their
effects against each paper method by the judging module's comparison, computed by hand."""

from __future__ import annotations

import pytest

from usvtool.report.data import ENDING, load
from usvtool.report.sections import builders, other_methods
from usvtool.results import Row, write_results


def _results(tmp_path, rows):
    said = {(r[0], r[5]) for r in rows}
    ends = {r[:5]: ENDING[r[1]] for r in rows if r[1] in ENDING}
    rows = [*rows, *((*job, metric, "True") for job, metric in ends.items()
                     if (job[0], metric) not in said)]  # fmt: skip
    write_results(tmp_path / "metrics.csv", [Row(*r) for r in rows])
    return load([tmp_path / "metrics.csv"], ("iwso", "wso", "udwa"))


def _routes(case, method, values, metric="length_m"):
    return [(f"{case}-{method}-{i}-{metric}", "routes", case, method, i, metric, str(v))
            for i, v in enumerate(values)]  # fmt: skip


def _runs(case, method, values, metric):
    return [(f"{case}-{method}-{i}", "runs", f"{case}/s{i:03d}", method, 1, metric, str(v))
            for i, v in enumerate(values)]  # fmt: skip


def texts(table) -> list[list[str]]:
    return [[c.text for c in row] for row in table.rows]


@pytest.fixture
def results(tmp_path):
    rows = (
        # env1: a plugin's planner, myplan, below iwso in every route, and within half a metre
        # of wso's
        _routes("env1", "myplan", [600, 601, 602, 603, 604, 605])
        + _routes("env1", "iwso", [700, 701, 702, 703, 704, 705])
        + _routes("env1", "wso", [600.5, 601.5, 602.5, 603.5, 604.5, 605.5])
        # one route of myplan elsewhere: too few for a comparison
        + _routes("env2", "myplan", [500]) + _routes("env2", "iwso", [510, 520, 530])
        # the emergency family, 8 scenes: mine arrives 1 s before udwa and passes 10 m
        # further off in each; its third scene's run collided; udwa's last never arrived (no
        # arrival time; its closest distance, 27 m, measured)
        + _runs("emergency/head-on", "mine", [10, 20, 30, 40, 50, 60, 70, 80], "arrival_time_s")
        + _runs("emergency/head-on", "udwa", [11, 21, 31, 41, 51, 61, 71], "arrival_time_s")
        + _runs("emergency/head-on", "mine", [30 + i for i in range(8)], "closest_distance_m")
        + _runs("emergency/head-on", "udwa", [20 + i for i in range(8)], "closest_distance_m")
        + [("emergency/head-on-mine-2", "runs", "emergency/head-on/s002", "mine", 1,
            "collision", "target1"),
           ("emergency/head-on-udwa-7", "runs", "emergency/head-on/s007", "udwa", 1,
            "arrived", "False")]
        # a bundled scenario: shown together, never compared
        + [("b1", "runs", "emergency-head-on", "mine", 1, "arrival_time_s", "70")]
    )  # fmt: skip
    return _results(tmp_path, rows)


def test_only_the_methods_no_paper_names_get_a_part(results):
    assert other_methods.others(results) == ["myplan", "mine"]
    assert {"iwso", "wso", "udwa", "ccdwa", "issa", "pso-issa"} <= other_methods.PAPER_METHODS
    assert not {"udwa+", "iwso+g", "anyangle", "pso"} & other_methods.PAPER_METHODS
    section = other_methods.section(results)
    assert [s.id for s in section.subsections] == ["other-myplan", "other-mine"]
    # placed among the methods' sections, after the papers' claims
    ids = [s.id for s in (b(results) for b in builders()) if s is not None]
    assert ids.index("other-methods") > ids.index("claims")
    assert other_methods.section(_empty(results)) is None


def _empty(results):
    from usvtool.report.data import Results

    return Results([j for j in results.jobs if j.method in ("iwso", "wso")], [])


def test_a_planners_outcomes_and_effects_against_each_paper_method(results):
    part = other_methods.section(results).subsections[0]
    outcomes, effects = part.blocks
    assert outcomes.id == "other-myplan-routes" and outcomes.placement == "main"
    # median of 600..605 = 602.5 (IQR 603.75 - 601.25 = 2.5); one route: itself; turns: none
    assert texts(outcomes) == [
        ["env1", "6", "0", "602.5 (2.5)", "-",
         "length: better than 1, worse than 0, equivalent to 1 of 2"],
        ["env2", "1", "0", "500.0", "-", "-"],
    ]  # fmt: skip
    assert effects.placement == "appendix"
    assert effects.columns == [
        "cases", "paper method", "metric", "medians (IQR); runs entered",
        "effect [95 %]; change %", "test: p (uncorrected), rank effect [95 %]", "failures",
        "outcome"]  # fmt: skip
    iwso, wso = texts(effects)  # env2 left out (n 1)
    # every route of myplan below every one of iwso's: Cliff's delta 1, the interval the
    # point, U's exact p 2 / C(12, 6) = 2 / 924 = 0.0022 (uncorrected); every difference
    # myplan - iwso is (i - j) - 100 for i, j in 0..5: their median, the Hodges-Lehmann
    # shift, -100 m; the medians' change (702.5 - 602.5) / 702.5 = +14.2 %; no route failed
    assert iwso[:5] == ["env1", "iwso", "length_m", "602 (2.5) vs 702 (2.5); n 6/6",
                        iwso[4]]  # fmt: skip
    assert iwso[4].startswith("shift -100 m [") and "; +14.2 % [" in iwso[4]
    assert iwso[5:] == ["Mann-Whitney U p 0.0022, δ 1.00 [1.00, 1.00]", "-", "better"]
    # wso's routes half a metre longer, interleaved with myplan's: the differences (i - j) -
    # 0.5 have the median -0.5 m, change (603 - 602.5) / 603 = +0.1 %, the U test far from
    # significant. The margin, 1 % of wso's median 603 m = 6.03 m: myplan + 6.03 lies above
    # every wso route and myplan - 6.03 below every one, each one-sided U test at its extreme,
    # p = 1 / C(12, 6) = 1 / 924 = 0.0011: equivalent
    assert wso[3] == "602 (2.5) vs 603 (2.5); n 6/6"
    assert wso[4].startswith("shift -0.5 m [") and "; +0.1 % [" in wso[4]
    test, p = wso[5].split(", δ ")[0].rsplit(" p ", 1)
    assert test == "Mann-Whitney U" and float(p) > 0.05
    assert wso[5].endswith(f"; equivalent within ±6 (TOST p {1 / 924:.2g})")
    assert wso[6:] == ["-", "equivalent"]
    assert effects.rows[1][-1].css == "equivalent"


def test_a_controllers_outcomes_count_failures_and_pair_by_scene(results):
    part = other_methods.section(results).subsections[1]
    outcomes, effects = part.blocks
    rows = texts(outcomes)
    # emergency: 8 runs, 7 arrived, 1 collided, 0 did not arrive; no COLREGs counts (-);
    # arrival over the 7 that arrived: 10, 20, 40, 50, 60, 70, 80 -> 50 (IQR 65 - 30);
    # closest without the collided run's: 30, 31, 33, ..., 37 -> 34 (IQR 35.5 - 32)
    assert rows[0][:6] == ["emergency", "8", "7", "1", "0", "-"]
    assert rows[0][-3:] == ["50.0 (35.0)", "34.0 (3.5)",
                            "arrival: better than 1, worse than 0 of 1; closest: better than "
                            "1, worse than 0 of 1"]  # fmt: skip
    assert rows[1][:2] == ["bundled scenarios", "1"] and rows[1][-1] == "-"
    arrival, closest = texts(effects)
    # arrival, paired by scene: scene 2 (mine collided) and scene 7 (udwa never arrived)
    # measure no time: 6 pairs, each 1 s earlier: r +1, exact p 2 / 2^6 = 0.031; the shift
    # -1 s [-1, -1]; medians over the pairs 10, 20, 40, 50, 60, 70 -> 45 (IQR 57.5 - 25)
    # and 46 (32.5); change (46 - 45) / 46 = +2.2 %. Failures: one each, in other scenes:
    # two discordant pairs split 1 / 1, McNemar p = 1
    assert arrival[:4] == ["emergency", "udwa", "arrival_time_s",
                           "45 (32.5) vs 46 (32.5); 6 of 8 pairs measured"]  # fmt: skip
    assert arrival[4].startswith("shift -1 s [-1, -1]; +2.2 % [")
    assert arrival[5:] == [f"Wilcoxon signed-rank p {2 / 64:.2g}, r 1.00 [1.00, 1.00]",
                           "failed 1/8 vs 1/8, McNemar p 1", "better"]  # fmt: skip
    # closest: udwa's run that never arrived keeps its 27 m; only scene 2 leaves: 7 pairs,
    # each 10 m further: p 2 / 2^7 = 0.016; medians 34 (3.5) and 24 (3.5), change +41.7 %
    assert closest[3] == "34 (3.5) vs 24 (3.5); 7 of 8 pairs measured"
    assert closest[4].startswith("shift 10 m [10, 10]; +41.7 % [")
    assert closest[5:] == [f"Wilcoxon signed-rank p {2 / 128:.2g}, r 1.00 [1.00, 1.00]",
                           "failed 1/8 vs 1/8, McNemar p 1", "better"]  # fmt: skip


def test_a_metric_no_run_wrote_is_left_out_but_failing_everywhere_is_not(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    # mine and udwa with arrival times only: no closest distance to compare
    rows = (_runs("emergency/head-on", "mine", [10, 20, 30], "arrival_time_s")
            + _runs("emergency/head-on", "udwa", [11, 21, 31], "arrival_time_s"))  # fmt: skip
    found = other_methods.comparisons(_results(tmp_path / "a", rows), "runs", "mine",
                                      "emergency")  # fmt: skip
    assert [(rival, metric) for rival, metric, _ in found] == [("udwa", "arrival_time_s")]
    # mine collided in each of 3 scenes: nothing measured, yet the failures (3 against none,
    # McNemar p 2 / 2^3 = 0.25) are compared on both metrics the table has
    rows = (_runs("emergency/head-on", "udwa", [11, 21, 31], "arrival_time_s")
            + _runs("emergency/head-on", "udwa", [5, 6, 7], "closest_distance_m")
            + _runs("emergency/head-on", "mine", [0.1, 0.2, 0.3], "closest_distance_m")
            + [(f"emergency/head-on-mine-{i}", "runs", f"emergency/head-on/s{i:03d}", "mine",
                1, "collision", "target1") for i in range(3)])  # fmt: skip
    found = other_methods.comparisons(_results(tmp_path / "b", rows), "runs", "mine",
                                      "emergency")  # fmt: skip
    assert [metric for _, metric, _ in found] == ["arrival_time_s", "closest_distance_m"]
    assert all(t.statistic is None and t.failures.p == pytest.approx(0.25) for *_, t in found)
    assert {t.outcome for *_, t in found} == {"missing"}
