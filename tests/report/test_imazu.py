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


def job(root, case: str, method: str, metrics: dict, family: str = "imazu", scale: float = 1.0,
        options: dict | None = None) -> JobResults:
    """A run job of ``case``: its metrics as a results table holds them, its trace's first step
    and its events: own ship north at 6 m/s, 12 m long; one 10 m target head-on at 4 m/s,
    500 m ahead, so its CPA is 500 / 10 = 50 s ahead at 0 m (``scale`` times each length and
    the distance: the CPA ``scale`` times as far ahead); the verdicts' onset at a TCPA of
    120 s. The scenario file beside them says otherwise: the section never reads it.
    ``options``: the family options of its ``job.json`` (none: the family's defaults)."""
    d = root / "runs" / f"{case.replace('/', '-')}-{method}"
    d.mkdir(parents=True)
    rows = {m: Row("k", "runs", case, method, 1, m, str(v)) for m, v in metrics.items()}
    (d / "scenario.yaml").write_text(
        "sim: {dt: 0.1, duration: 999.0}\n"
        "own: {start: [0, 0], goal: [0, 900], heading: 90, speed: 2}\n"
        "targets: [{name: ts1, start: [0, 100], heading: 0, speed: 1, length: 10}]\n")
    ahead, own, target = 500.0 * scale, 12.0 * scale, 10.0 * scale
    (d / "trace.csv").write_text(
        "t,ship,x,y,heading,speed,yaw_rate\n"
        "0.000,own,0.000,0.000,0.000,6.0000,0.0000\n"
        f"0.000,ts1,0.000,{ahead:.3f},180.000,4.0000,0.0000\n"
        "0.100,own,0.000,0.600,0.000,6.0000,0.0000\n"
        f"0.100,ts1,0.000,{ahead - 0.4:.3f},180.000,4.0000,0.0000\n")
    write_events(d / "trace.events.json", {"encounters": [], "thresholds": {
        "horizon_s": 120.0, "apparent": {"course_deg": 30.0, "speed_reduction": 0.5},
        "domain_axes_m": [7 * own, 3 * own]},
        "run": {"own_length": own,
                "ships": [{"name": "own", "length": own}, {"name": "ts1", "length": target}],
                "map": None, "wind_field": None, "goal": [0.0, 800.0 * scale],
                "duration_s": 90.0, "scenario_file": "scenario.yaml"}})  # fmt: skip
    config = {"scene": {"family": family, "kind": case.split("/")[1], "scene": 0,
                        "options": options or {}}}  # fmt: skip
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


# --- several scales: one pipeline entry each ---------------------------------------------------


@pytest.fixture(scope="module")
def scales(tmp_path_factory):
    """The built section's runs (entry imazu, the family's defaults) and the same two cases
    at twice the scale in an entry with options, imazu-twice: 24 m own ship, 20 m target
    1000 m ahead, so 1000 / 24 = 41.7 L off and the CPA 1000 / 10 = 100 s ahead; udwa alone,
    one run arrived (compliant 1, excused 1), one that did not."""
    root = tmp_path_factory.mktemp("scales")
    ok = {"arrived": True, "arrival_time_s": 140.0}
    twice = {"scale": 2.0, "options": {"own_length": 24, "length": 20}}
    jobs = [
        job(root, "imazu/01/s000", "dwa", {**ok, "closest_distance_m": 41.25,
                                           **counts(1, 0, 0, 0)}),
        job(root, "imazu/01/s000", "udwa", {**ok, "closest_distance_m": 55.0,
                                            **counts(0, 1, 0, 0)}),
        job(root, "imazu/02/s000", "udwa", {"arrived": False, "closest_distance_m": 20.0,
                                            **counts(0, 0, 0, 1)}),
        job(root, "imazu-twice/01/s000", "udwa", {**ok, "closest_distance_m": 48.0,
                                                  **counts(1, 1, 0, 0)}, **twice),
        job(root, "imazu-twice/02/s000", "udwa", {"arrived": False, "closest_distance_m": 72.0,
                                                  **counts(0, 0, 0, 2)}, **twice),
    ]  # fmt: skip
    return imazu.section(Results(jobs, [], order=CONTROLLERS))


def test_each_scale_and_controller_has_a_row_by_hand(scales):
    rows = cells(scales, "imazu-scales")
    # imazu: 500 / 12 = 41.7 L off, the CPA 50 s ahead = 50 / 120 = 0.42 x the onset's TCPA;
    # imazu-twice: 1000 / 24 = 41.7 L, 100 s = 0.83 x
    assert rows[0][0] == "imazu: L 12 m, 42 L off, CPA 0.42 x the onset TCPA"
    assert rows[2][0] == "imazu-twice: L 24 m, 42 L off, CPA 0.83 x the onset TCPA"
    text = " ".join(scales.paragraphs)  # in full
    assert ("imazu: own ship 12 m (L) at 6.0 m/s; targets 10 m; at the start 42 L off, the CPA "
            "50 s ahead = 0.42 x the onset TCPA (120 s); imazu-twice: own ship 24 m (L) at 6.0 "
            "m/s; targets 20 m; at the start 42 L off, the CPA 100 s ahead = 0.83 x the onset "
            "TCPA (120 s).") in text
    # scale, controller, runs, arrived, collided, did not arrive, compliant / judged
    # (excused), not judged, the median closest distance (m, L)
    assert [r[1:] for r in rows] == [
        ["dwa", "1", "1", "0", "0", "1 / 1 (0)", "0", "41.2 m (3.4 L)"],
        # 55 and 20 m: 37.5 m = 3.1 x 12 m; its failed run's encounter not judged
        ["udwa", "2", "1", "0", "1", "0 / 1 (1)", "1", "37.5 m (3.1 L)"],
        # 48 and 72 m: 60 m = 2.5 x 24 m
        ["udwa", "2", "1", "0", "1", "1 / 2 (1)", "2", "60.0 m (2.5 L)"],
    ]  # fmt: skip
    assert rows[1][0] == ""  # the scale once per entry


def test_the_grid_and_every_run_are_the_default_entrys(scales):
    assert [r[0] for r in cells(scales, "imazu-table")] == ["01", "02"]
    assert [r[:2] for r in cells(scales, "imazu-totals")] == [["dwa", "1"], ["udwa", "2"]]
    grid = next(f for f in scales.figures() if f.id == "imazu-grid")
    assert {line.split(",")[0] for line in grid.data.splitlines()[1:]} == {
        "imazu/01/s000", "imazu/02/s000"}  # fmt: skip
    text = " ".join(scales.paragraphs)
    assert "own ship 12 m long at 6.0 m/s" in scales.paragraphs[0]
    assert "24 m" not in scales.paragraphs[0]
    assert ("2 scales, one pipeline entry each (imazu, imazu-twice): the totals, the grid and "
            "every run below are those of imazu (run at the family's defaults") in text
    # the table of the scales follows the totals, before the grid
    assert [b.id for b in scales.blocks][:3] == ["imazu-totals", "imazu-scales", "imazu-grid"]


def built_tables(section):
    return [t.id for t in section.tables()]


def test_one_scale_has_no_table_of_scales(built):
    assert "imazu-scales" not in built_tables(built)
    assert "one pipeline entry each" not in " ".join(built.paragraphs)


def test_the_main_entry_is_the_one_at_the_familys_defaults():
    def runs(options):
        config = {"scene": {"family": "imazu", "options": options}}
        return {"x/01/s000": {"udwa": JobResults("k", "runs", "x/01/s000", "udwa", 1, None,
                                                 config=config)}}  # fmt: skip

    at_defaults, compressed = runs({}), runs({"own_speed": 7})
    assert imazu.main_entry({"imazu": compressed, "zz": at_defaults}) == "zz"
    assert imazu.main_entry({"b": compressed, "imazu": compressed}) == "imazu"
    assert imazu.main_entry({"c": compressed, "b": compressed}) == "b"
    assert imazu.main_entry({"zz": at_defaults, "imazu": at_defaults}) == "imazu"
