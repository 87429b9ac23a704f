"""The Python examples of docs/api.md run as written, in order, from a project root in a
temporary directory (``charts/`` the bundled charts), each block in a namespace of its own:
they share only the files they write. About 6 s: a batch of three jobs and its report."""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # a batch on a worker pool, then its report

ROOT = Path(__file__).resolve().parent.parent
API = ROOT / "docs" / "api.md"


def python_blocks(text: str) -> list[str]:
    """The ``python`` code blocks of a Markdown text, in order."""
    return re.findall(r"^```python\n(.*?)^```", text, re.S | re.M)


def test_the_blocks_are_found():
    text = "a\n```python\nx = 1\n```\n```sh\nls\n```\n```python\ny = 2\nz = 3\n```\n"
    assert python_blocks(text) == ["x = 1\n", "y = 2\nz = 3\n"]
    assert len(python_blocks(API.read_text(encoding="utf-8"))) == 7  # one per stage, animate


def test_the_examples_run_and_write_what_they_say(tmp_path, monkeypatch, capsys):
    (tmp_path / "charts").symlink_to(ROOT / "charts")
    monkeypatch.chdir(tmp_path)
    for i, block in enumerate(python_blocks(API.read_text(encoding="utf-8"))):
        exec(compile(block, f"docs/api.md block {i + 1}", "exec"), {"__name__": "__api__"})
    printed = capsys.readouterr().out
    assert (tmp_path / "env1.tif").is_file()
    table = list(csv.DictReader(io.StringIO(printed[printed.index("chart,") :])))
    routes = {r["algorithm"]: r for r in table if r["chart"] == "env1"}
    assert set(routes) == {"iwso", "anyangle"} and routes["anyangle"]["length_ratio"] == "1.0"
    assert float(routes["iwso"]["length_ratio"]) >= 1.0
    (run,) = [r for r in table if r["run"]]
    assert run["scenario"] == "env1-head-on" and run["controller"] == "dwa"
    assert "3 jobs done, 0 failed" in printed
    assert (tmp_path / "batch" / "metrics.csv").is_file()
    assert (tmp_path / "head-on.html").read_bytes().startswith(b"<!DOCTYPE html>")
    assert (tmp_path / "report" / "index.html").is_file()
    assert not (tmp_path / "report" / "report.pdf").exists()  # pdf=False
