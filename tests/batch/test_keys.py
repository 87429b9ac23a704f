"""A job's key covers every byte it reads (docs/batch.md, "Key"): the files its options name
(resolved against the pipeline's root), the GDAL sidecars of every raster it reads (a chart's
source, a scenario's map and wind field), an S-57 cell's update files, and the files a scenario
names. Change one: the job runs again; change nothing: it is skipped."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
import rasterio
from affine import Affine
from shapely.geometry import box, mapping

from usvtool.batch.jobs import expand
from usvtool.cli.batch import scenario_files, stage_names
from usvtool.pipeline import load

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "tests" / "batch" / "scenarios" / "open-head-on.yaml"
NAMES = stage_names()
X0, Y0 = 300000.0, 3230000.0  # the chart's top left corner, UTM 16N
UTM16 = "EPSG:32616"


def write_chart(path: Path) -> Path:
    """A 60 x 40 GeoTIFF chart of 1 m pixels from (X0, Y0): water with a land square in rows
    and columns 10..29."""
    img = np.empty((3, 40, 60), np.uint8)
    img[:] = np.array([212, 234, 238], np.uint8)[:, None, None]
    img[:, 10:30, 10:30] = np.array([201, 185, 122], np.uint8)[:, None, None]
    with rasterio.open(path, "w", driver="GTiff", width=60, height=40, count=3, dtype="uint8",
                       crs=UTM16, transform=Affine(1, 0, X0, 0, -1, Y0)) as ds:  # fmt: skip
        ds.write(img)
    return path


def write_cutline(path: Path, right: float) -> Path:
    """A cutline (in UTM) around the chart up to ``right`` metres from its left edge."""
    polygon = mapping(box(X0 - 5, Y0 - 45, X0 + right, Y0 + 5))
    doc = {"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": UTM16}},
           "features": [{"type": "Feature", "properties": {}, "geometry": polygon}]}  # fmt: skip
    path.write_text(json.dumps(doc))
    return path


def chart_pipeline(d: Path, source: str = "chart.tif", options: str = "{cell-size: 2}") -> Path:
    """A pipeline of one chart and one A* route on it, root ``d``."""
    (d / "p.yaml").write_text(
        f"root: .\ncharts:\n  isle: {{source: {source}, options: {options},\n"
        f"         start: [{X0 + 3}, {Y0 - 3}], goal: [{X0 + 5}, {Y0 - 37}]}}\n"
        "routes:\n  r: {charts: [isle], algorithms: [astar], seeds: [1]}\n")  # fmt: skip
    return d / "p.yaml"


def keys(pipeline: Path) -> dict[str, str]:
    """Each job's key by its label."""
    return {j.label: j.key for j in expand(load(pipeline, NAMES), NAMES, scenario_files)}


def test_an_option_file_is_read_beside_the_pipeline_and_its_content_keys_the_job(
    tmp_path, inline_batch
):
    write_chart(tmp_path / "chart.tif")
    write_cutline(tmp_path / "cut.geojson", 65)  # the whole chart
    pipeline = chart_pipeline(tmp_path, options="{cell-size: 2, cutline: cut.geojson}")
    out = tmp_path / "out"
    first = inline_batch(pipeline, out)
    assert first.exit_code == 0 and first.counts() == (2, 0, 0), first.stderr
    (grid_dir,) = (out / "grids").iterdir()
    job = json.loads((grid_dir / "job.json").read_text())
    assert job["args"][job["args"].index("--cutline") + 1] == str(tmp_path / "cut.geojson")
    assert inline_batch(pipeline, out).counts() == (0, 2, 0)  # nothing changed
    grid = (grid_dir / "grid.tif").read_bytes()
    write_cutline(tmp_path / "cut.geojson", 50)  # the right 10 m cut off
    again = inline_batch(pipeline, out)
    assert again.counts() == (2, 0, 0), again.stderr  # the grid and its route run again
    (new_dir,) = {p for p in (out / "grids").iterdir()} - {grid_dir}
    with rasterio.open(new_dir / "grid.tif") as ds:  # columns 25..29 (x 50..60 m) outside
        cells = ds.read(1)
    assert (cells[:, 25:] != 0).all() and (cells[:, :3] == 0).any()
    assert (new_dir / "grid.tif").read_bytes() != grid
    # the same file named by its absolute path: the same bytes, the same key
    chart_pipeline(tmp_path, options=f"{{cell-size: 2, cutline: {tmp_path / 'cut.geojson'}}}")
    assert inline_batch(pipeline, out).counts() == (0, 2, 0)


def test_a_pam_sidecar_that_moves_the_chart_reruns_its_jobs(tmp_path, inline_batch):
    """The issue's case: a ``.aux.xml`` giving the GeoTIFF another geotransform (2 m pixels)."""
    write_chart(tmp_path / "chart.tif")
    pipeline = chart_pipeline(tmp_path)
    out = tmp_path / "out"
    assert inline_batch(pipeline, out).counts() == (2, 0, 0)
    pam = f"<PAMDataset><GeoTransform>{X0}, 2, 0, {Y0}, 0, -2</GeoTransform></PAMDataset>\n"
    (tmp_path / "chart.tif.aux.xml").write_text(pam)
    again = inline_batch(pipeline, out)
    assert again.counts() == (2, 0, 0), again.stderr
    transforms = set()
    for grid in out.glob("grids/*/grid.tif"):
        with rasterio.open(grid) as ds:
            transforms.add((ds.width, ds.height))
    assert transforms == {(30, 20), (60, 40)}  # 2 m cells over 60 m, then over 120 m
    assert inline_batch(pipeline, out).counts() == (0, 2, 0)


def raster_scenario(d: Path, role: str, raster: str) -> None:
    """The tiny scenario with ``raster`` as its map (``role`` map) or wind field (field)."""
    text = SCENARIO.read_text()
    if role == "map":
        text += f"map: {raster}\n"
    else:
        text += f"weather: {{field: {raster}}}\n"
    (d / "s.yaml").write_text(text)
    (d / "p.yaml").write_text("root: .\nsimulation: {scenarios: [s.yaml], controllers: [dwa], "
                              "seeds: [1]}\n")  # fmt: skip


SIDECARS = {"chart.tif": ["chart.tif.aux.xml", "chart.tif.ovr", "chart.tif.msk", "chart.tfw",
                          "chart.wld", "chart.tif.aux"],
            "chart.png": ["chart.pgw", "chart.png.aux.xml"],
            "chart.jpg": ["chart.jgw"]}  # fmt: skip
CASES = [(role, raster, sidecar) for role in ("source", "map", "field")
         for raster, names in SIDECARS.items() for sidecar in names]  # fmt: skip


@pytest.mark.parametrize("role, raster, sidecar", CASES)
def test_a_rasters_sidecars_key_the_jobs_that_read_it(tmp_path, role, raster, sidecar):
    (tmp_path / raster).write_bytes(b"raster")  # keys read bytes, they do not parse
    if role == "source":
        pipeline = chart_pipeline(tmp_path, source=raster)
    else:
        raster_scenario(tmp_path, role, raster)
        pipeline = tmp_path / "p.yaml"
    before = keys(pipeline)
    (tmp_path / "other.tfw").write_bytes(b"1")  # beside it, of another name: not read
    (tmp_path / f"{sidecar}.bak").write_bytes(b"1")
    assert keys(pipeline) == before
    (tmp_path / sidecar).write_bytes(b"1")
    added = keys(pipeline)
    assert added.keys() == before.keys() and not set(added.values()) & set(before.values())
    assert keys(pipeline) == added  # nothing changed: the same keys (the jobs are skipped)
    (tmp_path / sidecar).write_bytes(b"2")
    changed = keys(pipeline)
    assert not set(changed.values()) & (set(added.values()) | set(before.values()))


def test_an_s57_cells_update_files_key_its_grid(tmp_path):
    cell = tmp_path / "enc"
    cell.mkdir()
    (cell / "US1.000").write_bytes(b"base")
    (cell / "US1.001").write_bytes(b"update 1")
    pipeline = chart_pipeline(tmp_path, source="enc/US1.000")
    before = keys(pipeline)
    assert keys(pipeline) == before
    with open(cell / "US1.001", "ab") as f:  # the case: appending to an update
        f.write(b" and more")
    appended = keys(pipeline)
    assert not set(appended.values()) & set(before.values())
    (cell / "US1.002").write_bytes(b"update 2")
    added = keys(pipeline)
    assert not set(added.values()) & set(appended.values())
    (cell / "US2.001").write_bytes(b"another cell's")
    assert keys(pipeline) == added


def scenario_naming_files(d: Path) -> Path:
    """The tiny scenario with a map, a route, a target's track and a wind field (none of them
    read here: the keys read bytes)."""
    text = SCENARIO.read_text().replace("{name: t1, start: [100, 90], heading: 180, ",
                                        "{name: t1, track: tracks/t1.csv, ")  # fmt: skip
    text += "map: maps/m.tif\nroute: r.geojson\nweather: {field: ../w.tif}\n"
    (d / "s").mkdir()
    (d / "s" / "maps").mkdir()
    (d / "s" / "tracks").mkdir()
    (d / "s" / "x.yaml").write_text(text)
    for name in ("s/maps/m.tif", "s/r.geojson", "s/tracks/t1.csv", "w.tif", "s/other.csv"):
        (d / name).write_bytes(b"first")
    (d / "p.yaml").write_text("root: .\nsimulation: {scenarios: [s/*.yaml], controllers: "
                              "[dwa, gdwa], seeds: [1]}\n")  # fmt: skip
    return d / "p.yaml"


@pytest.mark.parametrize("named", ["s/maps/m.tif", "s/r.geojson", "s/tracks/t1.csv", "w.tif"])
def test_the_files_a_scenario_names_key_its_runs(tmp_path, named):
    pipeline = scenario_naming_files(tmp_path)
    assert sorted(p.relative_to(tmp_path).as_posix() for p in scenario_files(tmp_path / "s/x.yaml")
                  ) == ["s/maps/m.tif", "s/r.geojson", "s/tracks/t1.csv", "w.tif"]  # fmt: skip
    before = keys(pipeline)
    assert len(before) == 2  # dwa, gdwa
    (tmp_path / "s" / "other.csv").write_bytes(b"second")  # named by no scenario
    assert keys(pipeline) == before
    (tmp_path / named).write_bytes(b"second")
    after = keys(pipeline)
    assert after.keys() == before.keys() and not set(after.values()) & set(before.values())
    assert keys(pipeline) == after


def test_a_scenario_that_does_not_read_is_keyed_by_its_own_bytes(tmp_path):
    (tmp_path / "s.yaml").write_text("name: deep\nown: " + "[" * 20000 + "]" * 20000 + "\n")
    (tmp_path / "p.yaml").write_text("root: .\nsimulation: {scenarios: [s.yaml], controllers: "
                                     "[dwa], seeds: [1]}\n")  # fmt: skip
    before = keys(tmp_path / "p.yaml")
    assert keys(tmp_path / "p.yaml") == before
    (tmp_path / "s.yaml").write_text("name: deep\nown: [[[]]]\n")
    assert keys(tmp_path / "p.yaml").values() != before.values()


def test_the_file_options_are_the_commands_own_declarations():
    """Which options name files comes from the click commands: preprocess reads --cutline and
    writes -o, --preview and --summary; plan writes -o and --summary."""
    assert NAMES.files["preprocess"].reads == {"cutline"}
    assert NAMES.files["preprocess"].writes == {"output", "preview", "summary"}
    assert NAMES.files["plan"].reads == set()
    assert NAMES.files["plan"].writes == {"output", "summary"}


def test_nothing_changed_nothing_runs_on_the_bundled_pipeline():
    """The bundled pipeline's keys are the same twice over: reading them writes no sidecar."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        first = keys(ROOT / "pipelines" / "report.yaml")
    assert keys(ROOT / "pipelines" / "report.yaml") == first


def test_a_labelled_matrix_plans_the_same_chart_apart_and_shares_its_grid(tmp_path):
    """Two matrices of one chart, algorithm and seed with other options are refused unless one
    has a label: its routes are then the case CHART-LABEL, of their own keys, on the same
    grid job."""
    text = (ROOT / "tests" / "batch" / "tiny.yaml").read_text(encoding="utf-8")
    text = text.replace("root: ../..", f"root: {ROOT}").replace("routes:\n", (
        "routes:\n  many:\n    charts: [grid20]\n    algorithms: [pso]\n    seeds: [1]\n"
        "    options: {pop: 10, iters: 10, waypoints: 6}\n    label: w6\n"))  # fmt: skip
    path = tmp_path / "p.yaml"
    path.write_text(text, encoding="utf-8")
    jobs = expand(load(path, NAMES), NAMES)
    routes = [j for j in jobs if j.kind == "routes"]
    assert sorted((j.case, j.method, j.seed) for j in routes) == [
        ("grid20", "astar", None), ("grid20", "pso", 1), ("grid20", "pso", 2),
        ("grid20-w6", "pso", 1)]  # fmt: skip
    assert len({j.needs for j in routes}) == 1 and len({j.key for j in routes}) == 4
    assert sum(j.kind == "grids" for j in jobs) == 1
    labelled = next(j for j in routes if j.case == "grid20-w6")
    assert labelled.args[labelled.args.index("--waypoints") + 1] == "6"
