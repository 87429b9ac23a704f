"""The report's inputs (usvtool/report/data.py): tables whose values are not what their metric
holds are refused before anything is built."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from usvtool.errors import UsvError
from usvtool.report.data import load
from usvtool.results import read_results, timings_path, write_results

ROOT = Path(__file__).resolve().parents[2]
BASELINE = ROOT / "baselines" / "ci.csv"


def test_a_table_of_nan_is_refused_in_one_line_and_nothing_is_written(usv, tmp_path):
    """The issue's case: exit 0 and a COLREGs claim "does not hold (0/1 runs)". The CI
    baseline has 502 values; its 9 failed_rules are words, so 493 are numbers or True/False."""
    rows = read_results(BASELINE)
    assert len(rows) == 502 and sum(r.metric == "failed_rules" for r in rows) == 9
    table = tmp_path / "nan.csv"
    write_results(table, [replace(r, value="nan") for r in rows])
    r = usv("report", table, "-o", tmp_path / "out", "--no-pdf")
    assert r.exit_code == 1 and r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and len(lines[0]) - len(str(table)) <= 150, r.stderr
    assert lines[0].startswith(f"Error: {table}: 493 values are not finite numbers or "
                               "True/False (arrival_time_s, arrived, attempt, ")  # fmt: skip
    assert "and 17 more); line 2: " in lines[0]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("value", ["inf", "abc", "-nan"])
def test_one_bad_number_or_timing_is_refused_naming_its_file(tmp_path, value):
    rows = read_results(BASELINE)
    where = next(i for i, r in enumerate(rows) if r.metric == "closest_distance_m")
    table = tmp_path / "metrics.csv"
    write_results(table, [replace(r, value=value) if i == where else r
                          for i, r in enumerate(rows)])  # fmt: skip
    with pytest.raises(UsvError, match=f"^{table}: 1 value is not a finite number "
                                       rf"\(closest_distance_m\); line {where + 2}: "):  # fmt: skip
        load([table])
    write_results(table, rows)
    timings = read_results(BASELINE.with_name("timings.csv"))
    write_results(timings_path(table), [replace(timings[0], value=value), *timings[1:]])
    with pytest.raises(UsvError, match=f"^{timings_path(table)}: 1 value is not a finite"):
        load([table])
    write_results(timings_path(table), timings)
    assert len(load([table]).jobs) == len({r.key for r in rows})
