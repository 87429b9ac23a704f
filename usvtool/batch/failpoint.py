"""Fault injection for the batch's tests: kill a worker at a named point of a job's life, or
hang its job.

``USVTOOL_FAILPOINT="POINT:KEY[,POINT:KEY...]"`` in the environment of ``usvtool batch`` makes the
worker running the job whose key is ``KEY`` kill itself with SIGKILL at ``POINT``:

- ``before``: the worker has received the job and not started it;
- ``during``: the job's command has its fresh directory and is about to run;
- ``written``: the job's directory is complete and renamed into place, the outcome not sent;
- ``sending``: the outcome is half-way through the pipe to the parent (local pool only);

or, with ``hang:KEY``, make the job's command sleep for ever where ``during`` would kill: a job
that never ends however fast the machine is, for ``--timeout``'s tests (a job that merely runs
long stops being long on a fast machine, and a short one is not short under load).

Not set (the normal case), :func:`reach` costs one dictionary lookup. A failpoint, not a mock:
the worker really dies, so the tests see what a SIGKILL, an OOM kill or a segfault does there.
"""

from __future__ import annotations

import os
import pickle
import signal
import struct
import time

POINTS = ("before", "during", "written", "sending")
#: The failpoint that hangs a job (at ``during``) rather than kill its worker.
HANG = "hang"
VARIABLE = "USVTOOL_FAILPOINT"


def reach(point: str, label: str, conn=None) -> None:
    """Kill this process if ``point`` is armed for the job ``label`` names (a job's key, or a
    task label ending in it). At ``sending``, first write half of a reply on ``conn``
    (``multiprocessing``'s framing: a 4-byte length, then the bytes) so that the parent's read is
    cut short."""
    armed = os.environ.get(VARIABLE)
    if not armed:
        return
    items = [(p, k) for p, _, k in (item.partition(":") for item in armed.split(","))]
    if point == "during" and any(p == HANG and label.endswith(k) for p, k in items):
        while True:  # until --timeout stops the job
            time.sleep(60)
    if not any(point == p and label.endswith(k) for p, k in items):
        return
    if conn is not None:
        body = pickle.dumps((True, "a reply cut short"))
        os.write(conn.fileno(), struct.pack("!i", len(body)) + body[: len(body) // 2])
    os.kill(os.getpid(), signal.SIGKILL)
