"""usvtool.companions: the sidecars GDAL reads with a raster, the update files of an S-57 cell."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio
from affine import Affine

from usvtool.companions import companions, s57_updates, sidecars


def touch(d: Path, *names: str) -> None:
    for name in names:
        (d / name).parent.mkdir(parents=True, exist_ok=True)
        (d / name).write_bytes(b"x")


@pytest.mark.parametrize(
    "source, expected",
    [
        ("a.tif", ["a.TFW", "a.aux", "a.tab", "a.tif.aux", "a.tif.aux.xml", "a.tif.msk",
                   "a.tif.ovr", "a.tifw", "a.wld"]),
        ("a.png", ["a.pgw", "a.png.aux.xml", "a.pngw", "a.wld"]),
        ("a.jpg", ["a.jgw", "a.jpg.aux.xml", "a.jpgw", "a.wld"]),
        ("a.KAP", ["a.KAP.aux.xml", "a.kpw", "a.wld"]),
    ],
)  # fmt: skip
def test_the_sidecars_of_a_raster_by_its_extension(tmp_path, source, expected):
    # every candidate of every extension, and files that are no sidecar of it
    touch(tmp_path, source, *expected, "a.pgw", "a.jgw", "a.tfw.bak", "b.tfw", "a.txt",
          "a.tif.aux.xml.old", "ab.wld")  # fmt: skip
    found = [p.name for p in sidecars(tmp_path / source)]
    assert found == sorted(set(expected))  # exactly these, sorted, the source itself excluded
    assert all(p.parent == tmp_path for p in sidecars(tmp_path / source))


def _tif(path: Path, size: int) -> None:
    with rasterio.open(path, "w", driver="GTiff", width=size, height=size, count=1,
                       dtype="uint8", crs="EPSG:32616",
                       transform=Affine(64 / size, 0, 0, 0, -64 / size, 64)) as ds:  # fmt: skip
        ds.write(np.zeros((1, size, size), np.uint8))


def test_gdal_reads_what_sidecars_names(tmp_path):
    """Independent check: GDAL's own file list of a GeoTIFF with a PAM file, external overviews
    and a world file is the file and its sidecars."""
    path = tmp_path / "g.tif"
    _tif(path, 64)
    _tif(tmp_path / "g.tif.ovr", 32)  # external overviews: a GeoTIFF of half the size
    (tmp_path / "g.tif.aux.xml").write_text("<PAMDataset><Metadata><MDI key='k'>v</MDI>"
                                            "</Metadata></PAMDataset>")  # fmt: skip
    with rasterio.open(path) as ds:
        assert ds.overviews(1) == [2]  # GDAL did take the .ovr
        gdal = sorted(Path(f).name for f in ds.files)
    assert gdal == ["g.tif", "g.tif.aux.xml", "g.tif.ovr"]
    assert [p.name for p in companions(path)] == gdal[1:]
    png = tmp_path / "p.png"
    with rasterio.open(png, "w", driver="PNG", width=8, height=8, count=1, dtype="uint8") as ds:
        ds.write(np.zeros((1, 8, 8), np.uint8))
    (tmp_path / "p.pgw").write_text("2\n0\n0\n-2\n100\n200\n")
    with rasterio.open(png) as ds:
        assert ds.transform == Affine(2, 0, 99, 0, -2, 201)  # GDAL did read the world file
        gdal = sorted(Path(f).name for f in ds.files if Path(f).name != "p.png")
    assert gdal and set(gdal) <= {p.name for p in companions(png)}


def test_the_update_files_of_an_s57_cell(tmp_path):
    touch(tmp_path, "US1.000", "US1.002", "US1.001", "US1.010", "US2.001", "US1.00a", "US1.0001")
    assert [p.name for p in s57_updates(tmp_path / "US1.000")] == ["US1.001", "US1.002",
                                                                    "US1.010"]  # fmt: skip
    assert [p.name for p in companions(tmp_path / "US1.000")] == ["US1.001", "US1.002", "US1.010"]
    assert s57_updates(tmp_path / "US3.000") == []
    # an update file read as a cell (a chart's inputs list them): the others, not itself
    assert [p.name for p in companions(tmp_path / "US1.002")] == ["US1.001", "US1.010"]


def test_update_files_in_a_cd_layout_are_found_where_gdal_looks(tmp_path):
    """ENC_ROOT/X/<edition>/0/X.000 with X/<edition>/1/X.001, ...: GDAL's S57 driver looks in
    ../<n>/ for an update not beside the cell, and stops at the first it finds nowhere."""
    touch(tmp_path, "X/5/0/X.000", "X/5/1/X.001", "X/5/0/X.002", "X/5/3/X.003", "X/5/5/X.005")
    found = s57_updates(tmp_path / "X/5/0/X.000")
    assert [p.relative_to(tmp_path).as_posix() for p in found] == ["X/5/1/X.001", "X/5/0/X.002",
                                                                    "X/5/3/X.003"]  # fmt: skip


def test_no_folder_no_companions(tmp_path):
    assert companions(tmp_path / "none" / "a.tif") == []
    assert companions(tmp_path / "none" / "a.000") == []
