"""The Imazu section (usvtool/report/sections/imazu.py) on hand-built runs: the table's cells
and totals counted by hand, failures never compliant, the scale read from the runs' files (not
the family's defaults), and the grid figure at >= 150 dpi."""

from __future__ import annotations

import io

import pytest
from PIL import Image

from usvtool.report.data import JobResults, Results
from usvtool.report.figures.imazu import outcome
from usvtool.report.sections import imazu
from usvtool.results import Row
from usvtool.trace import write_events

CONTROLLERS = ("dwa", "udwa")


def job(root, case: str, method: str, metrics: dict, family: str = "imazu") -> JobResults:
    """A run job of ``case``: its metrics as a results table holds them, its trace's first step
    and its events: own ship north at 6 m/s, 12 m long; one 10 m target head-on at 4 m/s,
    500 m ahead, so its CPA is 500 / 10 = 50 s ahead at 0 m. The scenario file beside them
    says otherwise: the section never reads it."""
    d = root / "runs" / f"{case.replace('/', '-')}-{method}"
    d.mkdir(parents=True)
    rows = {m: Row("k", "runs", case, method, 1, m, str(v)) for m, v in metrics.items()}
    (d / "scenario.yaml").write_text(
        "sim: {dt: 0.1, duration: 999.0}\n"
        "own: {start: [0, 0], goal: [0, 900], heading: 90, speed: 2}\n"
        "targets: [{name: ts1, start: [0, 100], heading: 0, speed: 1, length: 10}]\n")
    (d / "trace.csv").write_text(
        "t,ship,x,y,heading,speed,yaw_rate\n"
        "0.000,own,0.000,0.000,0.000,6.0000,0.0000\n"
        "0.000,ts1,0.000,500.000,180.000,4.0000,0.0000\n"
        "0.100,own,0.000,0.600,0.000,6.0000,0.0000\n"
        "0.100,ts1,0.000,499.600,180.000,4.0000,0.0000\n")
    write_events(d / "trace.events.json", {"encounters": [], "thresholds": {
        "apparent": {"course_deg": 30.0, "speed_reduction": 0.5}, "domain_axes_m": [84, 36]},
        "run": {"own_length": 12.0,
                "ships": [{"name": "own", "length": 12.0}, {"name": "ts1", "length": 10.0}],
                "map": None, "wind_field": None, "goal": [0.0, 800.0], "duration_s": 90.0,
                "scenario_file": "scenario.yaml"}})  # fmt: skip
    config = {"scene": {"family": family, "kind": case.split("/")[1], "scene": 0}}
    return JobResults(f"{case}-{method}", "runs", case, method, 1, d, rows, config=config)


def counts(c, e, n, j) -> dict:
    return {"compliant": c, "compliant_excused": e, "noncompliant": n, "not_judged": j}


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    root = tmp_path_factory.mktemp("imazu")
    ok = {"arrived": True, "arrival_time_s": 140.0}
    jobs = [
        job(root, "imazu/01/s000", "dwa", {**ok, "closest_distance_m": 41.25,
                                           **counts(1, 0, 0, 0)}),
        job(root, "imazu/01/s000", "udwa", {**ok, "closest_distance_m": 55.0,
                                            **counts(0, 1, 0, 0)}),
        job(root, "imazu/02/s000", "dwa", {"arrived": False, "collision": "ts1",
                                           "closest_distance_m": 3.5, **counts(0, 0, 0, 1)}),
        job(root, "imazu/02/s000", "udwa", {"arrived": False, "closest_distance_m": 20.0,
                                            **counts(0, 0, 0, 1)}),
        # another family's run, never in the section
        job(root, "emergency/head-on/s000", "dwa", {**ok, **counts(1, 0, 0, 0)}, "emergency"),
    ]  # fmt: skip
    results = Results(jobs, [], order=CONTROLLERS)
    return imazu.section(results)


def cells(section, table_id: str) -> list[list[str]]:
    table = next(t for t in section.tables() if t.id == table_id)
    return [[c.text for c in row] for row in table.rows]


def test_the_table_counts_arrivals_collisions_and_compliance_by_hand(built):
    rows = cells(built, "imazu-table")
    assert [r[:2] for r in rows] == [["01", "HO"], ["02", "HO"]]
    assert rows[0][2:] == ["41.2 m; 1/0/0/0", "55.0 m; 0/1/0/0"]
    assert rows[1][2:] == ["collided (ts1); 3.5 m; 0/0/0/1", "did not arrive; 20.0 m; 0/0/0/1"]
    # controller, cases, arrived, collided, did not arrive, compliant, excused only,
    # non-compliant, not judged, closest: median of 41.25 and 3.5 (IQR 0.75 x 37.75)
    assert cells(built, "imazu-totals") == [
        ["dwa", "2", "1", "1", "0", "1", "0", "0", "1", "22.4 (IQR 18.9)"],
        ["udwa", "2", "1", "0", "1", "0", "1", "0", "1", "37.5 (IQR 17.5)"]]


def test_a_failed_run_is_never_compliant_in_the_grid(built):
    grid = next(f for f in built.figures() if f.id == "imazu-grid")
    lines = [line.split(",") for line in grid.data.splitlines()]
    drawn = {(r[0], r[1]): r[2] for r in lines[1:]}
    assert drawn == {("imazu/01/s000", "dwa"): "compliant", ("imazu/01/s000", "udwa"): "excused",
                     ("imazu/02/s000", "dwa"): "collided",
                     ("imazu/02/s000", "udwa"): "not-arrived"}  # fmt: skip
    # a run that did not arrive is a failure whatever its counts say
    assert outcome(False, False, (3, 0, 0, 0)) == "not-arrived"
    assert outcome(True, True, (3, 0, 0, 0)) == "collided"


def test_the_scale_is_read_from_the_runs(built):
    text = " ".join(built.paragraphs)
    assert "own ship 12 m long at 6.0 m/s, its goal 800 m ahead" in text
    assert "targets 10 m long at 4.0 m/s" in text
    assert "every target 500 m off, its CPA 50.0 s ahead at 0.00 m" in text
    assert "after 90 s" in text
    thresholds = cells(built, "imazu-thresholds")
    assert ["ship domain: ellipse's full axes, along x across", "7 L x 3 L (84 m x 36 m)",
            "domain_axes_m"] in thresholds  # fmt: skip


def test_events_without_the_duration_are_refused(tmp_path):
    from usvtool.errors import UsvError

    run = job(tmp_path, "imazu/01/s000", "dwa", {"arrived": True})
    path = run.dir / "trace.events.json"
    path.write_text(path.read_text().replace('"duration_s": 90.0,', ""))
    with pytest.raises(UsvError, match="run has no duration_s .*simulate the run again"):
        imazu.section(Results([run], [], order=CONTROLLERS))


def test_the_grid_is_a_png_of_150_dpi_or_more(built):
    grid = next(f for f in built.figures() if f.id == "imazu-grid")
    image = Image.open(io.BytesIO(grid.png))
    assert image.format == "PNG"
    assert min(image.info["dpi"]) >= 149.9
    assert image.size[0] >= 7 * 150


def test_no_imazu_run_no_section():
    assert imazu.section(Results([], [])) is None
