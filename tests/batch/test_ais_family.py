"""The ``ais`` family in a pipeline (tests/batch/ais.yaml): its encounters and tracks files are
read relative to the pipeline's root and handed to the jobs by absolute path; their contents,
not their paths, key the runs, so a changed encounters or tracks file reruns its jobs and a
moved one does not; bad entries are refused in one line naming the field; the tiny pipeline
runs with every controller, and the report's traffic section reads its runs."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from usvtool.batch.jobs import expand
from usvtool.cli.batch import stage_names
from usvtool.digest import sha256
from usvtool.errors import UsvError
from usvtool.pipeline import load
from usvtool.tracks import Tracks, read_tracks, write_tracks

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "tests" / "batch" / "ais.yaml"
AIS = ROOT / "charts" / "ais"
NAMES = stage_names()
CONTROLLERS = ["dwa", "gdwa", "ccdwa", "udwa", "udwa+"]


def test_the_entry_reads_its_files_from_the_root_and_the_jobs_get_absolute_paths():
    p = load(TINY, NAMES)
    (entry,) = p.families
    options = dict(entry.options)
    assert options["encounters"] == AIS / "nyharbor-encounters.csv" and options["duration"] == 3
    jobs = expand(p, NAMES)
    assert sorted(j.method for j in jobs) == sorted(CONTROLLERS)
    assert {j.case for j in jobs} == {"nyharbor/under-way/s001"}
    args = jobs[0].args
    assert f"tracks={AIS / 'nyharbor-tracks.parquet'}" in args
    assert jobs[0].info["scene"]["options"]["encounters"] == str(AIS / "nyharbor-encounters.csv")
    # and their SHA-256, for a reader to check it reads what the run read (the report does)
    assert jobs[0].info["scene"]["sha256"] == {
        k: sha256(AIS / f"nyharbor-{k}.{ext}") for k, ext in (("encounters", "csv"),
                                                           ("tracks", "parquet"))}  # fmt: skip
    json.dumps(jobs[0].record())  # job.json holds the paths as text


def _copy(root: Path) -> Path:
    """The tiny pipeline with its two files in ``root`` (root: .)."""
    root.mkdir()
    for name in ("nyharbor-encounters.csv", "nyharbor-tracks.parquet"):
        shutil.copy(AIS / name, root / name)
    text = TINY.read_text().replace("root: ../..", "root: .").replace("charts/ais/", "")
    (root / "p.yaml").write_text(text)
    return root / "p.yaml"


def _keys(pipeline: Path) -> dict[str, str]:
    return {j.label: j.key for j in expand(load(pipeline, NAMES), NAMES)}


def test_the_files_contents_key_the_runs(tmp_path):
    pipeline = _copy(tmp_path / "a")
    before = _keys(pipeline)
    assert len(before) == 5
    assert _keys(_copy(tmp_path / "b")) == before  # moved, same bytes: the same keys
    assert _keys(load(TINY, NAMES).path) == before  # the committed files themselves
    encounters = tmp_path / "a" / "nyharbor-encounters.csv"
    text = encounters.read_text()
    encounters.write_text(text.replace("CYCLONE SHARK", "CYCLONE SHARKS", 1))
    changed = _keys(pipeline)
    assert changed.keys() == before.keys() and not set(changed.values()) & set(before.values())
    encounters.write_text(text)
    assert _keys(pipeline) == before
    tracks = tmp_path / "a" / "nyharbor-tracks.parquet"
    t = read_tracks(tracks)
    sog = t.sog.copy()
    sog[100] = np.nan if sog[100] == sog[100] else 1.0
    write_tracks(tracks, Tracks(**{**{c: getattr(t, c) for c in ("mmsi", "time", "lon", "lat",
                                   "cog", "heading", "length", "beam", "name", "ship_type",
                                   "track")}, "sog": sog}))  # fmt: skip
    assert not set(_keys(pipeline).values()) & set(before.values())


def test_a_map_is_read_from_the_root_and_its_content_keys_the_runs(tmp_path):
    """The optional map: given relative to the root, handed to the jobs by absolute path, its
    bytes in the runs' keys (another grid, other keys); without it the keys are the plain
    entry's."""
    from affine import Affine
    from rasterio.crs import CRS

    from usvtool.grid import Grid, write_grid

    pipeline = _copy(tmp_path / "a")
    plain = _keys(pipeline)
    cells = np.zeros((40, 40), np.uint8)
    write_grid(tmp_path / "a" / "water.tif",
               Grid(cells, Affine(1000, 0, 560000, 0, -1000, 4520000), CRS.from_epsg(32618)))
    pipeline.write_text(pipeline.read_text() + "      map: water.tif\n")  # options come last
    jobs = expand(load(pipeline, NAMES), NAMES)
    assert f"map={tmp_path / 'a' / 'water.tif'}" in jobs[0].args
    with_map = {j.label: j.key for j in jobs}
    assert with_map.keys() == plain.keys() and not set(with_map.values()) & set(plain.values())
    cells[0, 0] = 1
    write_grid(tmp_path / "a" / "water.tif",
               Grid(cells, Affine(1000, 0, 560000, 0, -1000, 4520000), CRS.from_epsg(32618)))
    assert not set(_keys(pipeline).values()) & set(with_map.values())


@pytest.mark.parametrize("options, words", [
    ("{tracks: nyharbor-tracks.parquet}",
     "families[0].options.encounters must be given for family ais: the encounters CSV"),
    ("{encounters: none.csv, tracks: nyharbor-tracks.parquet}",
     "families[0].options.encounters: none.csv: no such file"),
    ("{encounters: nyharbor-encounters.csv, tracks: nyharbor-tracks.parquet, own: c}",
     "families[0].options.own must be one of a, b for family ais, not 'c'"),
    ("{encounters: nyharbor-encounters.csv, tracks: nyharbor-tracks.parquet, map: no.tif}",
     "families[0].options.map: no.tif: no such file"),
])  # fmt: skip
def test_bad_entries_are_refused_naming_the_field(tmp_path, options, words):
    pipeline = _copy(tmp_path / "a")
    text = pipeline.read_text()
    start = text.index("    options:")
    pipeline.write_text(text[:start] + f"    options: {options}\n")
    with pytest.raises(UsvError) as e:
        load(pipeline, NAMES)
    assert str(e.value).startswith(f"{pipeline}: {words}") and "\n" not in str(e.value)


@pytest.mark.slow
def test_the_tiny_pipeline_runs_with_every_controller_and_the_report_reads_it(tmp_path,
                                                                              inline_batch):
    from usvtool.report.data import load as load_results
    from usvtool.report.sections import traffic

    out = tmp_path / "out"
    ran = inline_batch(TINY, out)
    assert ran.exit_code == 0 and ran.counts() == (5, 0, 0), ran.stderr
    for d in (out / "runs").iterdir():
        job = json.loads((d / "job.json").read_text())
        assert job["scene"]["family"] == "ais" and (d / "scenario.route.geojson").is_file()
        assert (d / "scenario.ais-368139870.csv").is_file()  # the other vessel, replayed
        summary = json.loads((d / "summary.json").read_text())
        assert summary["controller"] == job["method"] and summary["time_s"] == 3.0
    assert inline_batch(TINY, out).counts() == (0, 5, 0)
    section = traffic.section(load_results([out / "metrics.csv"], CONTROLLERS))
    recorded, runs = section.blocks
    assert [c.text for c in recorded.rows[0][:5]] == [
        "nyharbor/under-way/s001", "3", "H203 (367782880)", "CYCLONE SHARK (368139870)",
        "overtaking"]  # fmt: skip
    assert [r[1].text for r in runs.rows] == ["recorded", *CONTROLLERS]
    assert all(r[2].text == "did not arrive" and r[2].css == "fails" for r in runs.rows[1:])
