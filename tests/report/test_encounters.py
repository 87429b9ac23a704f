"""The report's encounter data (usvtool/report/encounters.py): ship lengths and scenario files."""

from __future__ import annotations

from usvtool.report.data import Job
from usvtool.report.encounters import lengths, scenario_file
from usvtool.trace import Trace


def test_each_ship_has_its_own_length_and_the_scenarios_files_resolve(tmp_path):
    (tmp_path / "wind.tif").write_bytes(b"x")
    scenario = tmp_path / "s.yaml"
    scenario.write_text("name: s\nweather: {field: wind.tif}\ntargets:\n"
                        "  - {name: ferry, start: [0, 100], heading: 180, speed: 3, length: 12}\n"
                        "  - {name: tug, start: [50, 100], heading: 180, speed: 2, length: 5}\n")
    job = Job("k", "runs", "s", "udwa", 1, tmp_path, config={"scenario": str(scenario)})
    trace = Trace.from_states([0.0], ["own", "ferry", "tug", "ghost"], [[[0, 0, 0, 1, 0]] * 4])
    assert lengths(job, trace, {"run": {"own_length": 2.5}}) == {
        "own": 2.5, "ferry": 12.0, "tug": 5.0, "ghost": 2.5}
    assert scenario_file(job, "weather", "field") == (tmp_path / "wind.tif").resolve()
    assert scenario_file(job, "map") is None
