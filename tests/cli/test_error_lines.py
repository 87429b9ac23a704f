"""The CLI's last line of defence: any error is one line, cut when huge, naming the file the
operating system refused."""

from __future__ import annotations

import errno
import os

import pytest

from usvtool.errors import LINE, UsvError, one_line


@pytest.fixture
def failing(monkeypatch, runner):
    """``failing(exc)`` runs ``usvtool compare`` with its function raising ``exc``."""
    from usvtool.cli import cli

    def run(exc):
        def boom(*args, **kwargs):
            raise exc

        monkeypatch.setattr("usvtool.report.regression.compare.compare", boom)
        return runner.invoke(cli, ["compare", "a.csv", "b.csv"], catch_exceptions=False)

    return run


def test_a_huge_error_is_cut_to_one_line_keeping_both_ends(failing):
    r = failing(UsvError("s.yaml: controller.sides must be numbers, not " + "[9, " * 10**5 + "]"
                         + " (known: a, b)"))  # fmt: skip
    assert r.exit_code == 1
    (line,) = r.stderr.splitlines()
    assert len(line) <= LINE + len("Error: ")
    assert line.startswith("Error: s.yaml: controller.sides") and line.endswith("(known: a, b)")


def test_an_os_error_naming_a_file_is_one_line_not_an_internal_error(failing):
    r = failing(PermissionError(errno.EACCES, os.strerror(errno.EACCES), "/x/metrics.csv"))
    assert r.exit_code == 1
    assert r.stderr == "Error: /x/metrics.csv: Permission denied\n"


def test_one_line_leaves_short_text_alone():
    assert one_line("a.csv: line 3:\n bad") == "a.csv: line 3: bad"
    assert one_line("x" * LINE) == "x" * LINE
    assert len(one_line("x" * (LINE + 1))) == LINE
