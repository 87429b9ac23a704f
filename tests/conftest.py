"""Shared fixtures: paths to the bundled charts, a CLI runner, bad S-57 cells, and an
independent collision reference written plainly with shapely (for the collision check's tests
and every stage whose routes or tracks must be collision-free).

The reference: a segment collides when it intersects the closed unit square of a blocked cell
(edges and corners included); shapely's predicates are exact, so no tolerance is involved.
"""

import contextlib
import importlib.util
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
import shapely
from click.testing import CliRunner

ROOT = Path(__file__).resolve().parent.parent
#: Settings of whoever started the suite that no test, nor any process a test starts, may
#: inherit: ``make -s test`` exports MAKEFLAGS=s (a make a test starts then prints nothing), a
#: caller's pytest options, the batch's fault injection (usvtool.batch.failpoint).
CALLER_SETTINGS = ("MAKEFLAGS", "MFLAGS", "GNUMAKEFLAGS", "MAKELEVEL", "MAKEOVERRIDES", "MAKEFILES",
                   "PYTEST_ADDOPTS", "PYTEST_PLUGINS", "USVTOOL_FAILPOINT")  # fmt: skip
for _name in CALLER_SETTINGS:
    os.environ.pop(_name, None)
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


@pytest.fixture(scope="session")
def benchmark():
    """``benchmark(name)``: the script benchmarks/NAME.py as a module (they are scripts, not a
    package), loaded once."""
    loaded = {}

    def load(name: str):
        if name not in loaded:
            path = ROOT / "benchmarks" / f"{name}.py"
            spec = importlib.util.spec_from_file_location(name, path)
            loaded[name] = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(loaded[name])
        return loaded[name]

    return load


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


class ShapelyReference:
    """Blocked cells of ``blocked`` (row 0 = y 0) as closed boxes in cell coordinates, grown
    by ``grow`` on every side."""

    def __init__(self, blocked: np.ndarray, grow: float = 0.0):
        rows, cols = np.nonzero(blocked)
        boxes = shapely.box(cols - grow, rows - grow, cols + 1 + grow, rows + 1 + grow)
        self.tree = shapely.STRtree(boxes)

    def segments_hit(self, a, b) -> np.ndarray:
        """Whether each segment ``a[i] → b[i]`` intersects a blocked cell's closed square."""
        lines = shapely.linestrings(np.stack([np.asarray(a, float), np.asarray(b, float)], 1))
        hit_lines, _ = self.tree.query(lines, predicate="intersects")
        out = np.zeros(len(lines), bool)
        out[hit_lines] = True
        return out

    def route_free(self, route) -> bool:
        """Whether the polyline (cell coordinates) touches no blocked cell."""
        route = np.asarray(route, float)
        return not self.segments_hit(route[:-1], route[1:]).any()


@pytest.fixture(scope="session")
def reference():
    """``reference(blocked)``: the :class:`ShapelyReference` of a blocked mask."""
    return ShapelyReference


@pytest.fixture
def one_cell() -> np.ndarray:
    """A 10 x 10 blocked mask whose only obstacle is the cell x 5..6, y 5..6 (cell coordinates)."""
    blocked = np.zeros((10, 10), bool)
    blocked[5, 5] = True
    return blocked
