"""The ``usvtool plan`` examples of docs/planning.md and README.md run as written.

Every ``usvtool plan`` line of the files' ``sh`` code blocks (continuation lines joined) runs
from a project root in a temporary directory: ``charts/`` the bundled charts, ``build/grids/``
every grid the examples name, made as ``make charts`` makes it (``usvtool preprocess`` with the
chart's options from pipelines/report.yaml). Each must exit 0 with a collision-free route.
About 15 s: the Boston and Mississippi grids take about 2 s each to build and to plan on.
"""

from __future__ import annotations

import json
import re
import shlex
from pathlib import Path

import pytest
from click.testing import CliRunner

from usvtool.batch.commands import option_args
from usvtool.cli import cli
from usvtool.pipeline import load

ROOT = Path(__file__).resolve().parent.parent
DOCS = ("docs/planning.md", "README.md")


def plan_examples(text: str) -> list[str]:
    """The ``usvtool plan`` command lines of the ``sh`` code blocks of a Markdown text, each on
    one line with single spaces."""
    commands = []
    for block in re.findall(r"^```sh\n(.*?)^```", text, re.S | re.M):
        for line in block.replace("\\\n", " ").splitlines():
            if line.startswith("usvtool plan "):
                commands.append(" ".join(line.split()))
    return commands


EXAMPLES = [(doc, c) for doc in DOCS for c in plan_examples((ROOT / doc).read_text())]


def test_the_examples_are_found():
    text = "text\n```sh\nusvtool plan a.tif --start 1 2 \\\n    --goal 3 4 -o p.geojson\nls\n```\n"
    text += "```python\nusvtool plan not.tif\n```\nusvtool plan outside.tif\n"
    assert plan_examples(text) == ["usvtool plan a.tif --start 1 2 --goal 3 4 -o p.geojson"]
    assert sum(doc == DOCS[0] for doc, _ in EXAMPLES) >= 5  # the five of the file's top
    assert any("build/grids/" in c for _, c in EXAMPLES)


@pytest.fixture(scope="module")
def project(tmp_path_factory) -> Path:
    """A project root: the bundled charts (a link) and the grids the examples name."""
    root = tmp_path_factory.mktemp("project")
    (root / "charts").symlink_to(ROOT / "charts")
    grids = root / "build" / "grids"
    grids.mkdir(parents=True)
    charts = load().charts
    names = sorted({n for _, c in EXAMPLES for n in re.findall(r"build/grids/(\w+)\.tif", c)})
    for name in names:
        if name not in charts:
            pytest.fail(f"an example plans on build/grids/{name}.tif: no chart of report.yaml")
        chart = charts[name]
        args = ["preprocess", str(ROOT / chart.source), *option_args(chart.options),
                "-o", grids / f"{name}.tif"]  # fmt: skip
        result = CliRunner().invoke(cli, [str(a) for a in args])
        assert result.exit_code == 0, result.output
    return root


@pytest.mark.parametrize("doc, command", EXAMPLES, ids=[f"{d}:{c[13:45]}" for d, c in EXAMPLES])
def test_a_plan_example_runs_as_written(project, monkeypatch, doc, command):
    monkeypatch.chdir(project)
    result = CliRunner().invoke(cli, shlex.split(command)[1:])
    assert result.exit_code == 0, f"{doc}: {command}\n{result.output}"
    summary = json.loads(result.stdout)
    assert summary["collision_free"] is True
    assert (project / summary["output"]).is_file()
