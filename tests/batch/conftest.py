"""The batch tests' helpers: ``usvtool batch`` run in this process with its jobs run in this
process too (an executor that runs each task as it is submitted), so that a batch of small
jobs takes a fraction of a second and a test can patch what the jobs see."""

from __future__ import annotations

import json
from concurrent.futures import Future
from dataclasses import dataclass
from pathlib import Path

import pytest
from click.testing import CliRunner

from usvtool.cli import cli


class Inline:
    """An executor that runs each task in this process when it is submitted."""

    capacity = 1
    name = "inline"

    def submit(self, label: str, function, *args, limited: bool = False) -> Future:
        future: Future = Future()
        try:
            future.set_result(function(*args))
        except Exception as exc:
            future.set_exception(exc)
        return future

    @staticmethod
    def failure(exc: BaseException) -> str:
        return f"{type(exc).__name__}: {exc}"

    def close(self, pending=None) -> None:
        pass


@dataclass
class Ran:
    """What ``usvtool batch`` did: its exit status, stdout's summary (None when it printed
    none) and stderr."""

    exit_code: int
    summary: dict | None
    stderr: str

    def counts(self) -> tuple[int, int, int]:
        """(done, skipped, failed)."""
        assert self.summary is not None, self.stderr
        return self.summary["done"], self.summary["skipped"], self.summary["failed"]


@pytest.fixture
def inline_batch(monkeypatch):
    """``inline_batch(PIPELINE, OUT, *options)``: ``usvtool batch`` in this process."""
    monkeypatch.setattr("usvtool.batch.engine._executor", lambda options: Inline())

    def run(pipeline: Path, out: Path, *options) -> Ran:
        r = CliRunner().invoke(cli, ["batch", str(pipeline), "-o", str(out), *map(str, options)])
        if r.exception is not None and not isinstance(r.exception, SystemExit):
            raise r.exception
        return Ran(r.exit_code, json.loads(r.stdout) if r.stdout else None, r.stderr)

    return run
