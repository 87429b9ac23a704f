"""``usvtool functions`` through click's CliRunner."""

from __future__ import annotations

import csv
import io
import json

import pytest
from click.testing import CliRunner

from usvtool.cli import cli

SMALL = ["--runs", "2", "--pop", "6", "--iters", "5", "--dim", "4"]


def run(*args):
    return CliRunner().invoke(cli, ["functions", *map(str, args)])


def test_json_summary_and_table_on_stderr():
    result = run(*SMALL, "--algo", "gwo", "--algo", "iwso", "--function", "f1", "--function", "F8")
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["algorithms"] == ["gwo", "iwso"] and summary["functions"] == ["F1", "F8"]
    assert (summary["runs"], summary["pop"], summary["iters"], summary["dim"]) == (2, 6, 5, 4)
    cells = summary["results"]
    assert [(c["function"], c["algorithm"]) for c in cells] == [
        ("F1", "gwo"), ("F1", "iwso"), ("F8", "gwo"), ("F8", "iwso"),
    ]  # fmt: skip
    for c in cells:
        assert c["best"] <= c["mean"] <= c["worst"] and c["std"] >= 0
        assert c["best"] >= c["optimum"] - 1e-9
    assert cells[2]["optimum"] == pytest.approx(-418.9829 * 4, abs=1e-3)
    assert cells[0]["evaluations"] == 6 * 6  # gwo: pop (start) + pop per iteration
    lines = result.stderr.splitlines()
    assert lines[0].split() == ["Function", "GWO", "IWSO"]
    assert [ln.split()[0] for ln in lines[2:7]] == ["F1", "Worst", "Mean", "Std", "Evals"]


def test_defaults_cover_all_algorithms_and_functions():
    result = run("--runs", "1", "--pop", "3", "--iters", "1", "--dim", "2")
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    from usvtool.plan.optimizers import OPTIMIZERS

    assert summary["algorithms"] == list(OPTIMIZERS) and summary["functions"][-1] == "F10"
    assert len(OPTIMIZERS) >= 11  # the papers' ten and ssa-redraw, and any registered since
    assert len(summary["results"]) == 10 * len(OPTIMIZERS)
    assert summary["seed"] == 0


def test_csv_and_table_file(tmp_path):
    table = tmp_path / "table1.txt"
    result = run(*SMALL, "--algo", "ssa", "--function", "F9", "--format", "csv", "--table", table)
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(io.StringIO(result.stdout)))
    assert len(rows) == 1 and rows[0]["algorithm"] == "ssa" and rows[0]["function"] == "F9"
    assert set(rows[0]) == {
        "function", "algorithm", "best", "worst", "mean", "std", "optimum", "evaluations",
    }  # fmt: skip
    assert float(rows[0]["best"]) <= float(rows[0]["worst"])
    assert table.read_text().startswith("Function")
    assert "Function" not in result.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["table1.txt"]


def test_identical_whatever_the_number_of_processes():
    args = [*SMALL, "--algo", "woa", "--algo", "issa", "--function", "F7", "--function", "F5"]
    serial = run(*args, "--seed", "11")
    parallel = run(*args, "--seed", "11", "-j", "2")
    other = run(*args, "--seed", "12")
    assert serial.exit_code == parallel.exit_code == other.exit_code == 0
    assert serial.stdout == parallel.stdout
    assert serial.stdout != other.stdout


def test_subset_results_match_the_full_run():
    # a cell's runs depend only on (seed, algorithm, function, run), not on what else runs
    one = json.loads(run(*SMALL, "--algo", "mrfo", "--function", "F2").stdout)["results"]
    both = json.loads(
        run(*SMALL, "--algo", "pso", "--algo", "mrfo", "--function", "F2").stdout
    )["results"]
    assert one == both[1:]


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (["--runs", "0"], "--runs"),
        (["--pop", "1"], "--pop"),
        (["--iters", "0"], "--iters"),
        (["--dim", "0"], "--dim"),
        (["--algo", "sso"], "--algo"),
        (["--function", "F11"], "--function"),
        (["-j", "0"], "--jobs"),
        (["--format", "xml"], "--format"),
    ],
)
def test_usage_errors_name_the_option(args, option):
    result = run(*args)
    assert result.exit_code == 2
    error = [ln for ln in result.output.splitlines() if ln.startswith("Error:")]
    assert len(error) == 1 and option in error[0]


def test_table_in_missing_directory(tmp_path):
    result = run(*SMALL, "--table", tmp_path / "no" / "t.txt")
    assert result.exit_code == 1
    assert result.output.strip().startswith("Error: --table")
    assert len(result.output.strip().splitlines()) == 1
