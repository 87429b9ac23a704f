"""How fast this machine is right now: the CPU time of a fixed workload, a yardstick for the
timings of ``make report`` and ``make test``.

The shared 2-core machine of this round ran the same code up to half again as slowly in some
hours as in others, so a timing means little without the machine's speed beside it. The
workload mixes what usvtool's work is made of: twenty 600 x 600 matrix products (NumPy's BLAS,
on one thread, as usvtool runs it) and three million steps of a Python loop (the interpreter).
It took 0.27-0.36 s of CPU at 16:10 on 2026-12-06, within the quarter hour `make report`
took 4 min 46 s from a fresh clone (README.md). Earlier that day the yardstick was the same
workload with NumPy's BLAS on its default two threads, whose spinning doubled its CPU time
(0.66-0.71 s at 16:10): 0.54-0.62 s in the machine's usual hours and 0.85-0.95 s in its slow
ones.

Usage: ``python benchmarks/machine_probe.py`` (prints ``probe <seconds>``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before NumPy loads OpenBLAS

import time  # noqa: E402

import numpy as np  # noqa: E402


def probe() -> float:
    """The CPU seconds of the fixed workload."""
    started = time.process_time()
    a = np.random.default_rng(0).random((600, 600))
    for _ in range(20):
        a @ a
    total = 0
    for i in range(3_000_000):
        total += i
    return time.process_time() - started


if __name__ == "__main__":
    print(f"probe {probe():.2f}")
