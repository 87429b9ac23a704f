"""pytest at the project's root (tests/conftest.py holds the suite's fixtures): usvtool.gym's
doctests need gymnasium, the gym extra (docs/gym.md), which make test installs; without it that
package is not collected, as tests/gym skips its environment's tests."""

try:
    import gymnasium  # noqa: F401
except ImportError:
    collect_ignore = ["usvtool/gym"]
