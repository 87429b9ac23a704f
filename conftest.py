"""pytest at the project's root (tests/conftest.py holds the suite's fixtures): usvtool.gym's
doctests need gymnasium, the gym extra (docs/gym.md), which make test installs; without it that
package is not collected, as tests/gym skips its environment's tests.

BLAS on one thread in the test processes and what they start, as usvtool's command line runs it
(:func:`usvtool.cli.main`): set before anything loads NumPy, and so before the workers start."""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

try:
    import gymnasium  # noqa: F401
except ImportError:
    collect_ignore = ["usvtool/gym"]
