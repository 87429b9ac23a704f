"""The Make side of the pipeline, dry runs only (``make -n -W FILE``: what a change of FILE would
re-run) on up-to-date stand-in targets in a temporary build directory: each stage depends on its
own code, not on every source file, and the commands write their summaries (--summary)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
pytestmark = pytest.mark.skipif(shutil.which("make") is None, reason="needs GNU Make")


@pytest.fixture(scope="module")
def tree(tmp_path_factory):
    """A build directory whose grid env1 and route env1/astar are newer than every source."""
    tmp = tmp_path_factory.mktemp("build")
    fragment = tmp / "pipeline.mk"
    subprocess.run([sys.executable, "-m", "usvtool.cli", "batch", "pipelines/report.yaml",
                    "--make-fragment", fragment], cwd=ROOT, check=True)  # fmt: skip
    _newer_than_every_source(fragment, tmp / "grids" / "env1.tif",
                             tmp / "paths" / "env1" / "astar.geojson")  # fmt: skip
    return tmp


def _newer_than_every_source(*targets: Path) -> None:
    future = time.time() + 3600
    for t in targets:
        t.parent.mkdir(parents=True, exist_ok=True)
        t.touch()
        os.utime(t, (future, future))


def make(tree: Path, *args: str) -> subprocess.CompletedProcess:
    variables = [f"BIN={Path(sys.executable).parent}", f"PIPELINE_MK={tree / 'pipeline.mk'}",
                 f"OUT={tree / 'grids'}", f"PATHS_DIR={tree / 'paths'}"]  # fmt: skip
    targets = [str(tree / "grids" / "env1.tif"), str(tree / "paths" / "env1" / "astar.geojson")]
    return subprocess.run(["make", "-f", "pipelines/report.mk", *variables, *args, *targets],
                          cwd=ROOT, capture_output=True, text=True)  # fmt: skip


def commands(tree: Path, changed: str) -> str:
    r = make(tree, "-n", "-W", changed)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_up_to_date_targets_need_nothing(tree):
    assert make(tree, "-q").returncode == 0


@pytest.mark.parametrize(
    "changed",
    ["usvtool/chart/gridding.py", "usvtool/cli/preprocess.py", "usvtool/grid.py",
     "usvtool/cli/options.py", "charts/env1.geojson"],
)  # fmt: skip
def test_a_chart_stage_change_remakes_the_grid_and_its_routes(tree, changed):
    out = commands(tree, changed)
    assert " preprocess charts/env1.geojson " in out and " plan " in out


@pytest.mark.parametrize(
    "changed",
    ["usvtool/plan/planner.py", "usvtool/plan/optimizers/iwso.py", "usvtool/cli/plan.py",
     "usvtool/route.py", "usvtool/collision.py"],
)  # fmt: skip
def test_a_plan_stage_change_replans_without_remaking_the_grid(tree, changed):
    out = commands(tree, changed)
    assert " plan " in out and " preprocess " not in out


@pytest.mark.parametrize("changed", ["usvtool/metrics/tabulate.py", "usvtool/sim/run.py"])
def test_other_stages_remake_neither(tree, changed):
    out = commands(tree, changed)
    assert " plan " not in out and " preprocess " not in out


def test_summaries_are_written_by_the_commands(tree):
    out = commands(tree, "usvtool/grid.py")
    lines = [line for line in out.splitlines() if "usvtool" in line]
    assert lines and all("--summary " in line for line in lines)
    assert all(line.endswith("> /dev/null") and line.count(">") == 1 for line in lines)


@pytest.fixture(scope="module")
def report_tree(tmp_path_factory):
    """A build directory whose batch table and report are newer than every source."""
    tmp = tmp_path_factory.mktemp("report")
    _newer_than_every_source(tmp / "stamp", tmp / "system", tmp / "batch" / "metrics.csv",
                             tmp / "report" / "index.html")  # fmt: skip
    return tmp


def make_report(tree: Path, *args: str, target: str = "report") -> subprocess.CompletedProcess:
    variables = [f"BIN={Path(sys.executable).parent}", f"BUILD={tree}", f"STAMP={tree / 'stamp'}",
                 f"SYSTEM_STAMP={tree / 'system'}"]  # fmt: skip
    return subprocess.run(["make", *variables, *args, target], cwd=ROOT, capture_output=True,
                          text=True)  # fmt: skip


def test_a_second_make_report_does_nothing(report_tree):
    # the report's files are up to date (`report` itself always prints the report's last line)
    index = report_tree / "report" / "index.html"
    assert make_report(report_tree, "-q", target=str(index)).returncode == 0
    dry = make_report(report_tree, "-n").stdout
    assert "usvtool batch" not in dry and "usvtool report" not in dry and "summary_line" in dry


@pytest.mark.parametrize("changed", ["templates/report.html.j2", "templates/style.css",
                                     "usvtool/report/sections/planning.py",
                                     "usvtool/cli/report.py"])
def test_a_template_or_report_change_renders_only_the_report(report_tree, changed):
    r = make_report(report_tree, "-n", "-W", changed)
    assert r.returncode == 0, r.stderr
    assert "usvtool report" in r.stdout and "usvtool batch" not in r.stdout


@pytest.mark.parametrize("changed", ["usvtool/plan/planner.py", "usvtool/sim/run.py",
                                     "pipelines/full.yaml", "charts/env1.geojson"])
def test_a_stage_chart_or_pipeline_change_runs_the_batch_then_the_report(report_tree, changed):
    r = make_report(report_tree, "-n", "-W", changed)
    assert r.returncode == 0, r.stderr
    batch = r.stdout.find("usvtool batch pipelines/full.yaml")
    assert 0 <= batch < r.stdout.find("usvtool report"), r.stdout


#: A project of two charts (paths relative to its root): each file, and the charts whose grid
#: reads it (a raster's sidecars, an S-57 cell's update files, an input glob's matches, an
#: option file and its sidecar), or none (another file's sidecar, another cell's update).
CHART_FILES = {
    "charts/r.tif": {"r"}, "charts/r.tif.aux.xml": {"r"}, "charts/r.TFW": {"r"},
    "charts/other.tif.aux.xml": set(), "extra/a.dat": {"r"}, "extra/b.dat": {"r"},
    "cut/cut.geojson": {"r"}, "cut/cut.geojson.aux.xml": {"r"}, "cut/notes.txt": set(),
    "enc/CELL.000": {"s"}, "enc/CELL.001": {"s"}, "enc/CELL.002": {"s"}, "enc/OTHER.001": set(),
}  # fmt: skip
SOURCES = {"r": "charts/r.tif", "s": "enc/CELL.000"}


@pytest.fixture()
def project(tmp_path):
    """CHART_FILES, a pipeline of their two charts with a route each, and ``usvtool/`` (a link:
    the rules depend on the stages' code); the fragment, grids and routes newer than all."""
    for name in CHART_FILES:
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_text(name)
    (tmp_path / "usvtool").symlink_to(ROOT / "usvtool")
    (tmp_path / "p.yaml").write_text(
        "charts:\n"
        "  r: {source: charts/r.tif, inputs: [extra/*.dat], options: {cutline: cut/cut.geojson},\n"
        "      start: [1, 1], goal: [5, 5]}\n"
        "  s: {source: enc/CELL.000, start: [1, 1], goal: [5, 5]}\n"
        "routes:\n  a: {charts: [r, s], algorithms: [astar], seeds: [1]}\n")  # fmt: skip
    subprocess.run([sys.executable, "-m", "usvtool.cli", "batch", "p.yaml", "--make-fragment",
                    "pipeline.mk"], cwd=tmp_path, check=True)  # fmt: skip
    _newer_than_every_source(tmp_path / "pipeline.mk", tmp_path / "grids" / "r.tif",
                             tmp_path / "grids" / "s.tif")  # fmt: skip
    return tmp_path


def make_project(project: Path, *args: str) -> subprocess.CompletedProcess:
    variables = [f"BIN={Path(sys.executable).parent}", "PIPELINE=p.yaml", "PIPELINE_MK=pipeline.mk",
                 "OUT=grids"]  # fmt: skip
    return subprocess.run(["make", "-f", str(ROOT / "pipelines" / "charts.mk"), *variables, *args,
                           "grids/r.tif", "grids/s.tif"], cwd=project, capture_output=True,
                          text=True)  # fmt: skip


def grid_keys(project: Path) -> dict[str, str]:
    from usvtool.batch.jobs import expand
    from usvtool.cli.batch import stage_names
    from usvtool.pipeline import load

    names = stage_names()
    jobs = expand(load(project / "p.yaml", names), names)
    return {j.case: j.key for j in jobs if j.kind == "grids"}


def test_make_remakes_a_grid_when_a_file_its_batch_key_hashes_changes(project):
    assert make_project(project, "-q").returncode == 0
    keys = grid_keys(project)
    for name, readers in CHART_FILES.items():
        r = make_project(project, "-n", "-W", name)
        assert r.returncode == 0, r.stderr
        remade = {c for c, source in SOURCES.items() if f" preprocess {source} " in r.stdout}
        with open(project / name, "a") as f:
            f.write("changed")
        changed = {c for c, k in grid_keys(project).items() if keys[c] != k}
        keys = grid_keys(project)
        assert (name, remade) == (name, readers) and (name, changed) == (name, readers)


def test_a_file_new_in_a_charts_folder_regenerates_the_fragment(project):
    assert make_project(project, "-q").returncode == 0
    (project / "enc" / "CELL.003").write_text("an update")
    past = time.time() - 3600  # the fragment older than the folder the update was added to
    os.utime(project / "pipeline.mk", (past, past))
    r = make_project(project, "-n")
    assert r.returncode == 0, r.stderr
    assert "--make-fragment pipeline.mk" in r.stdout and " preprocess enc/CELL.000 " not in r.stdout
    fragment = (project / "pipeline.mk").read_text()
    assert "CHART_INPUTS_s := enc/CELL.001 enc/CELL.002 enc/CELL.003\n" in fragment
    assert make_project(project, "-n", "-W", "enc/CELL.003").stdout.count(" preprocess ") == 1


@pytest.mark.parametrize("setting", ["MAKEFLAGS=s", "MAKEFLAGS=n", "MAKELEVEL=3"])
def test_the_tests_that_start_make_ignore_the_callers_make_and_pytest_settings(setting):
    """``make -s test`` exports MAKEFLAGS=s to the suite; the tests that start make pass
    all the same (they used to fail: a dry run printed nothing)."""
    name, _, value = setting.partition("=")
    r = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:xdist", "-p",
                        "no:cacheprovider", f"{__file__}::test_a_file_new_in_a_charts_folder"
                        "_regenerates_the_fragment"], cwd=ROOT, capture_output=True, text=True,
                       env={**os.environ, name: value})  # fmt: skip
    assert r.returncode == 0 and "1 passed" in r.stdout, r.stdout + r.stderr
