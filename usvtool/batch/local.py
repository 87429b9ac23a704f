"""The local executor: long-lived worker processes (pebble's ``ProcessPool``, spawned).

Each worker imports what the jobs need once and runs one job at a time in-process. A worker
that dies in a job (``os._exit``, a segfault, a kill) fails that job only: pebble reports it
on that job's future (``ProcessExpired``) and starts a new worker. Workers ignore SIGINT: a
Ctrl-C reaches the batch, which stops the pool (SIGTERM to the workers: a running command
removes its temporaries). With a ``timeout``, a job running longer is stopped (pebble
terminates its worker, SIGTERM, and starts a new one) and fails with that reason.
"""

from __future__ import annotations

import multiprocessing
import signal
from concurrent.futures import Future


def _ignore_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _death(exitcode: int | None) -> str:
    if exitcode is not None and exitcode < 0:
        try:
            return f"killed by {signal.Signals(-exitcode).name}"
        except ValueError:
            return f"killed by signal {-exitcode}"
    return f"exit status {exitcode}"


class LocalPool:
    """``workers`` processes on this machine; ``timeout``: seconds a job may run (None: any)."""

    def __init__(self, workers: int, timeout: float | None = None):
        import pebble

        self.capacity = workers
        self.timeout = timeout
        self.name = f"local, {workers} worker{'s' * (workers > 1)}"
        self._pool = pebble.ProcessPool(max_workers=workers, initializer=_ignore_sigint,
                                        context=multiprocessing.get_context("spawn"))  # fmt: skip
        self._closed = False

    def submit(self, label: str, function, *args, limited: bool = False) -> Future:
        """Run ``function(*args)`` in a worker, within the timeout if ``limited`` (a job, not
        the table); ``label`` names the task (unused here)."""
        return self._pool.schedule(function, args, timeout=self.timeout if limited else None)

    def failure(self, exc: BaseException) -> str:
        """The one-line error of a task that raised ``exc``."""
        import pebble

        if isinstance(exc, pebble.ProcessExpired):
            return f"its worker process died ({_death(exc.exitcode)})"
        if isinstance(exc, TimeoutError):
            return f"it ran longer than --timeout {self.timeout:g} s and was stopped"
        return f"{type(exc).__name__}: {exc}"

    def close(self, pending=None) -> None:
        """Let the workers finish; with ``pending`` (futures), stop them now instead."""
        if self._closed:
            return
        self._closed = True
        if pending is not None:
            self._pool.stop()
        else:
            self._pool.close()
        self._pool.join()
