"""Progress on stderr: a rich progress bar on a terminal, plain lines otherwise.

Both print each failure as it happens and a final line with the counts and the time. The plain
lines come every :data:`EVERY_S` seconds (and are what a log file or CI shows), each with the
time left at the pace so far (:func:`remaining`), as the bar shows it.
"""

from __future__ import annotations

import sys
import time

EVERY_S = 5.0


def counts(done: int, skipped: int, failed: int) -> str:
    return f"{done} done, {skipped} skipped, {failed} failed"


def remaining(elapsed: float, ran: int, left: int) -> str:
    """``, about N s left``: the jobs left at the pace of the jobs run so far (the skipped ones,
    already done, took no time); '' before any job ran or when none is left.

    >>> remaining(50.0, 10, 30), remaining(50.0, 0, 30), remaining(9.0, 10, 0)
    (', about 150 s left', '', '')
    """
    if ran == 0 or left == 0:
        return ""
    return f", about {elapsed / ran * left:.0f} s left"


class Lines:
    """A status line every :data:`EVERY_S` seconds, a line per failure."""

    def __init__(self, total: int, skipped: int, where: str, stream=None):
        self.stream = stream or sys.stderr
        self.total, self.skipped, self.done, self.failed = total, skipped, 0, 0
        self.started = self.last = time.monotonic()
        self.say(f"batch: {total} jobs, {skipped} already done, on {where}")

    def say(self, text: str) -> None:
        print(text, file=self.stream, flush=True)

    def advance(self, label: str, error: str | None) -> None:
        if error is None:
            self.done += 1
        else:
            self.failed += 1
            self.say(f"batch: FAILED {label}: {error}")
        self.tick()

    def tick(self) -> None:
        now = time.monotonic()
        if now - self.last >= EVERY_S:
            self.last = now
            finished = self.skipped + self.done + self.failed
            tally = counts(self.done, self.skipped, self.failed)
            elapsed = now - self.started
            left = remaining(elapsed, self.done + self.failed, self.total - finished)
            self.say(f"batch: {finished}/{self.total} ({tally}) after {elapsed:.0f} s{left}")

    def close(self) -> None:
        elapsed = time.monotonic() - self.started
        self.say(f"batch: {self.total} jobs: {counts(self.done, self.skipped, self.failed)} in "
                 f"{elapsed:.1f} s")  # fmt: skip


class Bar(Lines):
    """A rich progress bar (jobs finished of all, elapsed and remaining time)."""

    def __init__(self, total: int, skipped: int, where: str):
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        console = Console(stderr=True)
        self._bar = Progress(TextColumn("batch"), BarColumn(), MofNCompleteColumn(),
                             TextColumn("{task.fields[failed]} failed"), TimeElapsedColumn(),
                             TimeRemainingColumn(), console=console)  # fmt: skip
        self._bar.start()
        self._task = self._bar.add_task("batch", total=total, completed=skipped, failed=0)
        super().__init__(total, skipped, where, console.file)

    def say(self, text: str) -> None:
        self._bar.console.print(text, highlight=False, markup=False)

    def tick(self) -> None:
        self._bar.update(self._task, completed=self.skipped + self.done + self.failed,
                         failed=self.failed)  # fmt: skip

    def close(self) -> None:
        self.tick()
        self._bar.stop()
        super().close()
