"""The Dask executor: jobs as tasks on an existing dask.distributed cluster (``--scheduler``).

Imported only when used (``pip install 'usvtool[dask]'``). Each job is one task whose key
names the job (``usvtool-<kind>-<key>-<random>``), so replicate runs, which differ in their
seed and so in their key, are never merged, and a rerun is a new task. The workers run the
same function as the local pool's, in their own processes, on the files of a filesystem they
share with the batch (docs/cluster.md). A worker that dies in a task makes the scheduler try
the task on another worker, up to its ``allowed-failures``; then the job fails
(``KilledWorker``) and the others go on.
"""

from __future__ import annotations

import secrets
import socket

from usvtool.errors import UsvError

CONNECT_TIMEOUT_S = 10


class DaskCluster:
    """A client of the scheduler at ``address`` (``tcp://HOST:PORT``)."""

    def __init__(self, address: str):
        try:
            from distributed import Client
        except ImportError:
            raise UsvError("--scheduler: dask.distributed is not installed (pip install "
                           "'usvtool[dask]')") from None  # fmt: skip
        from distributed.comm.addressing import parse_host_port

        scheme, sep, location = address.partition("://")
        try:
            host, port = parse_host_port(location) if sep else (None, None)
        except ValueError as exc:
            host, port = None, exc
        if host is None:
            why = f" ({port})" if port else ""
            raise UsvError(f"--scheduler {address}: not a scheduler address{why}; expected "
                           "tcp://HOST:PORT")  # fmt: skip
        try:
            if scheme == "tcp":  # refused at once (Dask would retry until its timeout)
                socket.create_connection((host, port), timeout=CONNECT_TIMEOUT_S).close()
            self._client = Client(address, timeout=CONNECT_TIMEOUT_S, set_as_default=False)
        except (OSError, TimeoutError) as exc:
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise UsvError(f"--scheduler {address}: cannot reach the scheduler: {reason}") from None
        threads = sum(self._client.nthreads().values())
        self.capacity = max(1, threads)
        self.name = f"dask {address}, {threads} worker thread{'s' * (threads != 1)}"
        self._closed = False

    def submit(self, label: str, function, *args, limited: bool = False):
        """Run ``function(*args)`` as a task keyed by ``label`` and a random suffix (no time
        limit: a Dask task cannot be stopped once it runs, so ``usvtool batch`` refuses
        ``--timeout`` with ``--scheduler``)."""
        key = f"usvtool-{label}-{secrets.token_hex(4)}"
        return self._client.submit(function, *args, key=key, pure=False, retries=0)

    @staticmethod
    def failure(exc: BaseException) -> str:
        from distributed.scheduler import KilledWorker

        if isinstance(exc, KilledWorker):
            return "its worker process died on every worker it was tried on (dask KilledWorker)"
        return f"{type(exc).__name__}: {exc}"

    def close(self, pending=None) -> None:
        """Disconnect; with ``pending`` (futures), cancel those tasks first."""
        if self._closed:
            return
        self._closed = True
        if pending:
            self._client.cancel(list(pending))
        self._client.close()
