"""Raster sources: any CRS, no-data / alpha / mask bands, 16-bit, cutlines, --resolution.

Expected pixel values are computed by hand in the comments: 16-bit v scales to
round(v * 255 / 65535) (or / 4095 for 12-bit data), alpha a over white gives
round((c * a + 255 * (255 - a)) / 255).
"""

import json
import re
import warnings

import cv2
import numpy as np
import pytest
import rasterio
import shapely
from affine import Affine
from rasterio import features
from rasterio.warp import Resampling, calculate_default_transform, reproject
from shapely.geometry import Polygon, box, mapping

from usvtool.chart.colours import colour_index
from usvtool.chart.preprocessing import PreprocessOptions, preprocess
from usvtool.chart.sources import RasterChart, read_raster
from usvtool.errors import UsvError
from usvtool.geodesy import WGS84, reproject_geometries, transformer
from usvtool.grid import OBSTACLE, read_grid

LANDA, DEPDW = (201, 185, 122), (212, 234, 238)
UTM16 = "EPSG:32616"
ORIGIN = (300000.0, 3230000.0)  # UTM 16N, near Head of Passes


def write_tif(path, bands, crs=UTM16, res=1.0, **profile):
    """A GeoTIFF (bands first) with ``res`` m pixels from :data:`ORIGIN`; crs None: no georef."""
    count, h, w = bands.shape
    profile = dict(driver="GTiff", width=w, height=h, count=count, dtype=bands.dtype.name,
                   **profile)
    if crs is not None:
        profile.update(crs=crs, transform=Affine(res, 0, ORIGIN[0], 0, -res, ORIGIN[1]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
        with rasterio.open(path, "w", **profile) as ds:
            ds.write(bands)
    return path


def island(h=40, w=60):
    """Water with a land square in rows 10..29, columns 10..29 (RGB, bands first)."""
    img = np.empty((3, h, w), np.uint8)
    img[:] = np.array(DEPDW, np.uint8)[:, None, None]
    img[:, 10:30, 10:30] = np.array(LANDA, np.uint8)[:, None, None]
    return img


# ---- the bundled KAP saved as a Web Mercator GeoTIFF, its cutline as no-data ----------------


def kap_cutline(kap):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with rasterio.open(kap) as ds:
            wkt = ds.tags()["BSB_CUTLINE"]
    numbers = [float(v) for v in re.findall(r"-?\d+\.\d+", wkt)]
    return Polygon(np.reshape(numbers, (-1, 2)))


@pytest.fixture(scope="module")
def kap_3857(kap, tmp_path_factory):
    """The KAP warped from its GCPs to EPSG:3857 (nearest neighbour), as a palette GeoTIFF whose
    pixels outside the chart's cutline hold the no-data index 255."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with rasterio.open(kap) as ds:
            band, cmap, (gcps, gcp_crs) = ds.read(1), ds.colormap(1), ds.gcps
    h, w = band.shape
    dst_t, dw, dh = calculate_default_transform(gcp_crs, "EPSG:3857", w, h, gcps=gcps)
    out = np.full((dh, dw), 255, np.uint8)
    reproject(band, out, gcps=gcps, src_crs=gcp_crs, dst_transform=dst_t, dst_crs="EPSG:3857",
              dst_nodata=255, resampling=Resampling.nearest)
    cut = reproject_geometries([kap_cutline(kap)], WGS84, "EPSG:3857")[0]
    out[features.geometry_mask([cut], out.shape, dst_t)] = 255
    path = tmp_path_factory.mktemp("mercator") / "11361_4_3857.tif"
    with rasterio.open(path, "w", driver="GTiff", width=dw, height=dh, count=1, dtype="uint8",
                       crs="EPSG:3857", transform=dst_t, nodata=255) as ds:
        ds.write(out, 1)
        ds.write_colormap(1, cmap)
    return path


@pytest.fixture(scope="module")
def kap_and_mercator(kap, kap_3857):
    return preprocess(kap, PreprocessOptions()), preprocess(kap_3857, PreprocessOptions())


def test_web_mercator_geotiff_gives_the_kaps_grid_in_ground_metres(kap_and_mercator):
    ours, theirs = kap_and_mercator
    assert theirs.summary()["source_kind"] == "geotiff"
    assert theirs.grid.crs.to_epsg() == ours.grid.crs.to_epsg() == 32616  # warped to UTM 16N
    assert theirs.summary()["cell_size_m"] == theirs.grid.cell_size == 3.75
    assert theirs.grid.transform.a == pytest.approx(3.75)  # UTM metres, not Mercator units
    share = theirs.summary()["obstacle_fraction"]
    assert abs(share - ours.summary()["obstacle_fraction"]) <= 0.01  # before: 0.229 vs 0.674


def test_web_mercator_geotiffs_paper_margin_is_outside_the_chart(kap_and_mercator):
    _, theirs = kap_and_mercator
    grid = theirs.grid
    to_utm = transformer(WGS84, grid.crs)
    row, col = grid.cell_of(*to_utm.transform(-89.265, 29.1233 - 0.005))  # blank paper
    assert grid.cells[row, col] == OBSTACLE
    assert not theirs.chart.valid.all()


def test_utm_geotiff_is_kept_as_is(tmp_path):
    img = island()
    img[:, 5, 7] = (255, 0, 0)
    path = write_tif(tmp_path / "utm.tif", img, res=2.0)
    chart = read_raster(path)
    assert chart.kind == "geotiff" and chart.frame.crs.to_epsg() == 32616
    assert chart.frame.transform == Affine(2.0, 0, ORIGIN[0], 0, -2.0, ORIGIN[1])
    assert np.array_equal(chart.rgb, np.moveaxis(img, 0, -1))  # not resampled
    assert chart.valid.all()


# ---- RasterChart as colour indices ---------------------------------------------------------


def test_colour_index_of_a_small_image():
    rgb = np.array([[[9, 9, 9], [0, 0, 255]], [[9, 9, 9], [0, 1, 0]]], np.uint8)
    index, palette = colour_index(rgb)
    # distinct colours in packed order: (0,0,255)=255 < (0,1,0)=256 < (9,9,9)
    assert palette.tolist() == [[0, 0, 255], [0, 1, 0], [9, 9, 9]]
    assert index.tolist() == [[2, 0], [2, 1]] and index.dtype == np.uint8


def test_raster_chart_from_rgb_or_from_indices():
    rgb = np.moveaxis(island(), 0, -1)
    valid = np.ones(rgb.shape[:2], bool)
    a = RasterChart.from_rgb(rgb, valid, None, "image")
    assert sorted(map(tuple, a.palette.tolist())) == sorted([DEPDW, LANDA])
    assert np.array_equal(a.palette[a.index], rgb)
    b = RasterChart(a.index, a.palette, valid, None, "image")
    assert np.array_equal(b.rgb, rgb) and b.rgb is b.rgb  # made once


def test_palette_geotiff_merges_repeated_and_drops_unused_entries(tmp_path):
    band = np.zeros((1, 8, 8), np.uint8)
    band[0, :, 4:] = 2  # entry 2 repeats entry 0's white
    band[0, 0, 0] = 1
    path = tmp_path / "pal.tif"
    with rasterio.open(path, "w", driver="GTiff", width=8, height=8, count=1, dtype="uint8",
                       crs=UTM16, transform=Affine(1, 0, ORIGIN[0], 0, -1, ORIGIN[1])) as ds:
        ds.write(band)
        ds.write_colormap(1, {0: (255, 255, 255), 1: (0, 0, 0), 2: (255, 255, 255),
                              3: (9, 9, 9)})
    chart = read_raster(path)
    assert chart.palette.tolist() == [[255, 255, 255], [0, 0, 0]]  # entry order, distinct
    assert (chart.index == (band[0] == 1)).all()


def test_16_bit_palette_geotiff_indexes_its_three_used_entries(tmp_path):
    band = np.zeros((1, 8, 8), np.uint16)
    band[0, :, 4:] = 1000
    band[0, 0, 0] = 65535
    path = tmp_path / "pal16.tif"
    with rasterio.open(path, "w", driver="GTiff", width=8, height=8, count=1, dtype="uint16",
                       crs=UTM16, transform=Affine(1, 0, ORIGIN[0], 0, -1, ORIGIN[1])) as ds:
        ds.write(band)
        ds.write_colormap(1, {0: (255, 255, 255), 1000: (0, 0, 255), 65535: (9, 9, 9)})
    chart = read_raster(path)
    assert chart.palette.tolist() == [[255, 255, 255], [0, 0, 255], [9, 9, 9]]
    assert chart.index.dtype == np.uint8  # 3 colours of a 65 536-entry table
    assert chart.index[0, :6].tolist() == [2, 0, 0, 0, 1, 1]


# ---- no-data, alpha, internal mask ---------------------------------------------------------


def test_nodata_pixels_are_outside_the_chart_and_obstacles_in_the_grid(tmp_path):
    img = island()
    img[:, 0:10, 40:60] = 0  # a 10 x 20 px no-data block in the water, top right
    path = write_tif(tmp_path / "nodata.tif", img, res=1.0, nodata=0)
    chart = read_raster(path)
    expected = np.ones((40, 60), bool)
    expected[0:10, 40:60] = False
    assert np.array_equal(chart.valid, expected)
    grid = preprocess(path, PreprocessOptions(cell_size=5.0, margin=0.1)).grid
    # cells of 5 m from the top left: rows 0-1, columns 8-11 are the no-data block
    assert (grid.cells[0:2, 8:12] == OBSTACLE).all()
    assert (grid.cells[4:8, 8:12] == 0).all()  # open water below it stays navigable


def test_internal_mask_band_marks_outside(tmp_path):
    path = tmp_path / "mask.tif"
    mask = np.full((40, 60), 255, np.uint8)
    mask[:, :5] = 0
    with rasterio.Env(GDAL_TIFF_INTERNAL_MASK=True):
        write_tif(path, island())
        with rasterio.open(path, "r+") as ds:
            ds.write_mask(mask)
    assert np.array_equal(read_raster(path).valid, mask > 0)


def rgba_pixels(scale=1):
    """RGBA (bands first) ``scale`` x the 8-bit values: three probe pixels in row 0 of an
    island chart: alpha 0, alpha 128 over (0, 100, 200), and opaque (0, 100, 200)."""
    img = np.concatenate([island(), np.full((1, 40, 60), 255, np.uint8)]).astype(np.uint16)
    img[:, 0, 0] = (0, 100, 200, 0)
    img[:, 0, 1] = (0, 100, 200, 128)
    img[:, 0, 2] = (0, 100, 200, 255)
    return (img * scale).astype(np.uint8 if scale == 1 else np.uint16)


# (0, 100, 200) at alpha 128 over white: (0 + 255 * 127) / 255 = 127,
# (100 * 128 + 255 * 127) / 255 = 177.2 -> 177, (200 * 128 + 255 * 127) / 255 = 227.4 -> 227
COMPOSITED = [127, 177, 227]


@pytest.mark.parametrize("scale", [1, 257])
def test_rgba_geotiff_alpha_zero_outside_partial_over_white(tmp_path, scale):
    path = write_tif(tmp_path / "rgba.tif", rgba_pixels(scale), photometric="RGB", alpha="YES")
    chart = read_raster(path)
    assert not chart.valid[0, 0] and chart.valid.sum() == 40 * 60 - 1
    assert chart.rgb[0, 1].tolist() == COMPOSITED
    assert chart.rgb[0, 2].tolist() == [0, 100, 200]
    assert chart.rgb[20, 20].tolist() == list(LANDA)


@pytest.mark.parametrize("scale", [1, 257])
def test_rgba_png_through_opencv(tmp_path, scale):
    rgba = np.moveaxis(rgba_pixels(scale), 0, -1)
    path = tmp_path / "chart.png"
    cv2.imwrite(str(path), cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGRA))
    chart = read_raster(path, resolution=1.0)
    assert chart.kind == "image" and not chart.valid[0, 0]
    assert chart.rgb[0, 1].tolist() == COMPOSITED and chart.rgb[0, 2].tolist() == [0, 100, 200]


# ---- 16-bit ---------------------------------------------------------------------------------


def test_16_bit_rgb_scales_by_257(tmp_path):
    img = island().astype(np.uint16) * 257  # 8-bit colours stored as v * 257: recovered exactly
    # 65535 -> 255; 1000 / 257 = 3.89 -> 4; 128 / 257 = 0.498 -> 0; 129 / 257 = 0.502 -> 1
    img[:, 0, 0] = (65535, 1000, 128)
    img[:, 0, 1] = (129, 0, 0)
    chart = read_raster(write_tif(tmp_path / "rgb16.tif", img, crs=None), resolution=1.0)
    assert chart.rgb[0, 0].tolist() == [255, 4, 0] and chart.rgb[0, 1].tolist() == [1, 0, 0]
    assert chart.rgb[20, 20].tolist() == list(LANDA) and chart.rgb[35, 50].tolist() == list(DEPDW)


def test_12_bit_tiff_scales_by_its_declared_nbits(tmp_path):
    img = (island().astype(np.uint32) * 4095 // 255).astype(np.uint16)
    # 4095 -> 255; 2048 * 255 / 4095 = 127.5 -> 128; 16 * 255 / 4095 = 0.996 -> 1
    img[:, 0, 0] = (4095, 2048, 16)
    chart = read_raster(write_tif(tmp_path / "rgb12.tif", img, nbits=12))
    assert chart.rgb[0, 0].tolist() == [255, 128, 1]


def test_16_bit_grey_png(tmp_path):
    grey = np.full((40, 60), 212 * 257, np.uint16)
    grey[10:30, 10:30] = 1000  # 1000 / 257 = 3.89 -> 4
    path = tmp_path / "grey16.png"
    cv2.imwrite(str(path), grey)
    chart = read_raster(path, resolution=1.0)
    assert chart.rgb[20, 20].tolist() == [4, 4, 4] and chart.rgb[0, 0].tolist() == [212] * 3
    assert len(chart.palette) == 2


def test_float_image_is_refused(tmp_path):
    path = write_tif(tmp_path / "float.tif", island().astype(np.float32))
    with pytest.raises(UsvError, match="float.tif: expected 8- or 16-bit colour, found float32"):
        read_raster(path)


# ---- cutlines --------------------------------------------------------------------------------


def write_geojson(path, geometry, crs=None):
    doc = {"type": "FeatureCollection",
           "features": [{"type": "Feature", "properties": {}, "geometry": mapping(geometry)}]}
    if crs:
        doc["crs"] = {"type": "name", "properties": {"name": crs}}
    path.write_text(json.dumps(doc))
    return path


def test_cutline_in_a_named_crs_clips_a_geotiff(tmp_path):
    chart_path = write_tif(tmp_path / "utm.tif", island())
    x0, y0 = ORIGIN
    # the left 25 columns (pixel centres at x0 + 0.5 .. x0 + 24.5), all 40 rows
    cut = write_geojson(tmp_path / "cut.geojson", box(x0 - 5, y0 - 50, x0 + 25, y0 + 5), UTM16)
    valid = read_raster(chart_path, cutline=cut).valid
    expected = np.zeros((40, 60), bool)
    expected[:, :25] = True
    assert np.array_equal(valid, expected)


def test_cutline_on_a_kap_intersects_its_own(kap, tmp_path):
    own = read_raster(kap)
    north = box(-89.30, 29.16, -89.20, 29.20)  # lon/lat: the chart's northern part
    clipped = read_raster(kap, cutline=write_geojson(tmp_path / "north.geojson", north))
    # independent check: pixel centres inside the polygon in UTM, by shapely
    poly = reproject_geometries([north], WGS84, own.frame.crs)[0]
    rows, cols = np.nonzero(own.valid)
    x, y = own.frame.transform @ (cols + 0.5, rows + 0.5)
    inside = shapely.contains_xy(poly, x, y)
    assert clipped.valid.sum() == inside.sum() and 0 < inside.sum() < own.valid.sum()
    assert clipped.valid[rows[inside], cols[inside]].all()
    assert np.array_equal(clipped.index, own.index)


# ---- bad input through the CLI: one line naming the option, exit 1 --------------------------


def one_line_error(r, *words):
    assert r.exit_code == 1, r.output
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    for w in words:
        assert w in r.stderr


def bad_cutlines(tmp_path):
    (tmp_path / "text.geojson").write_text("not json")
    return {
        "missing": (tmp_path / "missing.geojson", "no such file"),
        "not json": (tmp_path / "text.geojson", "not a GeoJSON polygon"),
        "line": (write_geojson(tmp_path / "line.geojson", shapely.LineString([(0, 0), (1, 1)])),
                 "not a polygon (LineString)"),
        "elsewhere": (write_geojson(tmp_path / "far.geojson", box(10, 10, 11, 11)),
                      "no part of the chart"),
        "bowtie": (write_geojson(tmp_path / "bow.geojson",
                                 Polygon([(0, 0), (1, 1), (1, 0), (0, 1)])), "not a valid polygon"),
    }


@pytest.mark.parametrize("case", ["missing", "not json", "line", "elsewhere", "bowtie"])
def test_bad_cutline(case, tmp_path, usv):
    chart = write_tif(tmp_path / "utm.tif", island())
    cut, words = bad_cutlines(tmp_path)[case]
    out = tmp_path / "grid.tif"
    one_line_error(usv("preprocess", chart, "-o", out, "--cutline", cut), "--cutline", words)
    assert not out.exists()


def test_cutline_refused_for_a_plain_image_and_a_vector_map(tmp_path, charts, usv):
    cut = write_geojson(tmp_path / "cut.geojson", box(0, 0, 1, 1))
    plain = write_tif(tmp_path / "plain.tif", island(), crs=None)
    args = ("-o", tmp_path / "g.tif", "--cutline", cut)
    one_line_error(usv("preprocess", plain, "--resolution", 1, *args), "--cutline",
                   "no georeference")
    one_line_error(usv("preprocess", charts / "env1.geojson", *args), "--cutline")


def test_resolution_refused_for_georeferenced_sources(tmp_path, kap, charts, usv):
    geotiff = write_tif(tmp_path / "utm.tif", island())
    for source in (kap, geotiff, charts / "env1.geojson"):
        r = usv("preprocess", source, "-o", tmp_path / "g.tif", "--resolution", 2)
        one_line_error(r, "--resolution", source.name)
    assert not (tmp_path / "g.tif").exists()


def test_cli_16_bit_rgba_png(tmp_path, usv):
    rgba = np.moveaxis(rgba_pixels(257), 0, -1).copy()
    rgba[:, 50:, 3] = 0  # the right 10 columns are outside the chart
    src = tmp_path / "chart16.png"
    cv2.imwrite(str(src), cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGRA))
    out = tmp_path / "grid.tif"
    r = usv("preprocess", src, "-o", out, "--resolution", 1, "--cell-size", 5, "--margin", 0.1)
    assert r.exit_code == 0, r.stderr
    cells = read_grid(out).cells  # 12 x 8 cells of 5 m from the lower-left corner
    assert (cells[:, 10:] == OBSTACLE).all()  # outside the chart
    assert (cells[2:6, 2:6] == OBSTACLE).all()  # the island
    assert (cells[:, 7:9] == 0).all()  # water between
