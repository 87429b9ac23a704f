"""The benchmark functions' tables (usvtool/report/sections/benchmark_functions.py, published.py)
on a hand-made results table: small figures never print as 0.00, and our number of runs stands
beside the paper's."""

from __future__ import annotations

from usvtool.report.data import load
from usvtool.report.document import number
from usvtool.report.papers import TABLES
from usvtool.report.sections import benchmark_functions, published
from usvtool.results import Row, write_results

#: GWO's F3 over 5 seeds: mean (0.001 + 0.002 + 0.003 + 0.0035 + 0.00415) / 5 = 0.00273.
GWO_F3 = ("0.001", "0.002", "0.003", "0.0035", "0.00415")


def results(tmp_path):
    rows = [Row(f"g{s}", "functions", "F3", "gwo", s, "final_cost", v)
            for s, v in enumerate(GWO_F3)]  # fmt: skip
    write_results(tmp_path / "metrics.csv", rows)
    return load([tmp_path / "metrics.csv"])


def cells(table, method: str, case: str) -> dict[str, list[str]]:
    """The row's texts by heading (repeated headings, "paper", in order)."""
    row = next(r for r in table.rows if r[0].text == method and r[1].text == case)
    out: dict[str, list[str]] = {}
    for heading, cell in zip(table.columns, row, strict=True):
        out.setdefault(heading, []).append(cell.text)
    return out


def test_the_number_rule_never_prints_a_non_zero_as_zero():
    # at least two significant digits from 1e-3 to 1, scientific with three below and from 1e6
    assert [number(v, 2).text for v in (0.00273, 0.1, 0.0999, 0.0, 1.5, 9e-4)] == [
        "0.0027", "0.10", "0.100", "0.00", "1.50", "9.00e-04"]  # fmt: skip
    assert [number(v, 3).text for v in (0.0273, 0.00999, 2.5e6)] == ["0.027", "0.0100",
                                                                      "2.50e+06"]  # fmt: skip
    for digits in range(5):
        for v in (1e-9, 3e-4, 0.004, 0.04, 0.4, -0.004):
            shown = number(v, digits).text
            assert float(shown) != 0 and abs(float(shown) - v) <= 0.01 * abs(v), (v, digits)


def test_table_1_shows_our_small_mean_with_its_digits_and_our_runs_beside_the_papers(tmp_path):
    table = published.table(results(tmp_path), TABLES["iwso-dwa-table-1"])
    row = cells(table, "gwo", "F3")
    assert row["runs"] == ["5"] and row["paper"][0] == "25"
    assert row["Mean"] == ["0.0027"] and row["paper"][3] == "2.73e-3"  # ours, the paper's
    assert row["Best"] == ["0.0010"] and row["Worst"] == ["0.0042"]
    assert "the paper's: 25 each" in table.caption


def test_the_section_says_how_many_runs_we_have_and_the_paper_had(tmp_path):
    section = benchmark_functions.section(results(tmp_path))
    assert "5 run(s) each (the paper's Table 1 25" in section.paragraphs[0]
    ours = cells(section.blocks[0], "gwo", "F3")  # Table 1 with ours beside the paper's
    assert ours["runs"] == ["5"] and ours["Mean"] == ["0.0027"]
    # every row of ours is Table 1's: the second table repeats none, and says so in the HTML
    rest = section.blocks[-1]
    assert [b.id for b in section.blocks] == ["paper-iwso-dwa-table-1", "functions-table"]
    assert rest.rows == [] and rest.placement == "html"
    assert rest.caption.startswith("None: every optimizer and function of our runs is in Table 1")


def test_the_every_optimizer_table_shows_only_what_table_1_does_not(tmp_path):
    rows = [Row(f"g{s}", "functions", "F3", "gwo", s, "final_cost", v)
            for s, v in enumerate(GWO_F3)]  # fmt: skip
    rows += [Row("i1", "functions", "F3", "issa", 1, "final_cost", "0.5"),  # no Table 1 column
             Row("g6", "functions", "F6", "gwo", 1, "final_cost", "2.0")]  # F6: n/c in Table 1
    write_results(tmp_path / "metrics.csv", rows)
    section = benchmark_functions.section(load([tmp_path / "metrics.csv"]))
    rest = section.blocks[-1]
    assert rest.id == "functions-table"
    assert [(r[0].text, r[1].text) for r in rest.rows] == [("F3", "issa"), ("F6", "gwo")]
    assert ("Left to Table 1 above (ours beside the paper's), not repeated here: gwo on the "
            "functions it compares; on F6, which it marks n/c, every optimizer is here."
            ) in rest.caption  # fmt: skip


def _table(tmp_path, values: dict[tuple[str, str], tuple[str, ...]]):
    rows = [Row(f"{f}{a}{s}", "functions", f, a, s, "final_cost", v)
            for (f, a), vs in values.items() for s, v in enumerate(vs)]  # fmt: skip
    write_results(tmp_path / "metrics.csv", rows)
    return load([tmp_path / "metrics.csv"])


def test_the_section_says_where_our_iwso_is_far_from_table_1(tmp_path):
    results = _table(tmp_path, {
        ("F5", "iwso"): ("28", "30"),  # mean 29; the paper's 2.87e-7 to 2.24e-6: far
        ("F5", "boa"): ("28.85", "28.9"),  # the paper's 28.8 to 28.9 (1 %: 0.289): within
        ("F8", "iwso"): ("-5000", "-6000"),  # mean -5500; the paper's -12300 to -12200: far
        ("F8", "wso"): ("-9000", "-9200"),  # mean -9100: lower than IWSO's
    })  # fmt: skip
    assert [f.function for f in benchmark_functions.far(results, "iwso")] == ["F5", "F8"]
    text = benchmark_functions.discussion(results)
    assert ("on 2 function(s): F5 mean 29 (best 28, worst 30, 2 runs) against the paper's "
            "1.03e-06 (2.87e-07 to 2.24e-06); F8 mean -5500") in text
    # WSO's F8, -9100, is outside its own paper range (-4110 to -2940): 0 of 1 there
    assert "within the paper's range on F5 1 of 1, F8 0 of 1. " in text
    assert "not below WSO's on F8 (-5500 against -9100)" in text
    assert "Our runs are" not in text  # no job.json records the set-up


def test_no_discussion_where_our_iwso_is_within_the_papers_range(tmp_path):
    # the paper's F5 IWSO: 2.87e-7 to 2.24e-6, and 1e-8 of slack
    results = _table(tmp_path, {("F5", "iwso"): ("1e-6", "2e-6")})
    assert benchmark_functions.far(results, "iwso") == []
    assert benchmark_functions.discussion(results) is None
