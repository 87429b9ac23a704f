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


def limits(monkeypatch, as_limit, data_limit, vm_size=500 * MiB, vm_data=250 * MiB):
    """Soft RLIMIT_AS and RLIMIT_DATA (None: unlimited), what the process maps, 24 GiB."""
    soft = {budget.resource.RLIMIT_AS: as_limit, budget.resource.RLIMIT_DATA: data_limit}
    monkeypatch.setattr(budget.resource, "getrlimit", lambda kind: (
        budget.resource.RLIM_INFINITY if soft[kind] is None else soft[kind],
        budget.resource.RLIM_INFINITY))  # fmt: skip
    monkeypatch.setattr(budget, "_status_bytes", {"VmSize": vm_size, "VmData": vm_data}.get)
    monkeypatch.setattr(budget, "machine_memory", lambda: 24 * GiB)


@pytest.mark.parametrize("as_limit, data_limit, room", [
    (None, None, None),  # no limit: half of 24 GiB
    (4_096_000_000, None, 2_678_784_000),  # ulimit -v 4000000: (4096000000 - 500 MiB) x 3/4
    (None, GiB, 608_698_368),  # (1 GiB - 250 MiB) x 3/4
    (4_096_000_000, GiB, 608_698_368),  # the lesser
    (400 * MiB, None, 0),  # already past the limit: no room
])  # fmt: skip
def test_the_default_budget_within_the_address_space_limits(monkeypatch, as_limit, data_limit,
                                                            room):  # fmt: skip
    limits(monkeypatch, as_limit, data_limit)
    assert budget.room_budget() == room
    assert budget.default_budget() == (12 * GiB if room is None else room)


def test_a_memory_error_inside_its_guard_is_one_line():
    with pytest.raises(UsvError) as caught:
        with budget.allocating(9.64 * GiB, "running s.yaml (its rollouts)", "lower v_samples"):
            raise MemoryError("Unable to allocate 6.71 GiB")
    assert str(caught.value) == ("out of memory while running s.yaml (its rollouts) (about "
                                 "9.64 GiB needed); lower v_samples")  # fmt: skip
    with budget.allocating(GiB, "x", "y"):  # nothing raised: nothing said
        pass
