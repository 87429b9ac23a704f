"""The batch's table measured in parts (usvtool/batch/results_tables.py, docs/batch.md "The
tables"): as many ``usvtool metrics`` commands as the executor runs at once, each over every
route and whole scenarios' runs, give the table of one command, byte for byte."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from usvtool.batch.jobs import Job
from usvtool.batch.results_tables import parts

ROOT = Path(__file__).resolve().parent.parent.parent

# routes on grid20 (astar and pso: anyangle-free, so no length ratio), the open-water scenario,
# and three scenes of the emergency family: four scenarios with two controllers each, udwa's
# optimisation rates against dwa's run of the same scenario
PIPELINE = f"""
root: {ROOT}
charts:
  grid20: {{source: charts/grid20.geojson, options: {{cell-size: 1, no-swell: true,
           occupancy: 0.5}}, start: [0.5, 0.5], goal: [19.5, 19.5]}}
routes:
  tiny:
    charts: [grid20]
    algorithms: [astar, pso]
    seeds: [1]
    options: {{pop: 10, iters: 10}}
simulation:
  scenarios: [tests/batch/scenarios/*.yaml]
  controllers: [dwa, udwa]
  seeds: [1]
  reference_controller: dwa
families:
  - family: emergency
    kinds: [head-on, crossing, overtaking]
    scenes: [4]
    controllers: [dwa, udwa]
    seeds: [1]
    options: {{duration: 2}}
"""


def run(key: str, scenario: str, tmp_path: Path) -> Job:
    (tmp_path / "runs" / key).mkdir(parents=True)
    (tmp_path / "runs" / key / "summary.json").write_text(json.dumps({"scenario": scenario}))
    return Job("runs", key, scenario, "dwa", 1, ())


def test_a_scenario_s_runs_stay_in_one_part_and_every_part_has_every_route(tmp_path):
    routes = [Job("routes", f"r{i}", "grid20", "pso", i, (), needs="g") for i in range(2)]
    runs = [run(f"{s}{i}", s, tmp_path) for s, n in (("a", 3), ("b", 2), ("c", 2), ("d", 1))
            for i in range(n)]  # fmt: skip
    two = parts(tmp_path, routes + runs, 2)
    # a (3 runs) first to one part, then b (2) to the other, c (2) to the second (2 < 3), d to
    # the first (3 < 4): 4 runs each
    assert [[j.key for j in p if j.kind == "runs"] for p in two] == [
        ["a0", "a1", "a2", "d0"], ["b0", "b1", "c0", "c1"]]  # fmt: skip
    assert all(p[:2] == routes for p in two)
    assert len(parts(tmp_path, runs, 8)) == 4  # no more parts than scenarios
    assert parts(tmp_path, routes, 4) == [routes]  # no runs: one part
    assert [len(p) for p in parts(tmp_path, runs, 1)] == [8]


@pytest.mark.slow  # a grid, 2 routes and 8 short runs in this process, then the tables twice
def test_three_parts_give_the_table_of_one_command(tmp_path, inline_batch, monkeypatch):
    from usvtool.batch import engine, results_tables

    executor = type(engine._executor(None))  # inline_batch's: tasks run as they are submitted
    commands: list[int] = []  # the jobs of each usvtool metrics command
    measure = results_tables.measure

    def counted(out, jobs, *args):
        commands.append(len(jobs))
        return measure(out, jobs, *args)

    monkeypatch.setattr(results_tables, "measure", counted)
    pipeline = tmp_path / "p.yaml"
    pipeline.write_text(PIPELINE)
    out = tmp_path / "out"
    tables = {}
    for capacity in (1, 3):  # the second batch skips every job and makes the tables again
        monkeypatch.setattr(executor, "capacity", capacity)
        commands.clear()
        assert inline_batch(pipeline, out).exit_code == 0
        # one command over the 2 routes and 8 runs; or three, each with both routes and the
        # runs of whole scenarios (2 each): the fourth to the first part, 2 + 4, 2 + 2, 2 + 2
        assert commands == ([10] if capacity == 1 else [6, 4, 4])
        tables[capacity] = {n: (out / n).read_bytes() for n in ("metrics.csv", "timings.csv")}
    assert tables[1] == tables[3]
    text = tables[1]["metrics.csv"].decode()
    assert ",closest_distance_rate," in text and ",routes,grid20,pso,1,length_m," in text
    assert text.count(",closest_distance_rate,") == 8  # every run of the four scenarios
