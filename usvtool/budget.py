"""The memory budget: how much a job may need, and the one check against it.

``preprocess``, ``plan`` and ``simulate`` estimate the peak memory of a job from the sizes they
know before allocating (a raster's header, a grid's header, the controller's samples, the run's
steps) and call :func:`require`, which refuses a job past the budget in one line naming what
needs the memory, how much, the budget and the option that brings the need down. Each stage's
per-element figures are measured peaks (docs/preprocess.md, docs/planning.md,
docs/simulate.md).

The budget is ``--max-memory`` (:func:`parse_size`: ``4G``, ``512M``, ``2.5GiB`` or plain
bytes), by default the least of :data:`DEFAULT_FRACTION` of the machine's memory
(:func:`machine_memory`) and :data:`ROOM_FRACTION` of the room left under the process's
address-space limits (:func:`room_budget`). ``usvtool batch`` gives each job its share of its
own budget (docs/batch.md). A job allowed that still runs out of memory (the estimate was short,
or ``--max-memory`` more than the process can map) ends in one line all the same: the stages
wrap their big allocations in :func:`allocating`.

>>> parse_size("2.5GiB") == 5 * 2**29, parse_size("512m"), parse_size("1000")
(True, 536870912, 1000)
>>> require(2 * 2**30, "x.tif: reading 10 x 10 pixels", "give a smaller image", budget=2**30)
Traceback (most recent call last):
...
usvtool.errors.UsvError: x.tif: reading 10 x 10 pixels needs about 2.00 GiB of memory, more \
than the budget of 1.00 GiB (--max-memory); give a smaller image
"""

from __future__ import annotations

import math
import os
import re
import resource
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from usvtool.errors import UsvError

#: The default budget's share of the machine's memory: a job may take half, leaving the rest
#: to the system and the other programs (two local batch workers get a quarter each).
DEFAULT_FRACTION = 0.5
#: The share of the room left under RLIMIT_AS (RLIMIT_DATA) that a job may count on: the limit
#: minus what is mapped when the job is checked (``VmSize``, ``VmData``). The rest is for what
#: the process maps after the check beyond the estimate: numba's and LLVM's compilations, the
#: threads' malloc arenas, a library's reserved but untouched mappings (measured 1.1-1.3 times
#: the estimate for small runs, 0.6-0.9 for large ones: docs/preprocess.md, "Memory budget").
ROOM_FRACTION = 0.75
#: Each address-space limit and the ``/proc/self/status`` field of what it already counts.
_LIMITS = ((resource.RLIMIT_AS, "VmSize"), (resource.RLIMIT_DATA, "VmData"))
MiB = 1 << 20
GiB = 1 << 30
_UNITS = {"": 1, "k": 1 << 10, "m": MiB, "g": GiB, "t": 1 << 40}
_SIZE = re.compile(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*(?:([kmgt])(?:i?b)?|b)?\s*", re.IGNORECASE)


def parse_size(text: str) -> int:
    """Bytes of a size: a number, optionally followed by K, M, G or T (with or without ``B`` or
    ``iB``; every unit a power of 1024, as Docker and Slurm read them). ``ValueError`` for
    anything else, or a size under one byte.

    >>> parse_size("4G"), parse_size("4 GB"), parse_size("1.5k")
    (4294967296, 4294967296, 1536)
    """
    match = _SIZE.fullmatch(str(text))
    if match is None:
        raise ValueError(f"{text!r} is not a size (e.g. 4G, 512M, 2.5GiB or bytes)")
    number, unit = match.groups()
    size = int(float(number) * _UNITS[(unit or "").lower()])
    if size < 1:
        raise ValueError(f"{text!r} is under one byte")
    return size


def machine_memory() -> int:
    """Bytes of memory this process can have: the machine's physical memory (``os.sysconf``,
    else ``/proc/meminfo``), or its cgroup's ``memory.max`` when that is lower (a container's
    limit)."""
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        total = _meminfo_total()
    limit = _cgroup_limit()
    return min(total, limit) if limit else total


def default_budget() -> int:
    """The budget when none is given: :data:`DEFAULT_FRACTION` of :func:`machine_memory`, or
    :func:`room_budget` when that is lower."""
    share = int(machine_memory() * DEFAULT_FRACTION)
    room = room_budget()
    return share if room is None else min(share, room)


def room_budget() -> int | None:
    """:data:`ROOM_FRACTION` of the room left under the process's soft RLIMIT_AS and
    RLIMIT_DATA (the limit minus what it already counts), the lesser; None when neither is
    set."""
    rooms = [limit - _status_bytes(field) for kind, field in _LIMITS
             if (limit := _soft_limit(kind)) is not None]  # fmt: skip
    return int(max(0, min(rooms)) * ROOM_FRACTION) if rooms else None


def require(nbytes: float, what: str, remedy: str, budget: int | None = None) -> None:
    """Refuse (:class:`UsvError`) a job whose estimated need ``nbytes`` exceeds ``budget``
    (None: :func:`default_budget`): one line, ``"{what} needs about N GiB of memory, more than
    the budget of B GiB (--max-memory); {remedy}"``. ``what`` names the input, the work and its
    sizes ("x.tif: reading 100 x 100 pixels"), ``remedy`` the option or field that brings the
    need down."""
    budget = default_budget() if budget is None else budget
    if nbytes > budget:
        raise UsvError(
            f"{what} needs about {size_text(nbytes)} of memory, more than the budget of "
            f"{size_text(budget)} (--max-memory); {remedy}"
        )


@contextmanager
def allocating(nbytes: float, what: str, remedy: str) -> Iterator[None]:
    """Turn a ``MemoryError`` raised inside into a one-line :class:`UsvError`: ``"out of memory
    while {what} (about N GiB needed); {remedy}"``, ``what`` naming the input and the work
    (``"reading 10 x 10 pixels of x.tif"``), ``nbytes`` its estimated need.

    >>> with allocating(3 * GiB, "reading 10 x 10 pixels of x.tif", "give a smaller image"):
    ...     raise MemoryError
    Traceback (most recent call last):
    ...
    usvtool.errors.UsvError: out of memory while reading 10 x 10 pixels of x.tif (about 3.00 \
GiB needed); give a smaller image
    """
    try:
        yield
    except MemoryError:
        raise UsvError(
            f"out of memory while {what} (about {size_text(nbytes)} needed); {remedy}"
        ) from None


def size_text(nbytes: float) -> str:
    """A size for messages: GiB to three digits (at least), MiB below a tenth of a GiB.

    >>> size_text(75.44 * GiB), size_text(1.164 * GiB), size_text(9313.2 * GiB), size_text(3 * MiB)
    ('75.4 GiB', '1.16 GiB', '9313 GiB', '3 MiB')
    """
    if nbytes < GiB / 10:
        return f"{math.ceil(nbytes / MiB)} MiB"
    gib = nbytes / GiB
    return f"{gib:.{2 if gib < 10 else 1 if gib < 100 else 0}f} GiB"


def _meminfo_total() -> int:
    for line in Path("/proc/meminfo").read_text().splitlines():
        if line.startswith("MemTotal:"):
            return int(line.split()[1]) * 1024
    raise OSError("/proc/meminfo: no MemTotal")


def _soft_limit(kind: int) -> int | None:
    """The soft limit of resource ``kind`` in bytes, None when unlimited."""
    soft = resource.getrlimit(kind)[0]
    return None if soft == resource.RLIM_INFINITY else soft


def _status_bytes(field: str) -> int:
    """Bytes of a ``/proc/self/status`` size field (``VmSize``, ``VmData``), 0 when unknown."""
    try:
        lines = Path("/proc/self/status").read_text().splitlines()
    except OSError:
        return 0
    return next((int(line.split()[1]) * 1024 for line in lines
                 if line.startswith(f"{field}:")), 0)  # fmt: skip


def _cgroup_limit() -> int | None:
    """The cgroup v2 ``memory.max`` of this process, None when unlimited or unknown."""
    try:
        lines = Path("/proc/self/cgroup").read_text().splitlines()
        group = next(line[3:] for line in lines if line.startswith("0::"))
        text = (Path("/sys/fs/cgroup") / group.lstrip("/") / "memory.max").read_text().strip()
    except (OSError, StopIteration):
        return None
    return int(text) if text.isdigit() else None
