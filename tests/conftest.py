"""Shared fixtures: paths to the bundled charts, a CLI runner."""

import contextlib
import shutil
from pathlib import Path

import numpy as np
import pytest
import shapely
from click.testing import CliRunner

ROOT = Path(__file__).resolve().parent.parent
CHARTS = ROOT / "charts"
KAP = CHARTS / "noaa" / "11361_4.KAP"
ENC = CHARTS / "noaa" / "US5MA12M.000"


@pytest.fixture(scope="session")
def kap() -> Path:
    """The NOAA raster chart 11361_4 (Head of Passes)."""
    return KAP


@pytest.fixture(scope="session")
def enc() -> Path:
    """The NOAA ENC cell US5MA12M (Boston Harbor)."""
    return ENC


@pytest.fixture(scope="session")
def charts() -> Path:
    return CHARTS


@pytest.fixture
def runner() -> CliRunner:
    return CliRunner()


@pytest.fixture
def usv(runner):
    """``usv(*args)`` invokes ``usvtool ARGS``; the result keeps stdout and stderr apart."""
    from usvtool.cli import cli

    def invoke(*args):
        return runner.invoke(cli, [str(a) for a in args], catch_exceptions=False)

    return invoke


def write_dsid_only_cell(path: Path) -> Path:
    """A genuine S-57 file with only its DSID record, written by GDAL's S57 driver.

    The driver writes the DSID when the file is created and refuses to create layers, so the
    attempt to write an M_COVR polygon fails and leaves a cell with no features at all.
    """
    from pyogrio.raw import write

    wkb = np.array([shapely.to_wkb(shapely.box(-71, 42, -70.9, 42.1))], dtype=object)
    with contextlib.suppress(Exception):
        write(path, wkb, [np.array([1], dtype=np.int32)], fields=["CATCOV"], layer="M_COVR",
              driver="S57", geometry_type="Polygon", crs="EPSG:4326")  # fmt: skip
    if not path.is_file() or not path.stat().st_size:
        pytest.skip("this GDAL does not write S-57 files")
    return path


BAD_CELLS = {  # bad S-57 inputs and the words their one-line error must hold
    "missing": "no such file",
    "empty": "empty file",
    "text": "not an S-57 cell",
    "raster-chart": "not an S-57 cell",
    "no-features": "no land",
}


@pytest.fixture
def bad_cell(tmp_path):
    """``bad_cell(kind)``: (path, expected words) of a bad S-57 input of that kind.

    Kinds: missing, empty, text, raster-chart, no-features.
    """

    def make(kind: str) -> tuple[Path, str]:
        path = tmp_path / f"{kind}.000"
        if kind == "empty":
            path.write_bytes(b"")
        elif kind == "text":
            path.write_text("not a chart\n")
        elif kind == "raster-chart":
            shutil.copy(KAP, path)
        elif kind == "no-features":
            write_dsid_only_cell(path)
        return path, BAD_CELLS[kind]

    return make
