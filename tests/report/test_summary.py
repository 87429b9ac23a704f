"""The report's first page (usvtool/report/sections/summary.py) on a hand-made results table:
what was compared, the headline verdicts from the claims section's own, and the caveats."""

from __future__ import annotations

from dataclasses import replace

from usvtool.report import judging
from usvtool.report.data import load
from usvtool.report.sections import summary
from usvtool.results import Row, write_results


def _rows():
    rows = []
    for i in range(6):  # iwso shorter than wso in env1: holds (every route collision-free)
        for key, env, m, length in (("a", "env1", "iwso", 700), ("b", "env1", "wso", 800),
                                    ("c", "env2", "iwso", 700), ("d", "env2", "wso", 800)):
            rows.append((f"{key}{i}", "routes", env, m, i, "length_m", str(length + i)))
            rows.append((f"{key}{i}", "routes", env, m, i, "collision_free", "True"))
    for i in range(3):  # two kinds of one scene family, and a bundled scenario (all arrived)
        for kind in ("head-on", "crossing", "overtaking"):
            for m in ("udwa", "ccdwa"):
                for metric, value in (("closest_distance_m", "30"), ("arrived", "True")):
                    rows.append((f"{m}-{kind}-{i}", "runs", f"emergency/{kind}/s{i:03d}", m, 1,
                                 metric, value))  # fmt: skip
    rows.append(("single", "runs", "emergency-head-on", "udwa", 1, "closest_distance_m", "30"))
    for f in ("F1", "F2"):
        for s in range(5):
            rows.append((f"{f}-{s}", "functions", f, "iwso", s, "final_cost", "0.1"))
    return rows


def test_the_summary_states_what_was_compared_and_the_claims_own_verdicts(tmp_path):
    write_results(tmp_path / "metrics.csv", [Row(*r) for r in _rows()])
    results = load([tmp_path / "metrics.csv"])
    s = summary.section(results)
    assert s.id == "summary"
    text = s.paragraphs[0]
    assert "24 routes of 2 optimizers and planners (env1, env2: 6 runs a method)" in text
    assert "10 benchmark-function runs of 1 optimizers (F1, F2: 5 runs a method)" in text
    assert ("19 simulated runs of 2 controllers on the scene families emergency (3 kinds x 3 "
            "scenes), paired by scene, and on 1 bundled scenario (one run each") in text
    (table,) = s.tables()
    verdicts = [v for v in judging.paper_verdicts(results) if not v.variant]
    assert [r[0].text for r in table.rows] == [v.claim.id for v in verdicts]
    assert [r[-1].text for r in table.rows] == [v.verdict for v in verdicts]
    row = next(r for r in table.rows if r[0].text == "iwso-shorter")
    assert row[-1].text == judging.HOLDS
    assert row[1].text == "710.873 vs 847.487 m; 927.925 vs 1044.975 m"  # as printed
    # both cases better (p = 2 / 924 each, Holm over the table's two tested p: 4 / 924)
    assert row[2].text.startswith("2/2 better; weakest env")
    # every identical closest distance: ties, inconclusive
    closest = next(r for r in table.rows if r[0].text == "udwa-larger-closest-distance")
    assert closest[-1].text == judging.INCONCLUSIVE
    caveats = s.paragraphs[-1]
    assert caveats.startswith("Caveats.")
    assert "5 runs per function and algorithm against the paper's 25" in caveats
    # 2 tested comparisons (iwso-shorter's): 5 runs against 5 can reach p = 2 / C(10, 5) =
    # 0.0079, times 2 = 0.016 < 0.05 after Holm: not "too few"; with 8 more, 10 x 0.0079 can not
    assert sum(t.p is not None for v in verdicts for t in v.tests) == 2
    assert "too few" not in caveats
    shorter = next(v for v in verdicts if v.claim.id == "iwso-shorter")
    more = [replace(shorter, tests=shorter.tests * 5) if v is shorter else v for v in verdicts]
    assert "25, too few to hold after Holm's correction." in " ".join(
        summary.caveats(results, more))
