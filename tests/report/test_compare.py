"""``usvtool compare``: hand-made results tables (usvtool.results.write_results), classes checked
against hand-computed medians, rates and tolerances; the outputs' bytes, self-containment and
atomicity; bad inputs; the command line in a subprocess."""

from __future__ import annotations

import errno
import hashlib
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from usvtool.errors import UsvError
from usvtool.report.regression.compare import CompareOptions, compare
from usvtool.report.regression.presentation import MARKDOWN_ROWS
from usvtool.report.regression.tolerances import RULES
from usvtool.results import Row, write_results

ROOT = Path(__file__).resolve().parents[2]
SEEDS = (1, 2, 3)


def job_key(kind: str, case: str, method: str, seed) -> str:
    return hashlib.sha256(f"{kind}/{case}/{method}/{seed}".encode()).hexdigest()[:16]


def rows(kind: str, case: str, method: str, metric: str, values, seeds=SEEDS) -> list[Row]:
    """One row per seed: ``values[i]`` is seed ``seeds[i]``'s value (as text)."""
    return [Row(job_key(kind, case, method, s), kind, case, method, s, metric, str(v))
            for s, v in zip(seeds, values, strict=True)]  # fmt: skip


def baseline_rows() -> list[Row]:
    return [
        *rows("routes", "env1", "iwso", "length_m", [700.0, 702.0, 701.0]),  # median 701
        *rows("routes", "env1", "iwso", "turns", [3, 1, 2]),  # median 2
        *rows("routes", "env1", "iwso", "collision_free", ["True", "False", "True"]),  # 2/3
        *rows("routes", "env1", "pso", "length_m", [1.0, 2.0, 3.0, 10.0], seeds=(1, 2, 3, 4)),
        *rows("runs", "head-on", "udwa", "closest_distance_m", [20.0, 22.0, 21.0]),
        *rows("runs", "head-on", "udwa", "arrived", ["True", "True", "True"]),
        *rows("runs", "head-on", "udwa", "failed_rules", ["rule8-in-time"], seeds=(2,)),
        *rows("runs", "head-on", "udwa", "collision", ["target"], seeds=(3,)),
    ]


def write(path: Path, table: list[Row]) -> Path:
    write_results(path, table)
    return path


def replaced(table: list[Row], group: tuple, values) -> list[Row]:
    """``table`` with the values of one group (kind, case, method, metric) replaced, seed by
    seed in the order of the rows."""
    out, new = [], iter(values)
    for r in table:
        if r.group == group:
            r = Row(r.key, r.kind, r.case, r.method, r.seed, r.metric, str(next(new)))
        out.append(r)
    return out


@pytest.fixture
def tables(tmp_path):
    """``tables(head_rows, base_rows=None)``: (baseline, current) paths in separate folders
    (so that each has its own timings.csv)."""

    def make(head: list[Row], base: list[Row] | None = None) -> tuple[Path, Path]:
        (tmp_path / "base").mkdir(exist_ok=True)
        (tmp_path / "head").mkdir(exist_ok=True)
        return (write(tmp_path / "base" / "ci.csv", base or baseline_rows()),
                write(tmp_path / "head" / "metrics.csv", head))  # fmt: skip

    return make


def outputs(out: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(out.iterdir())}


def by_label(result) -> dict:
    return {c.label: c for c in result.comparisons}


LENGTH = ("routes", "env1", "iwso", "length_m")


def test_the_same_table_is_all_ok_and_the_figures_are_the_hand_computed_ones(tables):
    base, head = tables(baseline_rows())
    result = compare(CompareOptions(str(base), str(head)))
    c = by_label(result)
    assert {x.status for x in result.comparisons} == {"ok"}
    assert result.status == 0
    assert (c["routes/env1/iwso/length_m"].base, c["routes/env1/iwso/length_m"].aggregate) == (
        701.0, "median")  # fmt: skip
    assert c["routes/env1/iwso/turns"].base == 2
    assert c["routes/env1/pso/length_m"].base == 2.5  # the median of 1, 2, 3, 10
    assert c["routes/env1/pso/length_m"].n_base == 4
    rate = c["routes/env1/iwso/collision_free"]
    assert (rate.aggregate, rate.base) == ("mean", pytest.approx(2 / 3))
    collision = c["runs/head-on/udwa/collision"]  # one job of three hit something
    assert (collision.aggregate, collision.base, collision.n_base) == ("share", 1 / 3, 3)
    assert c["runs/head-on/udwa/failed_rules"].base == "rule8-in-time"


def test_an_injected_regression_is_flagged(tables):
    base, head = tables(replaced(baseline_rows(), LENGTH, [770.0, 772.0, 771.0]))
    result = compare(CompareOptions(str(base), str(head)))
    c = by_label(result)["routes/env1/iwso/length_m"]
    # median 701 -> 771: +70 m against 2 % of 701 = 14.02 m
    assert (c.base, c.head, c.change, c.allowed, c.status) == (701, 771, 70, 14.02, "regressed")
    assert c.relative_change == pytest.approx(70 / 701)
    assert result.status == 1
    assert result.summary()["regressed"] == ["routes/env1/iwso/length_m"]
    assert result.counts()["regressed"] == 1 and result.counts()["ok"] == 7


def test_a_missing_row_is_flagged(tables):
    head = [r for r in baseline_rows() if r.metric != "closest_distance_m"]
    result = compare(CompareOptions(*map(str, tables(head))))
    c = by_label(result)["runs/head-on/udwa/closest_distance_m"]
    assert (c.status, c.base, c.head) == ("missing", 21.0, None)
    assert result.status == 1
    assert result.summary()["missing"] == ["runs/head-on/udwa/closest_distance_m"]


def test_an_improvement_and_a_change_inside_the_tolerance_are_not_flagged(tables):
    head = replaced(baseline_rows(), LENGTH, [690.0, 712.0, 711.0])  # median 711: +10 < 14.02
    head = replaced(head, ("runs", "head-on", "udwa", "closest_distance_m"), [30.0, 32.0, 31.0])
    head = replaced(head, ("routes", "env1", "iwso", "collision_free"), ["True"] * 3)
    result = compare(CompareOptions(*map(str, tables(head))))
    c = by_label(result)
    assert c["routes/env1/iwso/length_m"].status == "ok"
    assert c["routes/env1/iwso/length_m"].change == 10
    assert c["runs/head-on/udwa/closest_distance_m"].status == "improved"  # higher is better
    assert c["routes/env1/iwso/collision_free"].status == "improved"  # 2/3 -> 1
    assert result.status == 0 and not result.summary()["regressed"]


def test_lower_for_a_larger_is_better_metric_regresses(tables):
    head = replaced(baseline_rows(), ("runs", "head-on", "udwa", "closest_distance_m"),
                    [10.0, 11.0, 12.0])  # fmt: skip
    head = replaced(head, ("routes", "env1", "iwso", "collision_free"), ["False"] * 3)
    c = by_label(compare(CompareOptions(*map(str, tables(head)))))
    assert c["runs/head-on/udwa/closest_distance_m"].status == "regressed"
    assert c["routes/env1/iwso/collision_free"].status == "regressed"  # 2/3 -> 0, tolerance 0


def test_new_rows_are_new_and_do_not_fail(tables):
    head = baseline_rows() + rows("functions", "F1", "pso", "final_cost", [1e-5, 2e-5, 3e-5])
    result = compare(CompareOptions(*map(str, tables(head))))
    c = by_label(result)["functions/F1/pso/final_cost"]
    assert (c.status, c.base, c.head) == ("new", None, 2e-5)
    assert result.status == 0


def test_absent_collision_and_failed_rules_mean_none_not_missing(tables):
    head = [r for r in baseline_rows() if r.metric not in ("collision", "failed_rules")]
    result = compare(CompareOptions(*map(str, tables(head))))
    c = by_label(result)
    assert (c["runs/head-on/udwa/collision"].head, c["runs/head-on/udwa/collision"].status) == (
        0.0, "improved")  # fmt: skip
    assert (c["runs/head-on/udwa/failed_rules"].head,
            c["runs/head-on/udwa/failed_rules"].status) == ("", "changed")  # fmt: skip
    assert result.status == 0
    # a collision in a run that had none regresses
    result = compare(CompareOptions(*map(str, tables(baseline_rows(), head))))
    assert by_label(result)["runs/head-on/udwa/collision"].status == "regressed"


def test_the_floor_and_a_change_equal_to_the_tolerance(tables):
    base = rows("routes", "env1", "iwso", "mot", [0, 0, 0]) + rows(
        "routes", "env1", "iwso", "length_ratio", [0.7, 0.7, 0.7])  # fmt: skip
    head = rows("routes", "env1", "iwso", "mot", [0.001, 0.001, 0.001]) + rows(
        "routes", "env1", "iwso", "length_ratio", [0.714, 0.714, 0.714])  # fmt: skip
    c = by_label(compare(CompareOptions(*map(str, tables(head, base)))))
    assert (c["routes/env1/iwso/mot"].allowed, c["routes/env1/iwso/mot"].status) == (0.01, "ok")
    ratio = c["routes/env1/iwso/length_ratio"]  # 2 % of 0.7 is exactly 0.014
    assert (ratio.change, ratio.allowed, ratio.status) == (0.014, 0.014, "ok")
    head = replaced(head, ("routes", "env1", "iwso", "length_ratio"), [0.7141] * 3)
    c = by_label(compare(CompareOptions(*map(str, tables(head, base)))))
    assert c["routes/env1/iwso/length_ratio"].status == "regressed"


def test_timings_are_reported_but_never_fail_by_default(tables, tmp_path):
    base, head = tables(baseline_rows())
    timing = rows("routes", "env1", "iwso", "wall_time_s", [1.0, 1.0, 1.0])
    write(base.with_name("timings.csv"), timing)
    write(head.with_name("timings.csv"), replaced(timing, timing[0].group, [9.0, 9.0, 9.0]))
    result = compare(CompareOptions(str(base), str(head)))
    c = by_label(result)["routes/env1/iwso/wall_time_s"]
    assert (c.timing, c.status, c.counted, c.base, c.head) == (True, "regressed", False, 1, 9)
    assert result.status == 0 and result.counts(timing=True)["regressed"] == 1
    assert result.summary()["groups"] == 8  # timings apart
    # the tolerances file beside the baseline makes them count
    base.with_suffix(".tolerances.yaml").write_text("count_timings: true\n")
    result = compare(CompareOptions(str(base), str(head)))
    assert result.status == 1
    assert result.summary()["regressed"] == ["routes/env1/iwso/wall_time_s"]


def test_a_tolerances_file_changes_the_rules(tables, tmp_path):
    base, head = tables(replaced(baseline_rows(), LENGTH, [770.0, 772.0, 771.0]))
    loose = tmp_path / "loose.yaml"
    loose.write_text("metrics:\n  length_m: {relative: 0.2}\n  turns: {better: none}\n")
    result = compare(CompareOptions(str(base), str(head), str(loose)))
    c = by_label(result)["routes/env1/iwso/length_m"]
    assert (c.allowed, c.absolute, c.status) == (140.2, 0.01, "ok")  # 20 % of 701; floor kept
    assert result.summary()["tolerances"] == str(loose)
    head2 = replaced(baseline_rows(), ("routes", "env1", "iwso", "turns"), [9, 9, 9])
    base, head = tables(head2)
    c = by_label(compare(CompareOptions(str(base), str(head), str(loose))))
    assert c["routes/env1/iwso/turns"].status == "changed"  # informational now


@pytest.mark.parametrize("text, words", [
    ("metrics: {length_m: {relative: -1}}", "metrics.length_m.relative"),
    ("metrics: {length_m: {relative: yes}}", "metrics.length_m.relative"),
    ("metrics: {length_m: {better: up}}", "metrics.length_m.better"),
    ("metrics: {length_m: {tolerance: 1}}", "unknown key 'tolerance'"),
    ("count_timings: maybe", "count_timings"),
    ("timings: true", "unknown key 'timings'"),
    ("[1, 2]", "must be a mapping"),
    ("metrics: {a: [1", "not valid YAML"),
])  # fmt: skip
def test_a_bad_tolerances_file_is_one_line_naming_it_and_the_field(
    usv, tables, tmp_path, text, words
):
    base, head = tables(baseline_rows())
    bad = tmp_path / "bad.yaml"
    bad.write_text(text + "\n")
    r = usv("compare", base, head, "--tolerances", bad, "-o", tmp_path / "out")
    assert r.exit_code == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and str(bad) in lines[0] and words in lines[0], r.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("which, content, words", [
    ("current", None, "no such file"),
    ("current", "", "empty file"),
    ("current", "a,b\n1,2\n", "not a results table"),
    ("baseline", "key,kind,case,method,seed,metric,value\nk,routes,env1,iwso,x,length_m,1\n",
     "line 2: seed 'x'"),
])  # fmt: skip
def test_bad_inputs_give_one_line_naming_the_file_and_write_nothing(
    usv, tables, tmp_path, which, content, words
):
    base, head = tables(baseline_rows())
    bad = base if which == "baseline" else head
    if content is None:
        bad.unlink()
    else:
        bad.write_text(content)
    out = tmp_path / "out"
    r = usv("compare", base, head, "-o", out)
    assert r.exit_code == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and str(bad) in lines[0] and words in lines[0], r.stderr
    assert r.stdout == ""
    assert not out.exists()


#: A job's length given twice: the same row repeated, and two values (805.76 and 99999).
TWICE = {"duplicate": ("805.76", "line 4 repeats line 2"),
         "conflict": ("99999", "line 2 says '805.76', line 4 says '99999'")}  # fmt: skip


@pytest.mark.parametrize("which", ["baseline", "current"])
@pytest.mark.parametrize("how", sorted(TWICE))
def test_a_metric_of_a_job_given_twice_is_refused_naming_the_lines(usv, tables, tmp_path, which,
                                                                    how):  # fmt: skip
    base, head = tables(baseline_rows())
    bad = base if which == "baseline" else head
    second, said = TWICE[how]
    bad.write_text("key,kind,case,method,seed,metric,value\n"
                   "0a,routes,env1,iwso,1,length_m,805.76\n"
                   "0a,routes,env1,iwso,1,turns,2\n"
                   f"0a,routes,env1,iwso,1,length_m,{second}\n")  # fmt: skip
    out = tmp_path / "out"
    r = usv("compare", base, head, "-o", out)
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr.splitlines() == [
        f"Error: {bad}: job 0a, metric length_m: {said} (a job has one row a metric)"]
    assert not out.exists()


def test_an_output_that_is_a_link_below_the_folder_is_refused_and_its_target_kept(
        usv, tables, tmp_path):  # fmt: skip
    base, head = tables(baseline_rows())
    out = tmp_path / "out"
    out.mkdir()
    (tmp_path / "precious.md").write_text("precious")
    (out / "summary.md").symlink_to(tmp_path / "precious.md")
    r = usv("compare", base, head, "-o", out)
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr.splitlines() == [
        f"Error: {out / 'summary.md'}: a symbolic link (to {tmp_path / 'precious.md'}) in the "
        f"output directory {out}: nothing is written or removed through a link below it; remove "
        "the link or choose another directory"]
    assert (tmp_path / "precious.md").read_text() == "precious"
    assert sorted(p.name for p in out.iterdir()) == ["summary.md"]


def test_a_failure_leaves_earlier_outputs_as_they_were(usv, tables, tmp_path):
    base, head = tables(baseline_rows())
    out = tmp_path / "out"
    assert usv("compare", base, head, "-o", out).exit_code == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    head.write_text("not a table\n")
    assert usv("compare", base, head, "-o", out).exit_code == 1
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before  # no temporary either


def full_disk_at(monkeypatch, suffix: str) -> None:
    """Writing the staged temporary of a file ending in ``suffix`` fails: no space left."""
    write_bytes = Path.write_bytes

    def failing(self, data):
        if self.name.startswith(".") and self.suffix == suffix:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return write_bytes(self, data)

    monkeypatch.setattr(Path, "write_bytes", failing)


def test_a_writer_failing_while_staged_writes_none_of_the_three(tables, tmp_path, monkeypatch):
    base, head = tables(baseline_rows())
    out = tmp_path / "out"
    compare(CompareOptions(str(base), str(head), out_dir=str(out)))
    before = outputs(out)
    full_disk_at(monkeypatch, ".md")
    head = write(head, replaced(baseline_rows(), LENGTH, [770.0, 772.0, 771.0]))
    with pytest.raises(UsvError, match=f"^{re.escape(str(out / 'summary.md'))}: cannot write "
                                       "it: No space left on device$"):  # fmt: skip
        compare(CompareOptions(str(base), str(head), out_dir=str(out)))
    assert outputs(out) == before  # the HTML and JSON written before it were not renamed


def test_a_full_disk_leaves_no_output_directory(tables, tmp_path, monkeypatch):
    base, head = tables(baseline_rows())
    full_disk_at(monkeypatch, ".json")
    with pytest.raises(UsvError, match="regression.json: cannot write it: No space left"):
        compare(CompareOptions(str(base), str(head), out_dir=str(tmp_path / "a" / "b")))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["base", "head"]  # no a/, no a/b/


def test_an_output_that_is_a_file_is_a_usage_error(usv, tables, tmp_path):
    base, head = tables(baseline_rows())
    (tmp_path / "out").write_text("x")
    r = usv("compare", base, head, "-o", tmp_path / "out")
    assert r.exit_code == 2 and "is a file" in r.stderr
    assert (tmp_path / "out").read_text() == "x"


def test_usage_errors_exit_2(usv, tables):
    base, _ = tables(baseline_rows())
    assert usv("compare", base).exit_code == 2
    assert usv("compare", base, base, "--no-such-option").exit_code == 2


def test_the_same_inputs_give_the_same_bytes_of_all_three_outputs(tables, tmp_path):
    base, head = tables(replaced(baseline_rows(), LENGTH, [770.0, 772.0, 771.0]))
    write(head.with_name("timings.csv"), rows("routes", "env1", "iwso", "wall_time_s", [1, 2, 3]))
    for name in ("a", "b"):
        compare(CompareOptions(str(base), str(head), out_dir=str(tmp_path / name)))
    a, b = outputs(tmp_path / "a"), outputs(tmp_path / "b")
    assert sorted(a) == ["index.html", "regression.json", "summary.md"]
    assert a == b
    # the rows of a table in another order: the same results
    shuffled = write(tmp_path / "head" / "shuffled.csv", list(reversed(
        replaced(baseline_rows(), LENGTH, [770.0, 772.0, 771.0]))))  # fmt: skip
    one = compare(CompareOptions(str(base), str(head))).comparisons
    assert compare(CompareOptions(str(base), str(shuffled))).comparisons == one


def test_the_json_has_every_group_with_its_figures(tables, tmp_path):
    base, head = tables(replaced(baseline_rows(), LENGTH, [770.0, 772.0, 771.0]))
    compare(CompareOptions(str(base), str(head), out_dir=str(tmp_path / "out")))
    data = json.loads((tmp_path / "out" / "regression.json").read_text())
    assert len(data["groups"]) == 8 and data["status"] == 1
    g = next(g for g in data["groups"] if g["metric"] == "length_m" and g["method"] == "iwso")
    assert {k: g[k] for k in ("base", "head", "change", "allowed", "class", "better")} == {
        "base": 701.0, "head": 771.0, "change": 70.0, "allowed": 14.02, "class": "regressed",
        "better": "lower"}  # fmt: skip


def test_the_html_references_nothing_outside_itself_and_regressions_come_first(tables, tmp_path):
    head = replaced(baseline_rows(), LENGTH, [770.0, 772.0, 771.0])
    head = [r for r in head if r.metric != "arrived"]
    base, head = tables(head)
    compare(CompareOptions(str(base), str(head), out_dir=str(tmp_path / "out")))
    page = (tmp_path / "out" / "index.html").read_text(encoding="utf-8")
    assert "<style>" in page and "border-collapse" in page  # the stylesheet inlined
    assert not re.search(r"""\b(src|href|action|data|poster)\s*=\s*["']?(?!#)""", page, re.I)
    assert not re.search(r"url\(|@import|https?://|file:|<link|<script", page, re.I)
    body = page[page.index("<tbody>"):]
    classes = re.findall(r'<tr class="status-(\w+)"', body)
    assert classes[:2] == ["regressed", "missing"] and set(classes[2:]) == {"ok"}
    assert ">701<" in body and ">771<" in body and "+70 (+10.0 %)" in body


def test_the_markdown_summary_is_short_with_regressions_and_missing_first(tables, tmp_path):
    many = [r for i in range(MARKDOWN_ROWS + 5)
            for r in rows("routes", f"chart{i:02}", "iwso", "length_m", [100, 100, 100])]
    worse = [Row(r.key, r.kind, r.case, r.method, r.seed, r.metric, "50") for r in many]
    head = replaced(baseline_rows(), LENGTH, [770.0, 772.0, 771.0]) + worse
    head = [r for r in head if r.metric != "arrived"]
    base, head = tables(head, baseline_rows() + many)
    result = compare(CompareOptions(str(base), str(head)))
    text = result.to_markdown()
    lines = text.splitlines()
    assert lines[0] == "## usvtool compare: FAIL: 1 regressed, 1 missing"
    table = [line for line in lines if line.startswith("| ") and "---" not in line][1:]
    assert len(table) == MARKDOWN_ROWS
    assert table[0].startswith("| regressed | routes | env1 | iwso | length_m | 701 | 771 |")
    assert table[1].startswith("| missing | runs | head-on | udwa | arrived | 1 | — |")
    assert all(line.startswith("| improved |") for line in table[2:])
    assert "and 7 more" in text  # 1 regressed + 1 missing + 35 improved, 30 shown
    assert len(text) < 5000


def test_every_metric_of_usvtool_metrics_has_a_rule_documented():
    from usvtool.metrics import ROUTE_COLUMNS, RUN_COLUMNS
    from usvtool.results import TIMING_METRICS

    assert set(ROUTE_COLUMNS) | set(RUN_COLUMNS) | set(TIMING_METRICS) | {"final_cost"} <= set(
        RULES)  # fmt: skip
    doc = (ROOT / "docs" / "compare.md").read_text(encoding="utf-8")
    assert [m for m in RULES if f"`{m}`" not in doc] == []


def test_the_command_line_in_a_subprocess(tables, tmp_path):
    base, head = tables(replaced(baseline_rows(), LENGTH, [770.0, 772.0, 771.0]))
    out = tmp_path / "regression"
    cmd = [sys.executable, "-m", "usvtool.cli", "compare", str(base), str(head), "-o", str(out)]
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 1
    summary = json.loads(p.stdout)
    assert summary["regressed"] == ["routes/env1/iwso/length_m"] and summary["status"] == 1
    assert summary["output"] == str(out)
    assert p.stderr.startswith((out / "summary.md").read_text(encoding="utf-8"))
    assert p.stderr.strip().splitlines()[-1].startswith("Error: 1 regressed, 0 missing")
    quiet = [sys.executable, "-m", "usvtool.cli", "-q", "compare", str(base), str(base), "-o",
             str(out)]  # fmt: skip
    p = subprocess.run(quiet, capture_output=True, text=True, cwd=tmp_path)
    assert (p.returncode, p.stderr) == (0, "")  # -q: no Markdown on stderr
    assert json.loads(p.stdout)["status"] == 0


def test_the_committed_ci_baseline_flags_an_injected_regression(tmp_path):
    """``make regression``'s own baseline: a copy with IWSO's env1 routes 10 % longer regresses
    (and only those rows' group), and the baseline against itself passes."""
    from dataclasses import replace

    from usvtool.results import read_results

    baseline = ROOT / "baselines" / "ci.csv"
    rows = read_results(baseline)
    worse = [replace(r, value=f"{float(r.value) * 1.1:.2f}")
             if (r.kind, r.case, r.method, r.metric) == ("routes", "env1", "iwso", "length_m")
             else r for r in rows]  # fmt: skip
    assert worse != rows
    write_results(tmp_path / "current.csv", worse)
    result = compare(CompareOptions(str(baseline), str(tmp_path / "current.csv")))
    regressed = [c for c in result.comparisons if c.status == "regressed"]
    assert result.status == 1
    assert [(c.kind, c.case, c.method, c.metric) for c in regressed] == [
        ("routes", "env1", "iwso", "length_m")]
    same = compare(CompareOptions(str(baseline), str(baseline)))
    assert same.status == 0


# ---- values that are not what their metric holds (the class `invalid`) ----


def ci_rows() -> list[Row]:
    from usvtool.results import read_results

    return read_results(ROOT / "baselines" / "ci.csv")


def test_a_table_of_nan_is_invalid_everywhere_a_number_is_expected(usv, tmp_path):
    """The issue's case: every value `nan` passed with "333 changed". Only the words of
    failed_rules may be any word (a rule named "nan" is a change); every other group of the
    CI baseline holds numbers or True/False."""
    from dataclasses import replace

    base = ROOT / "baselines" / "ci.csv"
    head = write(tmp_path / "nan.csv", [replace(r, value="nan") for r in ci_rows()])
    groups = {r.group for r in ci_rows()}
    words = {g for g in groups if g[3] in ("failed_rules", "excused_rules")}
    # hand-counted from the file: 20 runs with 3 counts more since the COLREGs split (issue 25),
    # the 4 runs that never arrive judging nothing (ccdwa's failed_rules gone)
    assert len(groups) == 392 and len(words) == 9
    r = usv("compare", base, head, "-o", tmp_path / "out")
    assert r.exit_code == 1
    summary = json.loads(r.stdout)
    assert summary["counts"]["invalid"] == 383 and summary["counts"]["changed"] == 9
    assert len(summary["invalid"]) == 383 and summary["status"] == 1
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("Error: 0 regressed, 0 missing, 383 invalid")
    assert "## usvtool compare: FAIL: 383 invalid" in r.stderr


def test_one_infinite_length_is_invalid_and_shown_first_in_every_report(tables, tmp_path):
    head = replaced(baseline_rows(), LENGTH, [700.0, "inf", 701.0])
    base, head = tables(head)
    result = compare(CompareOptions(str(base), str(head), out_dir=str(tmp_path / "out")))
    c = by_label(result)
    bad = c["routes/env1/iwso/length_m"]
    assert (bad.status, bad.base, bad.head, bad.invalid, bad.n_head) == (
        "invalid", 701.0, "inf", 1, 3)  # fmt: skip
    assert bad.change is None and result.status == 1
    assert {x.status for x in result.comparisons if x is not bad} == {"ok"}
    data = json.loads((tmp_path / "out" / "regression.json").read_text())
    assert data["invalid"] == ["routes/env1/iwso/length_m"] and data["counts"]["invalid"] == 1
    assert data["status"] == 1
    md = (tmp_path / "out" / "summary.md").read_text()
    assert md.startswith("## usvtool compare: FAIL: 1 invalid\n")
    assert "| invalid | routes | env1 | iwso | length_m | 701 | inf | 1 of 3 not numbers |" in md
    page = (tmp_path / "out" / "index.html").read_text()
    body = page[page.index("<tbody>"):]
    assert re.findall(r'<tr class="status-(\w+)"', body)[0] == "invalid"
    assert "1 of 3 not numbers" in body


def test_one_word_for_a_number_and_a_number_for_a_boolean_are_invalid(tables):
    head = replaced(baseline_rows(), ("runs", "head-on", "udwa", "closest_distance_m"),
                    [20.0, "abc", 21.0])  # fmt: skip
    head = replaced(head, ("routes", "env1", "iwso", "collision_free"), ["True", "1", "nan"])
    result = compare(CompareOptions(*map(str, tables(head))))
    c = by_label(result)
    word = c["runs/head-on/udwa/closest_distance_m"]
    assert (word.status, word.head, word.invalid) == ("invalid", "abc", 1)
    boolean = c["routes/env1/iwso/collision_free"]  # the contract writes True / False
    assert (boolean.status, boolean.head, boolean.invalid) == ("invalid", "1;nan", 2)
    assert result.status == 1
    assert sorted(result.summary()["invalid"]) == ["routes/env1/iwso/collision_free",
                                                   "runs/head-on/udwa/closest_distance_m"]


def test_words_stay_words_and_an_unknown_metric_is_judged_by_the_baseline(tables):
    """A collision names what was hit and failed_rules lists rules: any word is valid there.
    A metric the contract does not know holds numbers when every baseline value is one."""
    base = baseline_rows() + rows("routes", "env1", "iwso", "my_metric", [1, 2, 3]) + rows(
        "routes", "env1", "iwso", "my_word", ["a", "b", "c"])  # fmt: skip
    head = replaced(base, ("runs", "head-on", "udwa", "collision"), ["12"])
    head = replaced(head, ("routes", "env1", "iwso", "my_metric"), [1, 2, "nan"])
    head = replaced(head, ("routes", "env1", "iwso", "my_word"), ["a", "nan", "c"])
    head += rows("routes", "env1", "iwso", "fitness", ["nan"] * 3)  # a new group, broken
    c = by_label(compare(CompareOptions(*map(str, tables(head, base)))))
    assert c["runs/head-on/udwa/collision"].status == "ok"  # the same share of the jobs
    assert (c["routes/env1/iwso/my_metric"].status, c["routes/env1/iwso/my_metric"].head) == (
        "invalid", "nan")  # fmt: skip
    assert c["routes/env1/iwso/my_word"].status == "changed"
    assert (c["routes/env1/iwso/fitness"].status, c["routes/env1/iwso/fitness"].n_base) == (
        "invalid", 0)  # fmt: skip


def test_an_invalid_timing_counts_only_when_timings_count(tables):
    base, head = tables(baseline_rows())
    timing = rows("routes", "env1", "iwso", "wall_time_s", [1.0, 1.0, 1.0])
    write(base.with_name("timings.csv"), timing)
    write(head.with_name("timings.csv"), replaced(timing, timing[0].group, [1.0, "nan", 1.0]))
    result = compare(CompareOptions(str(base), str(head)))
    c = by_label(result)["routes/env1/iwso/wall_time_s"]
    assert (c.status, c.counted, result.status) == ("invalid", False, 0)
    base.with_suffix(".tolerances.yaml").write_text("count_timings: true\n")
    assert compare(CompareOptions(str(base), str(head))).status == 1


def test_a_baseline_holding_nan_is_refused_in_one_line_naming_it(usv, tables, tmp_path):
    table = replaced(baseline_rows(), LENGTH, ["nan", 702.0, "inf"])
    table = replaced(table, ("routes", "env1", "iwso", "collision_free"), ["True", "yes", "True"])
    base, head = tables(baseline_rows(), table)
    out = tmp_path / "out"
    r = usv("compare", base, head, "-o", out)
    assert r.exit_code == 1 and r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and len(lines[0]) <= 200, r.stderr
    assert lines[0].startswith(f"Error: {base}: 3 values are not")
    first = next(n for n, line in enumerate(base.read_text().splitlines(), start=1)
                 if line.endswith((",nan", ",inf", ",yes")))  # fmt: skip
    value = base.read_text().splitlines()[first - 1].split(",")
    assert f"(collision_free, length_m); line {first}: {value[5]} '{value[6]}'" in lines[0]
    assert not out.exists()
