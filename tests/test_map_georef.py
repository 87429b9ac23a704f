"""A scenario's map and wind field without a north-up geotransform: one line, no warning.

rasterio warns (``NotGeoreferencedWarning``, two lines on stderr) when it opens a raster with no
geotransform; the readers refuse such a map or field themselves, so the command's own line is
the only one. A rotated grid GeoTIFF given as a map is refused (its cells are not the grid's
north-up squares): preprocessing the chart it came from warps it north-up.
"""

import warnings

import cv2
import numpy as np
import rasterio
from affine import Affine
from rasterio.errors import NotGeoreferencedWarning

SCENARIO = """name: t
sim: {{dt: 0.5, duration: 5, goal_tolerance: 5}}
own: {{start: [5, 5], goal: [40, 40], heading: 0, speed: 2, vessel: iwso-dwa-usv}}
{extra}
"""


def one_line_without_warning(usv, *args, words=()):
    """Run ``usvtool ARGS``: exit 1, one line on stderr holding ``words``, and no rasterio
    NotGeoreferencedWarning (recorded here: pytest would catch it before the runner's stderr)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = usv(*args)
    assert not [w for w in caught if issubclass(w.category, NotGeoreferencedWarning)]
    assert r.exit_code == 1, r.output
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    for w in words:
        assert w in lines[0], lines[0]


def png_grid(path):
    """A 50 x 50 PNG of grid values (0 water, a 10 x 10 square of 1): no georeference."""
    cells = np.zeros((50, 50), np.uint8)
    cells[20:30, 20:30] = 1
    cv2.imwrite(str(path), cells)
    return path


def scenario(tmp_path, extra):
    path = tmp_path / "s.yaml"
    path.write_text(SCENARIO.format(extra=extra))
    return path


def test_a_png_map_is_one_line_in_simulate_and_plan(tmp_path, usv):
    png_grid(tmp_path / "map.png")
    words = ("map.png", "no geotransform")
    one_line_without_warning(
        usv, "simulate", scenario(tmp_path, "map: map.png"), "-o", tmp_path / "t.csv", words=words
    )
    one_line_without_warning(
        usv,
        "plan",
        tmp_path / "map.png",
        "--start",
        5,
        5,
        "--goal",
        40,
        40,
        "-o",
        tmp_path / "r.geojson",
        words=words,
    )
    assert not (tmp_path / "t.csv").exists() and not (tmp_path / "r.geojson").exists()


def test_a_png_wind_field_is_one_line(tmp_path, usv):
    cv2.imwrite(str(tmp_path / "wind.png"), np.full((20, 20, 3), 5, np.uint8))
    one_line_without_warning(
        usv,
        "simulate",
        scenario(tmp_path, "weather: {field: wind.png}"),
        "-o",
        tmp_path / "t.csv",
        words=("wind.png",),
    )


def test_a_rotated_grid_geotiff_as_a_map_is_refused(tmp_path, usv):
    # a grid preprocess could have written, then rotated by 30 degrees: its cells are no longer
    # the north-up squares the planners and the collision check work on
    t = Affine.translation(300000, 3300000) @ Affine.rotation(30) @ Affine.scale(2, -2)
    with rasterio.open(
        tmp_path / "rotated.tif",
        "w",
        driver="GTiff",
        width=50,
        height=50,
        count=1,
        dtype="uint8",
        crs="EPSG:32616",
        transform=t,
    ) as ds:
        ds.write(np.zeros((1, 50, 50), np.uint8))
    words = ("rotated.tif", "north-up", "preprocess")
    one_line_without_warning(
        usv,
        "simulate",
        scenario(tmp_path, "map: rotated.tif"),
        "-o",
        tmp_path / "t.csv",
        words=words,
    )
    one_line_without_warning(
        usv,
        "plan",
        tmp_path / "rotated.tif",
        "--start",
        300010,
        3300010,
        "--goal",
        300040,
        3300040,
        "-o",
        tmp_path / "r.geojson",
        words=words,
    )
