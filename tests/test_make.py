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
    subprocess.run([sys.executable, "-m", "usvtool.pipeline", "make", "pipelines/report.yaml",
                    "-o", fragment], cwd=ROOT, check=True)  # fmt: skip
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


@pytest.mark.parametrize("changed", ["usvtool/measure/table.py", "usvtool/sim/run.py"])
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


def make_report(tree: Path, *args: str) -> subprocess.CompletedProcess:
    variables = [f"BIN={Path(sys.executable).parent}", f"BUILD={tree}", f"STAMP={tree / 'stamp'}",
                 f"SYSTEM_STAMP={tree / 'system'}"]  # fmt: skip
    return subprocess.run(["make", *variables, *args, "report"], cwd=ROOT, capture_output=True,
                          text=True)  # fmt: skip


def test_a_second_make_report_does_nothing(report_tree):
    assert make_report(report_tree, "-q").returncode == 0


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
