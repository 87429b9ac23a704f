"""The user's claims (a pipeline's ``claims:``) in the report: written by the batch beside its
results table (claims.json), read beside each table, judged as the papers' are
(usvtool/report/judging.py) in a Holm family of their own, and shown in "Your claims" before the
papers' claims (usvtool/report/sections/your_claims.py), counted apart in the summary. On
hand-made results tables; every expected figure computed by hand."""

from __future__ import annotations

from pathlib import Path

import pytest
from scipy.stats import beta

from usvtool.batch import results_tables
from usvtool.errors import UsvError
from usvtool.pipeline import ClaimSpec, claims_path, claims_text
from usvtool.report import judging
from usvtool.report.data import ENDING, load
from usvtool.report.sections import builders, claims, summary, your_claims
from usvtool.results import Row, write_results


def _table(path: Path, rows, claimed=()) -> Path:
    """The results table of ``rows`` in ``path`` (every route collision-free, every run
    arrived unless a row says otherwise) with ``claimed`` beside it, as the batch writes
    them."""
    said = {(r[0], r[5]) for r in rows}
    ends = {r[:5]: ENDING[r[1]] for r in rows if r[1] in ENDING}
    rows = [*rows, *((*job, metric, "True") for job, metric in ends.items()
                     if (job[0], metric) not in said)]  # fmt: skip
    path.mkdir(parents=True, exist_ok=True)
    results_tables.write(path / "metrics.csv", [Row(*r) for r in rows], [], tuple(claimed))
    return path / "metrics.csv"


def _routes(case, method, values, metric="length_m"):
    return [(f"{case}-{method}-{i}", "routes", case, method, i, metric, str(v))
            for i, v in enumerate(values)]  # fmt: skip


def _runs(group, method, values, metric):
    return [(f"{group}-{method}-{i}", "runs", f"{group}/s{i:03d}", method, 1, metric, str(v))
            for i, v in enumerate(values)]  # fmt: skip


def relative(id_="c", **kw) -> ClaimSpec:
    base = dict(id=id_, kind="routes", method="iwso", rivals=("wso",), metric="length_m",
                better="lower", statistic="median", cases=("env1",))  # fmt: skip
    return ClaimSpec(**{**base, **kw})


def absolute(id_="a", **kw) -> ClaimSpec:
    base = dict(
        id=id_,
        kind="runs",
        method="udwa+",
        rivals=(),
        metric="closest_distance_m",
        better="higher",
        statistic="every",
        cases=("emergency",),
        target=50.0,
    )
    return ClaimSpec(**{**base, **kw})


# iwso all below wso, 6 against 6: U = 0, exact two-sided p = 2 / C(12, 6) = 2 / 924
SEPARATED = (_routes("env1", "iwso", [700, 701, 702, 703, 704, 705])
             + _routes("env1", "wso", [800, 801, 802, 803, 804, 805]))  # fmt: skip


def test_the_batch_writes_the_claims_beside_the_table_and_the_report_reads_them(tmp_path):
    claim = relative()
    table = _table(tmp_path, SEPARATED, [claim])
    assert claims_path(table).read_text() == claims_text([claim])
    results = load([table])
    (read,) = results.claims
    assert (read.id, read.paper, read.kind, read.method, read.rivals, read.cases) == (
        "c",
        "",
        "routes",
        "iwso",
        ("wso",),
        ("env1",),
    )
    # a batch without claims writes an empty list: no earlier batch's claims stay beside it
    _table(tmp_path, SEPARATED)
    assert load([table]).claims == ()
    # a table without claims.json (hand-made, or an older batch's) has none
    claims_path(table).unlink()
    assert load([table]).claims == ()


def test_a_relative_claim_holds_fails_or_is_inconclusive(tmp_path):
    results = load(
        [_table(tmp_path / "a", SEPARATED, [relative("h"), relative("f", better="higher")])]
    )
    held, failed = judging.user_verdicts(results)
    assert held.verdict == judging.HOLDS and failed.verdict == judging.FAILS
    # two comparisons, one Holm family: 2 x 2 / 924 each
    assert held.tests[0].p == failed.tests[0].p == pytest.approx(4 / 924)
    assert held.tests[0].comparison.effect == 1.0 and failed.tests[0].comparison.effect == -1.0
    # 700, 720, 800 against 730, 740: U = 2 of 6; of the C(5, 2) = 10 splits of the ranks, 8
    # are as far from 3 or farther (U <= 2 or >= 4): p = 0.8
    rows = _routes("env1", "iwso", [700, 720, 800]) + _routes("env1", "wso", [730, 740])
    (v,) = judging.user_verdicts(load([_table(tmp_path / "b", rows, [relative()])]))
    assert v.verdict == judging.INCONCLUSIVE and v.tests[0].p == pytest.approx(0.8)
    # wso's routes half a metre longer, interleaved with iwso's: the U test far from
    # significant; the margin, 1 % of wso's median 703 m = 7.03 m: iwso + 7.03 lies above every
    # wso route and iwso - 7.03 below every one, each one-sided U test at its extreme, p = 1 /
    # C(12, 6) = 1 / 924 < 0.05: equivalent
    rows = (_routes("env1", "iwso", [700, 701, 702, 703, 704, 705])
            + _routes("env1", "wso", [700.5, 701.5, 702.5, 703.5, 704.5, 705.5]))  # fmt: skip
    results = load([_table(tmp_path / "e", rows, [relative("same")])])
    (v,) = judging.user_verdicts(results)
    (t,) = v.tests
    assert v.verdict == judging.EQUIVALENT and t.p > 0.05
    assert t.equivalence.margin == pytest.approx(7.03)
    assert t.equivalence.p == pytest.approx(1 / 924)
    section = your_claims.section(results)
    assert ": 1 equivalent. " in section.paragraphs[0]
    row = section.tables()[0].rows[0]
    assert row[4].text.endswith(f"; equivalent within ±7 (TOST p {1 / 924:.2g})")
    assert (row[-1].text, row[-1].css) == ("equivalent", "equivalent")
    # a case without runs of the rival: not tested
    (v,) = judging.user_verdicts(
        load([_table(tmp_path / "c", SEPARATED, [relative(cases=("env1", "env9"))])])
    )
    assert v.verdict == judging.UNTESTED and v.reason == "no runs: env9 (wso)"


def test_an_absolute_claim_with_a_target(tmp_path):
    # udwa+'s closest distances in 4 scenes: 60, 55, 50 meet "50 m or more", 49 does not
    rows = _runs("emergency/head-on", "udwa+", [60, 55, 50, 49], "closest_distance_m")
    results = load([_table(tmp_path / "a", rows, [absolute()])])
    (v,) = judging.user_verdicts(results)
    (t,) = v.tallies
    assert v.verdict == judging.FAILS and (t.met, t.n) == (3, 4)
    assert t.low == pytest.approx(beta.ppf(0.025, 3, 2))  # Clopper-Pearson
    assert t.high == pytest.approx(beta.ppf(0.975, 4, 1))
    # 45 m or more: every run meets it
    (v,) = judging.user_verdicts(load([_table(tmp_path / "b", rows, [absolute(target=45.0)])]))
    assert v.verdict == judging.HOLDS and v.tallies[0].met == 4
    # a run that did not arrive never meets it, whatever its distance
    stopped = rows + [("emergency/head-on-udwa+-0", "runs", "emergency/head-on/s000", "udwa+",
                       1, "arrived", "False")]  # fmt: skip
    (v,) = judging.user_verdicts(load([_table(tmp_path / "c", stopped, [absolute(target=45.0)])]))
    assert v.verdict == judging.FAILS and v.tallies[0].met == 3
    assert v.tallies[0].note == "1 did not arrive"


def test_an_absolute_claim_of_a_share_is_judged_by_its_interval(tmp_path):
    # 10 of 10 runs meet it: the Clopper-Pearson interval is [0.025^(1/10), 1] = [0.6915, 1]
    rows = _runs("emergency/head-on", "udwa+", [60] * 10, "closest_distance_m")
    table = _table(tmp_path / "a", rows, [absolute("x", share=0.69), absolute("y", share=0.7)])
    x, y = judging.user_verdicts(load([table]))
    assert x.tallies[0].low == pytest.approx(0.025 ** (1 / 10))
    assert x.verdict == judging.HOLDS  # 0.6915 >= 0.69
    assert y.verdict == judging.INCONCLUSIVE  # 0.6915 < 0.7 <= 1
    # 2 of 10: the interval's top, beta(0.975; 3, 8) = 0.556, is below 0.7: does not hold
    rows = _runs("emergency/head-on", "udwa+", [60, 60, *[10] * 8], "closest_distance_m")
    (v,) = judging.user_verdicts(load([_table(tmp_path / "b", rows, [absolute(share=0.7)])]))
    assert v.tallies[0].high == pytest.approx(beta.ppf(0.975, 3, 8))
    assert beta.ppf(0.975, 3, 8) == pytest.approx(0.556, abs=1e-3)
    assert v.verdict == judging.FAILS


def test_the_users_claims_are_a_holm_family_apart_from_the_papers(tmp_path):
    # iwso 4 below wso 4 in env1 and env2: p = 2 / C(8, 4) = 2 / 70 each. The papers'
    # iwso-shorter makes both comparisons: corrected 2 x 2 / 70 = 0.057, inconclusive
    rows = [
        r
        for case in ("env1", "env2")
        for r in _routes(case, "iwso", [1, 2, 3, 4]) + _routes(case, "wso", [5, 6, 7, 8])
    ]
    alone = load([_table(tmp_path / "a", rows)])
    papers = {v.claim.id: v for v in judging.paper_verdicts(alone)}
    assert [t.p for t in papers["iwso-shorter"].tests] == pytest.approx([4 / 70, 4 / 70])
    assert papers["iwso-shorter"].verdict == judging.INCONCLUSIVE
    # the user's claim on env1 alone: one comparison, uncorrected 2 / 70 = 0.029: it holds,
    # and the papers' p are the same as without it (not 3 x 2 / 70)
    mine = load([_table(tmp_path / "b", rows, [relative()])])
    (v,) = judging.user_verdicts(mine)
    assert v.verdict == judging.HOLDS and v.tests[0].p == pytest.approx(2 / 70)
    theirs = {v.claim.id: v for v in judging.paper_verdicts(mine)}
    assert [t.p for t in theirs["iwso-shorter"].tests] == pytest.approx([4 / 70, 4 / 70])
    assert [(v.claim.id, v.verdict) for v in judging.paper_verdicts(mine)] == [
        (v.claim.id, v.verdict) for v in judging.paper_verdicts(alone)
    ]


def test_your_claims_come_before_the_papers_and_are_counted_apart(tmp_path):
    table = _table(tmp_path, SEPARATED, [relative("mine"), relative("lost", better="higher")])
    results = load([table])
    parts = [s for s in (b(results) for b in builders()) if s is not None]
    ids = [s.id for s in parts]
    assert ids[:3] == ["summary", "your-claims", "claims"]
    section = next(s for s in parts if s.id == "your-claims")
    table_, cases = section.tables()
    assert table_.id == your_claims.TABLE and cases.placement == "appendix"
    rows = [[c.text for c in row] for row in table_.rows]
    assert [r[0] for r in rows] == ["mine", "lost"]
    assert rows[0][1] == "iwso against wso: length_m lower (median) in env1"
    assert rows[0][-1] == judging.HOLDS and rows[1][-1] == judging.FAILS
    # medians 702.5 and 802.5, IQR 2.5 each, every route measured; the differences iwso - wso,
    # (i - j) - 100 for i, j in 0..5, have the median -100 m (the Hodges-Lehmann shift); the
    # medians' change (802.5 - 702.5) / 802.5 = +12.5 %; U's p, corrected over the two:
    # 2 x 2 / 924 = 0.0043; no route failed: no failures' test
    assert rows[0][2] == "median 702 (2.5) vs 802 (2.5), n 6/6"
    assert rows[0][3].startswith("shift -100 m [") and "; +12.5 % [" in rows[0][3]
    assert rows[0][4] == "Mann-Whitney U p 0.0043, δ 1.00 [1.00, 1.00]"
    assert table_.columns == ["claim", "what it says", "ours", "effect [95 %]", "tests",
                              "verdict"]  # fmt: skip
    # two metric p in the family, no failure: none of the failures'
    assert "The 2 p of these claims' metric comparisons are Holm-corrected together, in " in (
        section.paragraphs[0])
    # the summary: the papers' verdicts and the user's, in two tables, counted apart
    page1 = next(s for s in parts if s.id == "summary")
    yours = next(t for t in page1.tables() if t.id == "summary-your-verdicts")
    assert yours.title == "Your 2 claims: 1 holds, 1 does not hold"
    assert yours.placement == "html"  # page 1 stays the papers'; a line counts the user's
    assert any(
        p.startswith("Your 2 claims (") and p.endswith(": 1 holds, 1 does not hold.")
        for p in page1.paragraphs
    )
    assert claims.counts(parts, your_claims.TABLE) == {
        judging.HOLDS: 1, judging.FAILS: 1, judging.EQUIVALENT: 0, judging.INCONCLUSIVE: 0,
        judging.UNTESTABLE: 0, judging.UNTESTED: 0}  # fmt: skip
    papers = claims.counts(parts)
    assert sum(papers.values()) == len(judging.paper_verdicts(results)) - sum(
        v.variant for v in judging.paper_verdicts(results)
    )
    # no claims: no section, no table on page 1
    plain = load([_table(tmp_path / "plain", SEPARATED)])
    assert your_claims.section(plain) is None
    page1 = summary.section(plain)
    assert "summary-your-verdicts" not in {t.id for t in page1.tables()}
    assert not any(p.startswith("Your ") for p in page1.paragraphs)


def test_two_tables_with_one_claim_two_ways_are_refused_in_one_line(tmp_path):
    one = _table(tmp_path / "one", _routes("env1", "iwso", [1]), [relative()])
    two = _table(tmp_path / "two", _routes("env2", "iwso", [1]), [relative(cases=("env2",))])
    with pytest.raises(UsvError) as info:
        load([one, two])
    assert str(info.value) == (
        f"{claims_path(two)}: claim 'c' is also in {claims_path(one)}, with another cases "
        "(['env2'], there ['env1']): give each claim its own id"
    )
    # the same claim in both: judged once
    _table(tmp_path / "two", _routes("env2", "iwso", [1]), [relative()])
    assert len(load([one, two]).claims) == 1


def test_a_bad_claims_file_is_one_line_naming_the_field(tmp_path):
    table = _table(tmp_path, SEPARATED, [relative()])
    path = claims_path(table)
    path.write_text(path.read_text().replace('"lower"', '"less"'))
    with pytest.raises(UsvError) as info:
        load([table])
    assert str(info.value) == f"{path}: claims[0].better: must be lower or higher, not 'less'"


def test_a_hand_made_table_without_claims_reads_as_before(tmp_path):
    write_results(tmp_path / "metrics.csv", [Row(*r) for r in SEPARATED])
    assert load([tmp_path / "metrics.csv"]).claims == ()
