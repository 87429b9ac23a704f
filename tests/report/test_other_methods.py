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
        # env1: a plugin's planner, myplan, below both paper methods in every run
        _routes("env1", "myplan", [600, 601, 602, 603, 604, 605])
        + _routes("env1", "iwso", [700, 701, 702, 703, 704, 705])
        + _routes("env1", "wso", [800, 801, 802, 803, 804, 805])
        # one route of myplan elsewhere: too few for a comparison
        + _routes("env2", "myplan", [500]) + _routes("env2", "iwso", [510, 520, 530])
        # the emergency family: mine arrives 1 s before udwa in each of 6 scenes; its third
        # scene's run collided
        + _runs("emergency/head-on", "mine", [10, 20, 30, 40, 50, 60], "arrival_time_s")
        + _runs("emergency/head-on", "udwa", [11, 21, 31, 41, 51, 61], "arrival_time_s")
        + [("emergency/head-on-mine-2", "runs", "emergency/head-on/s002", "mine", 1,
            "collision", "target1")]
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
        ["env1", "6", "0", "602.5 (2.5)", "-", "length: better than 2, worse than 0 of 2"],
        ["env2", "1", "0", "500.0", "-", "-"],
    ]
    assert effects.placement == "appendix"
    # every route of myplan below every one of the rival: Cliff's delta 1, the interval the
    # point, U's exact p 2 / C(12, 6) = 2 / 924 = 0.0022 (uncorrected); env2 left out (n 1)
    assert texts(effects) == [
        ["env1", "iwso", "length_m", "6/6 (0/0)", "602 vs 702", "δ +1.00 [+1.00, +1.00]",
         "0.0022", "better"],
        ["env1", "wso", "length_m", "6/6 (0/0)", "602 vs 802", "δ +1.00 [+1.00, +1.00]",
         "0.0022", "better"],
    ]  # fmt: skip


def test_a_controllers_outcomes_count_failures_and_pair_by_scene(results):
    part = other_methods.section(results).subsections[1]
    outcomes, effects = part.blocks
    rows = texts(outcomes)
    # emergency: 6 runs, 5 arrived, 1 collided, 0 did not arrive; no COLREGs counts (-);
    # arrival median over the 5 that did not fail: 10, 20, 40, 50, 60 -> 40 (IQR 50 - 20)
    assert rows[0][:6] == ["emergency", "6", "5", "1", "0", "-"]
    assert rows[0][-3:-1] == ["40.0 (30.0)", "-"]
    assert rows[1][:2] == ["bundled scenarios", "1"] and rows[1][-1] == "-"
    # paired by scene: 5 differences of -1 s (better) and the collided run's (worst: +inf):
    # signed ranks 1-5 tied at 3 for the five, 6 for the collision: r = (15 - 6) / 21
    ((case, rival, metric, n, medians, effect, p, outcome),) = texts(effects)
    assert (case, rival, metric, n) == ("emergency", "udwa", "arrival_time_s", "6/6 (1/0)")
    assert effect.startswith(f"r {9 / 21:+.2f} [")
    assert outcome == "neither"  # n 6 with a loss: p far above 0.05
