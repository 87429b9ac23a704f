"""Shared fixtures: paths to the bundled charts, a CLI runner, bad S-57 cells, and an
independent collision reference written plainly with shapely (for the collision check's tests
and every stage whose routes or tracks must be collision-free).

The reference: a segment collides when it intersects the closed unit square of a blocked cell
(edges and corners included); shapely's predicates are exact, so no tolerance is involved.
"""

import contextlib
import importlib.util
import json
import os
import shutil
import signal
import subprocess
import sys
import time
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


@pytest.fixture
def dask_cluster(site, tmp_path):
    """A ``dask scheduler`` and two ``dask worker`` processes (the dask.distributed command of
    this environment) on this machine, on free ports, the workers with the requesting module's
    ``site`` (a folder holding a plugin's distribution) on their PYTHONPATH (a plugin must be
    installed where the jobs run); its address. Every
    process is stopped, its process group killed, however the test ends."""
    distributed = pytest.importorskip("distributed", reason="dask[distributed] is not installed "
                                      "(pip install 'usvtool[dask]')")  # fmt: skip
    dask = Path(sys.executable).with_name("dask")
    if not dask.exists():
        pytest.skip(f"no {dask}")
    env = {**os.environ, "PYTHONPATH": str(site), "DASK_DISTRIBUTED__WORKER__DAEMON": "False"}
    where = tmp_path / "cluster"
    where.mkdir()
    file = where / "scheduler.json"
    processes = []

    def start(*args, log: str):
        with open(where / log, "w") as out:
            processes.append(subprocess.Popen([str(dask), *map(str, args)], env=env, cwd=where,
                                              stdout=out, stderr=subprocess.STDOUT,
                                              start_new_session=True))  # fmt: skip

    try:
        start("scheduler", "--host", "127.0.0.1", "--port", 0, "--no-dashboard",
              "--scheduler-file", file, log="scheduler.log")  # fmt: skip
        deadline = time.monotonic() + 30
        while not (file.exists() and file.stat().st_size):
            assert time.monotonic() < deadline, (where / "scheduler.log").read_text()
            assert processes[0].poll() is None, (where / "scheduler.log").read_text()
            time.sleep(0.1)
        time.sleep(0.2)  # the file complete
        address = json.loads(file.read_text())["address"]
        for i in range(2):
            start("worker", address, "--nworkers", 1, "--nthreads", 1, "--no-dashboard",
                  "--host", "127.0.0.1", "--local-directory", where / f"w{i}",
                  log=f"worker{i}.log")  # fmt: skip
        with distributed.Client(address, timeout=30) as client:
            client.wait_for_workers(2, timeout=30)
        yield address
    finally:
        for p in processes:
            try:
                os.killpg(p.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        for p in processes:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                p.wait()


def pytest_collection_modifyitems(items):
    """The modules holding tests marked slow first, each module's tests kept in order: with
    pytest-xdist's ``--dist loadscope`` (make test) a module runs whole on one worker, in the
    order the modules come, so the long ones start first and the short ones fill the end
    rather than one worker finishing a long module alone (a sort, the same in every worker)."""
    slow = {item.path for item in items if item.get_closest_marker("slow") is not None}
    items.sort(key=lambda item: item.path not in slow)
