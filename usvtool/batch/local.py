"""The local executor: long-lived worker processes (spawned), each with a pipe of its own.

Each worker imports what the jobs need once and runs one task at a time. The parent alone
decides which worker runs which task, so it always knows what a dead worker was doing: a
worker that dies at any point (before it reads its task, in the task, after the task wrote its
result, or half-way through sending it back) fails that task only, and a new worker takes its
place. Workers ignore SIGINT: a Ctrl-C reaches the batch, which stops the pool (SIGTERM to the
workers: a running command removes its temporaries; SIGKILL :data:`GRACE_S` later). With a
``timeout``, a task running longer fails with :class:`TimeoutError` and its worker is stopped
the same way.

Hand-written: pebble's ``ProcessPool`` (used before) shares one task pipe and a process-shared
lock among its workers, and settles a dead worker's task from a thread that races with the one
reading the task's acknowledgement: a worker killed just after taking a task left that task
pending for ever (``usvtool batch`` hung at 13/14 jobs), and one killed holding the lock stops
the pool (pebble issues #97, #163). ``concurrent.futures.ProcessPoolExecutor`` and loky break
the whole pool, every pending task failing, when one worker dies.

Fault injection (tests): :func:`usvtool.batch.failpoint.reach` kills a worker at a named point.
"""

from __future__ import annotations

import multiprocessing
import signal
import threading
import time
from collections import deque
from concurrent.futures import Future
from multiprocessing.connection import Connection, wait

from usvtool.batch.failpoint import reach

#: Seconds a stopped worker has to remove its temporaries after SIGTERM, before SIGKILL.
GRACE_S = 5.0


class WorkerDied(Exception):
    """The worker running a task ended before sending its result; ``exitcode`` as
    ``multiprocessing`` gives it (negative: the signal that killed it)."""

    def __init__(self, exitcode: int | None):
        self.exitcode = exitcode
        super().__init__(_death(exitcode))


def _death(exitcode: int | None) -> str:
    if exitcode is not None and exitcode < 0:
        try:
            return f"killed by {signal.Signals(-exitcode).name}"
        except ValueError:
            return f"killed by signal {-exitcode}"
    return f"exit status {exitcode}"


def _serve(conn: Connection) -> None:
    """A worker's life: receive ``(label, function, args)``, send ``(ok, value)`` back, until
    the parent sends None or closes the pipe."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    while True:
        try:
            task = conn.recv()
        except EOFError:
            return
        if task is None:
            return
        label, function, args = task
        reach("before", label)
        try:
            reply = (True, function(*args))
        except Exception as exc:  # the task's own failure, sent back to its future
            reply = (False, exc)
        reach("sending", label, conn)
        try:
            conn.send(reply)
        except Exception as exc:  # a result or exception that cannot be pickled
            conn.send((False, RuntimeError(f"cannot send the result back: {exc}")))


class _Worker:
    """One worker process and the parent's end of its pipe; ``task`` its running task."""

    def __init__(self, context) -> None:
        self.conn, child = context.Pipe()
        self.process = context.Process(target=_serve, args=(child,), daemon=True,
                                       name="usvtool-worker")  # fmt: skip
        self.process.start()
        child.close()  # the parent holds only its end: the child's death reads as EOF
        self.task: tuple[Future, float | None] | None = None  # (future, deadline)
        self.kill_at: float | None = None  # stopped: SIGKILL then if still alive

    def deadlines(self) -> list[float]:
        """When the pool must look at this worker again: its task's time limit, its SIGKILL."""
        return [t for t in (self.kill_at, self.task and self.task[1]) if t is not None]

    def stop(self) -> None:
        """SIGTERM now, SIGKILL after the grace period (:meth:`LocalPool._reap`)."""
        if self.kill_at is None:
            self.kill_at = time.monotonic() + GRACE_S
            if self.process.is_alive():
                self.process.terminate()


class LocalPool:
    """``workers`` processes on this machine; ``timeout``: seconds a limited task may run (None:
    any). Futures are :class:`concurrent.futures.Future`; their callbacks run in the pool's
    thread."""

    def __init__(self, workers: int, timeout: float | None = None):
        self.capacity = workers
        self.timeout = timeout
        self.name = f"local, {workers} worker{'s' * (workers > 1)}"
        self._context = multiprocessing.get_context("spawn")
        self._queue: deque[tuple[Future, tuple, float | None]] = deque()
        self._workers: list[_Worker] = []
        self._lock = threading.RLock()  # a future's callback may submit
        self._wake_r, self._wake_w = self._context.Pipe(duplex=False)
        self._closing = False
        self._closed = False
        self._thread = threading.Thread(target=self._loop, name="usvtool-pool", daemon=True)
        self._thread.start()

    def submit(self, label: str, function, *args, limited: bool = False) -> Future:
        """Run ``function(*args)`` in a worker, within the timeout if ``limited`` (a job, not
        the table); ``label`` names the task (for :mod:`usvtool.batch.failpoint`)."""
        future: Future = Future()
        with self._lock:
            if self._closing:
                raise RuntimeError("the pool is closed")
            self._queue.append((future, (label, function, args), self.timeout if limited else None))
        self._wake()
        return future

    def failure(self, exc: BaseException) -> str:
        """The one-line error of a task that raised ``exc``."""
        if isinstance(exc, WorkerDied):
            return f"its worker process died ({exc})"
        if isinstance(exc, TimeoutError):
            return f"it ran longer than --timeout {self.timeout:g} s and was stopped"
        return f"{type(exc).__name__}: {exc}"

    def close(self, pending=None) -> None:
        """Let the workers finish the tasks given; with ``pending`` (futures), stop them now
        instead (SIGTERM), cancelling the tasks not started."""
        if self._closed:
            return
        self._closed = True
        with self._lock:
            self._closing = True
            if pending is not None:
                while self._queue:
                    self._queue.popleft()[0].cancel()
                for worker in self._workers:
                    worker.stop()
        self._wake()
        self._thread.join()
        self._wake_r.close()
        self._wake_w.close()

    def _wake(self) -> None:
        try:
            self._wake_w.send_bytes(b"")
        except OSError:  # closed: the loop has ended
            pass

    def _loop(self) -> None:
        """:meth:`_run`; should it fail (a bug), every task not settled fails with its error
        rather than waiting for ever."""
        try:
            self._run()
        except BaseException as exc:
            with self._lock:
                running = [w.task[0] for w in self._workers if w.task is not None]
                queued = [item[0] for item in self._queue]
                self._queue.clear()
            queued = [f for f in queued if f.set_running_or_notify_cancel()]
            for future in running + queued:
                future.set_exception(exc)
            for worker in self._workers:
                worker.process.kill()
            raise

    def _run(self) -> None:
        """Hand out tasks, collect results, settle dead and late workers, until closed and
        idle; then end the workers."""
        while True:
            with self._lock:
                self._dispatch()
                busy = [w for w in self._workers if w.task is not None]
                if self._closing and not self._queue and not busy:
                    break
                waits = [self._wake_r] + [w.conn for w in busy]
                waits += [w.process.sentinel for w in self._workers]
                deadline = min((t for w in self._workers for t in w.deadlines()), default=None)
            timeout = None if deadline is None else max(0.0, deadline - time.monotonic())
            ready = wait(waits, timeout)
            with self._lock:
                if self._wake_r in ready:
                    while self._wake_r.poll():
                        self._wake_r.recv_bytes()
                for worker in [w for w in self._workers if w.conn in ready]:
                    self._collect(worker)
                self._reap()
        for worker in self._workers:  # idle: ask each to end, then wait
            try:
                worker.conn.send(None)
            except OSError:
                pass
        for worker in self._workers:
            worker.process.join(GRACE_S)
            if worker.process.is_alive():
                worker.process.kill()
                worker.process.join()
            worker.conn.close()

    def _dispatch(self) -> None:
        """Give queued tasks to idle workers, starting workers up to the capacity."""
        while self._queue:
            idle = next((w for w in self._workers if w.task is None and w.kill_at is None), None)
            if idle is None:
                if len(self._workers) >= self.capacity:
                    return
                idle = _Worker(self._context)
                self._workers.append(idle)
            future, task, limit = self._queue.popleft()
            if not future.set_running_or_notify_cancel():
                continue
            idle.task = (future, None if limit is None else time.monotonic() + limit)
            try:
                idle.conn.send(task)
            except OSError:  # a dead worker (EPIPE): its task fails when _reap sees it dead
                continue
            except Exception as exc:  # arguments that cannot be pickled
                idle.task = None
                future.set_exception(exc)

    def _collect(self, worker: _Worker) -> None:
        """Read a worker's reply. A reply cut short means the worker is ending: wait for it
        (SIGKILL past the grace period), and its task fails with its death."""
        try:
            ok, value = worker.conn.recv()
        except (EOFError, OSError):
            worker.process.join(GRACE_S)
            if worker.process.is_alive():
                worker.process.kill()
                worker.process.join()
            return
        if worker.task is not None:
            future, worker.task = worker.task[0], None
            future.set_result(value) if ok else future.set_exception(value)

    def _reap(self) -> None:
        """Fail the task of every dead worker (a reply it sent before dying counts) and of every
        late one (stopping it), SIGKILL stopped workers past their grace, forget the dead."""
        now = time.monotonic()
        for worker in list(self._workers):
            alive = worker.process.is_alive()  # read once: a death after it is seen next time
            if worker.task is not None and not alive:
                if worker.conn.poll():
                    self._collect(worker)
                if worker.task is not None:
                    future, worker.task = worker.task[0], None
                    future.set_exception(WorkerDied(worker.process.exitcode))
            elif worker.task is not None and worker.task[1] is not None and worker.task[1] <= now:
                future, worker.task = worker.task[0], None
                future.set_exception(TimeoutError())
                worker.stop()
            if alive and worker.kill_at is not None and worker.kill_at <= now:
                worker.process.kill()
            if not alive:
                worker.process.join()
                worker.conn.close()
                self._workers.remove(worker)
