"""The memory budget contract (usvtool/budget.py): sizes, the default budget and the check."""

from pathlib import Path

import pytest

from usvtool import budget
from usvtool.budget import GiB, MiB, parse_size, require
from usvtool.errors import UsvError


@pytest.mark.parametrize("text, size", [
    ("4G", 4 * 1024**3), ("4g", 4 * 1024**3), ("4 GB", 4 * 1024**3), ("4GiB", 4 * 1024**3),
    ("512M", 512 * 1024**2), ("512mib", 512 * 1024**2), ("2.5GiB", 2684354560),
    ("1000", 1000), ("1000B", 1000), ("1.5k", 1536), (" 3T ", 3 * 1024**4), (".5K", 512),
])  # fmt: skip
def test_sizes(text, size):
    assert parse_size(text) == size


@pytest.mark.parametrize("text", ["", "G", "lots", "4X", "-1G", "0", "0.4", "1e9", "4 G B",
                                  "nan", "inf", "4GG", "1000iB", "4 iB"])  # fmt: skip
def test_not_sizes(text):
    with pytest.raises(ValueError, match="is not a size|under one byte"):
        parse_size(text)


def test_require_refuses_past_the_budget_in_one_line():
    require(GiB, "x", "y", budget=GiB)  # at the budget: allowed
    with pytest.raises(UsvError) as caught:
        require(GiB + 1, "c.tif: reading 9 x 9 pixels", "give a smaller image", budget=GiB)
    assert str(caught.value) == (
        "c.tif: reading 9 x 9 pixels needs about 1.00 GiB of memory, more than the budget of "
        "1.00 GiB (--max-memory); give a smaller image"
    )
    with pytest.raises(UsvError, match=r"about 15367 GiB .* budget of 40 MiB \(--max-memory\)"):
        require(15367.2 * GiB, "s.yaml: the run", "shorten sim.duration", budget=40 * MiB)


def test_the_default_budget_is_half_the_machines_memory():
    total = next(int(line.split()[1]) * 1024 for line in Path("/proc/meminfo").read_text()
                 .splitlines() if line.startswith("MemTotal:"))  # fmt: skip
    limit = budget._cgroup_limit()
    expected = min(total, limit) if limit else total
    assert budget.machine_memory() == pytest.approx(expected, rel=0.01)
    assert budget.default_budget() == int(budget.machine_memory() * 0.5)
    with pytest.raises(UsvError, match="budget of"):  # the default applies when none is given
        require(budget.machine_memory(), "x", "y")
