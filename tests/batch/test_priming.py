"""The order jobs start in (usvtool/batch/engine.py, ``_Run.take``): a kind's first job runs
alone, the other kinds' ready jobs starting meanwhile; once it has finished, failed or not, its
kind's jobs start as the priorities give them, the first of each method of the kind again
before the others of its method."""

from __future__ import annotations

import io

from usvtool.batch.engine import _Run
from usvtool.batch.jobs import Job
from usvtool.batch.progress import Lines


def job(kind: str, n: int, needs: str | None = None, method: str = "m") -> Job:
    return Job(kind, f"{kind}{n}", f"case{n}", method, n, ("x",), needs)


def started(run: _Run) -> list[str]:
    """The keys ``take`` gives until it gives none."""
    out = []
    while (j := run.take()) is not None:
        out.append(j.key)
    return out


def test_a_kinds_first_job_runs_alone_and_the_others_follow_once_it_has_finished():
    todo = [job("runs", i) for i in range(3)] + [job("functions", i) for i in range(2)]
    todo += [job("grids", 0), job("routes", 0, needs="grids0")]
    run = _Run(todo, set(), Lines(len(todo), 0, "test", io.StringIO()))
    # grids first (priority 0), then one run, then one function: each its kind's first
    assert started(run) == ["grids0", "runs0", "functions0"]
    run.finish(job("runs", 0), None)
    assert started(run) == ["runs1", "runs2"]  # runs primed: the rest at once
    run.finish(job("grids", 0), "it failed")  # its route fails with it, never started
    assert started(run) == []
    assert [j.key for j in run.failed] == ["grids0", "routes0"]
    run.finish(job("functions", 0), None)
    assert started(run) == ["functions1"]
    assert run.ready == [] and run.priming == set()


def test_a_route_made_ready_by_its_grid_waits_for_the_first_route():
    todo = [job("grids", 0)] + [job("routes", i, needs="grids0") for i in range(3)]
    run = _Run(todo, set(), Lines(len(todo), 0, "test", io.StringIO()))
    assert started(run) == ["grids0"]
    run.finish(todo[0], None)
    assert started(run) == ["routes0"]
    run.finish(todo[1], "failed too")  # a failed first job primes its kind as well
    assert started(run) == ["routes1", "routes2"]


def test_a_methods_first_job_runs_before_the_others_of_its_method():
    methods = ["dwa", "vo", "dwa", "vo", "sbmpc", "dwa"]
    todo = [job("runs", i, method=m) for i, m in enumerate(methods)]
    run = _Run(todo, set(), Lines(len(todo), 0, "test", io.StringIO()))
    assert started(run) == ["runs0"]  # the kind's first (and dwa's)
    run.finish(todo[0], None)
    assert started(run) == ["runs1", "runs2", "runs4", "runs5"]  # vo's first, dwa's, sbmpc's
    run.finish(todo[4], None)
    assert started(run) == []  # runs3 waits for vo's first
    run.finish(todo[1], "failed")
    assert started(run) == ["runs3"]
    assert run.priming == set() and run.firsts == {}
