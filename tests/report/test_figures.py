"""The report's figures (usvtool/report/figures): valid PNGs of the fixed size that are not blank
and show what they plot, the same bytes for the same inputs (here and in a fresh process), and
CSV data checked against values computed by hand from small hand-made inputs."""

from __future__ import annotations

import csv
import hashlib
import io
import json
import os
import subprocess
import sys
import time

import numpy as np
import pytest
from affine import Affine
from PIL import Image

from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.report import figures as F
from usvtool.report.figures.encounters import draw_ship
from usvtool.report.figures.raster import PREVIEW_HATCH, PREVIEW_STRIP_PX, ChartImage, display_rgb
from usvtool.report.figures.styles import DPI, MIN_FONT_PT, ship_styles, style
from usvtool.report.figures.wind import Difference, arrival_differences
from usvtool.trace import Trace, format_events

pytestmark = pytest.mark.slow  # every figure drawn


OBSTACLE_RGB, MARGIN_RGB = (64, 64, 64), (200, 200, 200)


# --- hand-made inputs ------------------------------------------------------------------------


def small_grid() -> Grid:
    """20 x 20 cells of 5 m (100 m square): a 4 x 4 obstacle at rows 8-11, columns 8-11 (map
    x 40..60, y 40..60) in a one-cell margin ring (6 x 6 minus 4 x 4 = 20 cells)."""
    cells = np.zeros((20, 20), np.uint8)
    cells[7:13, 7:13] = 2
    cells[8:12, 8:12] = 1
    return Grid(cells, Affine(5, 0, 0, 0, -5, 100))


def two_routes() -> dict[str, np.ndarray]:
    return {"wso": np.array([[5.0, 5.0], [5.0, 95.0], [95.0, 95.0]]),
            "astar": np.array([[5.0, 5.0], [95.0, 5.0], [95.0, 95.0]])}  # fmt: skip


def two_ship_trace() -> Trace:
    """t = 0..10 s: the own ship from (0, 0) east at 10 m/s; the target from (60, 100) south at
    10 m/s. Nearest distance sqrt((60 - 10t)^2 + (100 - 10t)^2): 116.619 m at 0, its minimum
    sqrt(800) = 28.284 m at t = 8 s."""
    t = np.arange(11.0)
    own = np.stack([10 * t, 0 * t, 0 * t + 90, 0 * t + 10, 0 * t], axis=1)
    target = np.stack([0 * t + 60, 100 - 10 * t, 0 * t + 180, 0 * t + 10, 0 * t], axis=1)
    return Trace.from_states(t, ["own", "target"], np.stack([own, target], axis=1))


def chart_image() -> ChartImage:
    """40 x 40 pixels over small_grid's 100 m: red west, blue east; the obstacle's pixels (rows
    and columns 16-23) outside the chart."""
    rgb = np.zeros((40, 40, 3), np.uint8)
    rgb[:, :20] = (255, 0, 0)
    rgb[:, 20:] = (0, 0, 255)
    outside = np.zeros((40, 40), bool)
    outside[16:24, 16:24] = True
    return ChartImage(rgb, (0.0, 100.0, 0.0, 100.0), outside)


def all_plots() -> dict[str, F.Plot]:
    """Every figure of the hand-made inputs (also run in a fresh process)."""
    grid, trace = small_grid(), two_ship_trace()
    shifted = trace.states()
    shifted[:, 0, 1] += 1.0  # the own ship 1 m further north
    other = Trace.from_states(trace.t, trace.ships, shifted)
    return {
        "routes": F.routes_on_grid(grid, two_routes(), (5, 5), (95, 95), "routes"),
        "routes_chart": F.routes_on_grid(grid, two_routes(), (5, 5), (95, 95), "on the chart",
                                         chart_image()),  # fmt: skip
        "convergence": F.convergence({"wso": [[3, 2, 1], [1, 1, 1], [2, 1.5, 1]],
                                      "astar": [[4, 4, 2]]}, "convergence"),  # fmt: skip
        "boxplots": F.boxplots({"length (m)": {"wso": [1, 2, 3], "astar": [2, 4]},
                                "turns": {"wso": [1, 1], "astar": [3, 0]}}, "boxes"),  # fmt: skip
        "snapshots": F.encounter_snapshots(trace, {"preparatory": 0, "meeting": 5,
                                                   "completion": 10},
                                           {"own": 10, "target": 5}, grid=grid,
                                           title="snapshots", goal=(100, 0)),  # fmt: skip
        "states": F.states_against_time(trace),
        "nearest": F.nearest_distance({"ccdwa": trace, "udwa": other}, "nearest", limit=20),
        "preprocessing": F.preprocessing(chart_image(), grid, "preprocessing"),
        "boxplots_clipped": F.boxplots({"turns": FAR_TURNS}, "one far value"),
        "differences_clipped": arrival_differences(FAR_DIFFERENCES, "one far scene"),
    }


#: astar's one route turns 33 times beside the optimizers' 1-5: beyond the axis.
FAR_TURNS = {"wso": [3.0, 3.0, 2.0, 5.0], "iwso": [1.0, 3.0, 3.0], "astar": [33.0]}
#: udwa+ arrives 105 s later on one scene, the others within 5 s of the reference.
FAR_DIFFERENCES = [
    Difference("udwa - dwa", "udwa", {"s0": -3.0, "s1": -2.0, "s2": -4.0}, 0, -3.0, -4.0, -2.0),
    Difference("udwa+ - dwa", "udwa+", {"s0": -1.0, "s1": 105.0, "s2": 1.0}, 0, 0.0, -1.0, 1.0),
]


# --- helpers ----------------------------------------------------------------------------------


def pixels(png: bytes) -> np.ndarray:
    """The PNG decoded (PIL) as an (h, w, 3) uint8 array; a valid PNG or an error."""
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))


def near(img: np.ndarray, rgb, tol: int = 40) -> int:
    """How many pixels are within ``tol`` (per channel) of colour ``rgb``."""
    return int((np.abs(img.astype(int) - np.array(rgb)).max(axis=2) <= tol).sum())


def hex_rgb(colour: str) -> tuple[int, int, int]:
    return tuple(int(colour[i:i + 2], 16) for i in (1, 3, 5))


def rows(plot: F.Plot) -> list[list[str]]:
    assert plot.data.endswith("\n") and "\r" not in plot.data
    return list(csv.reader(io.StringIO(plot.data)))


def capture_figures(draw) -> list:
    """The Matplotlib figures that ``draw()`` writes as PNGs (:func:`canvas.png` reads each
    one's pixels once), drawn (their artists as in the PNG)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    saved, original = [], FigureCanvasAgg.buffer_rgba

    def keep(self, *args, **kwargs):
        saved.append(self.figure)
        return original(self, *args, **kwargs)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(FigureCanvasAgg, "buffer_rgba", keep)
        draw()
    return saved


@pytest.fixture(scope="module")
def drawn() -> tuple[dict[str, F.Plot], list]:
    """Every figure of the hand-made inputs, and the Matplotlib figures they were saved from."""
    out: dict[str, F.Plot] = {}
    return out, capture_figures(lambda: out.update(all_plots()))


@pytest.fixture(scope="module")
def plots(drawn) -> dict[str, F.Plot]:
    return drawn[0]


# --- every figure -----------------------------------------------------------------------------

#: Pixels (width, height) at 150 dpi. The text width 182 mm = 7.165 in (1074 px: Matplotlib
#: truncates); routes: a 100 m square view with the legend beside it, a map 3.5 in square (of
#: 7.165 - 0.85 - 0.15 - 2.3 = 3.865) and 0.35 + 0.55 in of margins, 4.4 in; convergence
#: 7.2 x 4.4; boxplots two panels in one row, 2.9 + 0.4 in; snapshots three panels of
#: (7.165 - 0.6) / 3 in and 0.25 in each, 0.9 in more, 3.338 in; states 7.2 x 5.6; nearest
#: 7.2 x 3.9; preprocessing two panels of (7.165 - 0.5) / 2 in, a square grid, and 1.1 in, 4.433 in;
#: boxplots_clipped one panel, 7.2 x 3.3 in; differences_clipped two rows, 7.2 x (0.9 + 2 x 0.7).
SIZES = {"routes": (1074, 660), "routes_chart": (1074, 660), "convergence": (1080, 660),
         "boxplots": (1080, 495), "snapshots": (1074, 500), "states": (1080, 840),
         "nearest": (1080, 585), "preprocessing": (1074, 664), "boxplots_clipped": (1080, 495),
         "differences_clipped": (1080, 345)}  # fmt: skip


@pytest.mark.parametrize("name", sorted(SIZES))
def test_each_figure_is_a_png_of_its_fixed_size_with_many_colours_and_small(plots, name):
    img = pixels(plots[name].png)
    assert img.shape == (SIZES[name][1], SIZES[name][0], 3)
    dpi = Image.open(io.BytesIO(plots[name].png)).info["dpi"]
    assert dpi == pytest.approx((DPI, DPI), abs=0.05)
    packed = img.astype(np.int32) @ np.array([1 << 16, 1 << 8, 1])
    assert len(np.unique(packed)) > 20
    assert len(plots[name].png) < 300_000


def test_every_text_prints_at_least_7_pt_at_the_page_width(drawn):
    """A figure w inches wide is printed min(w * 150 / 96, 182 / 25.4) inches wide (a PNG at
    96 px an inch, at most the A4 text width): every text's size, so scaled, is >= 7 pt."""
    from matplotlib.text import Text

    figures = drawn[1]
    assert len(figures) == len(SIZES)
    for fig in figures:
        w = fig.get_figwidth()
        scale = min(w * 150 / 96, 182 / 25.4) / w
        texts = [t for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip()]
        assert len(texts) > 10  # titles, labels, ticks, legend
        smallest = min(texts, key=Text.get_fontsize)
        assert smallest.get_fontsize() * scale >= MIN_FONT_PT, smallest.get_text()


def test_a_method_has_its_style_in_every_figure_whatever_its_place():
    """Methods in different orders in four figures: each line's colour and marker are its
    registered style's, so the same in every figure (a colour by position would swap them)."""
    import matplotlib.colors as mcolors

    r, trace = two_routes(), two_ship_trace()
    figures = capture_figures(lambda: (
        F.routes_on_grid(small_grid(), {"astar": r["astar"], "iwso+s": r["wso"] + 1,
                                        "wso": r["wso"]}, (5, 5), (95, 95), ""),
        F.routes_on_grid(small_grid(), {"mine": r["astar"], "wso": r["wso"]}, (5, 5), (95, 95),
                         ""),
        F.convergence({"iwso+s": [[3, 2, 1]], "mine": [[2, 2, 2]], "wso": [[2, 1, 1]]}, ""),
        F.nearest_distance({"udwa": trace, "dwa": trace}, ""),
        F.boxplots({"m": {"mine": [1, 2], "astar": [2, 3], "wso": [0, 1]}}, "")))  # fmt: skip
    seen: dict[str, set] = {}
    for fig in figures[:4]:
        for line in fig.axes[0].get_lines():
            name = line.get_label().split(" (")[0]
            if name in ("astar", "iwso+s", "wso", "mine", "udwa", "dwa"):
                seen.setdefault(name, set()).add((mcolors.to_hex(line.get_color()),
                                                  line.get_marker()))  # fmt: skip
    assert set(seen) == {"astar", "iwso+s", "wso", "mine", "udwa", "dwa"}
    for name, looks in seen.items():
        assert looks == {(style(name).color.lower(), style(name).marker)}, name
    assert len(seen["wso"]) == 1 and seen["wso"] != seen["astar"]
    boxes = [p for p in figures[4].axes[0].patches]
    labels = [t.get_text() for t in figures[4].axes[0].get_xticklabels()]
    assert labels == ["wso", "astar", "mine"]  # family by family, the unregistered last
    assert [mcolors.to_hex(b.get_facecolor()[:3]) for b in boxes] == [
        style(m).color.lower() for m in labels]
    # a label (how many of its routes are collision-free) changes the tick, not the style
    (fig,) = capture_figures(lambda: F.boxplots(
        {"m": {"astar": [2, 3], "wso": [0, 1]}}, "", {"wso": "wso (2 of 3)"}))  # fmt: skip
    assert [t.get_text() for t in fig.axes[0].get_xticklabels()] == ["wso (2 of 3)", "astar"]
    assert mcolors.to_hex(fig.axes[0].patches[0].get_facecolor()[:3]) == style("wso").color.lower()


def test_the_same_inputs_give_the_same_bytes_here_and_in_a_fresh_process(plots, tmp_path):
    """Also whatever the user's matplotlibrc says (the style is set from the defaults)."""
    again = all_plots()
    assert {k: p.png for k, p in again.items()} == {k: p.png for k, p in plots.items()}
    assert {k: p.data for k, p in again.items()} == {k: p.data for k, p in plots.items()}
    code = ("import hashlib, json, runpy, sys; m = runpy.run_path(sys.argv[1]); "
            "print(json.dumps({k: hashlib.sha256(p.png).hexdigest() "
            "for k, p in m['all_plots']().items()}))")  # fmt: skip
    rc = tmp_path / "matplotlibrc"
    rc.write_text("lines.linewidth: 7\nfont.family: serif\nfont.size: 20\nfigure.facecolor: red\n")
    env = {**os.environ, "MATPLOTLIBRC": str(rc), "MPLBACKEND": "pdf"}
    out = subprocess.run([sys.executable, "-c", code, __file__], capture_output=True, text=True,
                         check=True, env=env)
    fresh = json.loads(out.stdout)
    assert fresh == {k: hashlib.sha256(p.png).hexdigest() for k, p in plots.items()}


# --- routes on the grid -----------------------------------------------------------------------


def test_routes_show_the_grid_classes_and_each_route_colour(plots):
    img = pixels(plots["routes"].png)
    assert near(img, OBSTACLE_RGB, 3) > 500  # 20 x 20 m of obstacle in a 100 m view
    assert near(img, MARGIN_RGB, 3) > 300
    for name in ("wso", "astar"):  # each route ~ 1000 px long; a legend sample is ~ 50 px
        assert near(img, hex_rgb(style(name).color), 30) > 400


def test_routes_over_a_chart_show_the_chart_not_the_grid(plots):
    img = pixels(plots["routes_chart"].png)
    # the chart's red and blue halves fill the map; the grid's dark obstacle is not drawn
    assert near(img, (255, 0, 0), 3) > 100_000 and near(img, (0, 0, 255), 3) > 100_000
    assert near(img, OBSTACLE_RGB, 3) < 2000  # text's edges; the grid's obstacle: ~ 21 000
    for name in ("wso", "astar"):
        assert near(img, hex_rgb(style(name).color), 30) > 400


def test_outside_the_chart_is_in_the_legend_when_the_view_shows_some():
    """chart_image's outside (x, y 40..60) lies in the whole-map view of two_routes, not in the
    view of a route from (75, 5) to (95, 25): 20 m padded by 1.6 m, x and y 73.4..96.6."""
    def legend(routes):
        fig = capture_figures(lambda: F.routes_on_grid(small_grid(), routes, (75, 5), (95, 25),
                                                       "", chart_image()))[0]  # fmt: skip
        return [t.get_text() for t in fig.axes[0].get_legend().get_texts()]

    assert "outside the chart (no data)" in legend(two_routes())
    texts = legend({"wso": np.array([[75.0, 5.0], [95.0, 25.0]])})
    assert texts == ["wso", "start", "goal", "obstacle (tinted red)",
                     "safety margin (tinted yellow)"]  # fmt: skip


def test_a_preview_png_gives_its_map_over_the_grid_and_its_outside(tmp_path):
    """A preview of small_grid (20 x 20 cells): a 40 x 40 map above the 80-pixel strip; the
    obstacle cells (rows, columns 8-11: pixels 16-23) half hatched (outside the chart), and the
    hatch's grey also on a navigable pixel, which is not outside."""
    import cv2

    image = np.full((40 + PREVIEW_STRIP_PX, 40, 3), 255, np.uint8)
    image[:40] = (10, 120, 200)
    image[16:24, 16:20] = PREVIEW_HATCH[0]
    image[16:24:2, 16:20] = PREVIEW_HATCH[1]
    image[0, 0] = PREVIEW_HATCH[0]
    path = tmp_path / "preview.png"
    cv2.imwrite(str(path), image[:, :, ::-1])
    chart = F.preview_chart(path, small_grid())
    assert chart.rgb.shape == (40, 40, 3) and chart.extent == (0.0, 100.0, 0.0, 100.0)
    assert (chart.rgb[30, 30] == (10, 120, 200)).all()
    expected = np.zeros((40, 40), bool)
    expected[16:24, 16:20] = True
    assert (chart.outside == expected).all()
    assert F.preview_chart(tmp_path / "missing.png", small_grid()) is None
    cv2.imwrite(str(path), np.zeros((50, 5, 3), np.uint8))  # 50 px: no room for a 20 px map
    assert F.preview_chart(path, small_grid()) is None


def test_a_route_along_the_edges_is_marked_in_the_map_its_legend_and_its_data():
    plots = []
    fig = capture_figures(lambda: plots.append(F.routes_on_grid(
        small_grid(), two_routes(), (5, 5), (95, 95), "", hugging=["wso"])))[0]
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert texts[:2] == ["wso (edges)", "astar"] and texts[-1] == "hugs the grid's edges"
    band = [line for line in fig.axes[0].get_lines() if line.get_linewidth() == 6.5]
    assert len(band) == 1 and band[0].get_xydata().tolist() == two_routes()["wso"].tolist()
    kinds = [r[0] for r in rows(plots[0])[1:]]
    assert kinds == ["route-edges"] * 3 + ["route"] * 3 + ["start", "goal"]
    with pytest.raises(UsvError, match="hugging names no route: pso"):
        F.routes_on_grid(small_grid(), two_routes(), (5, 5), (95, 95), "", hugging=["pso"])


def test_a_far_value_is_marked_at_the_axis_edge_and_kept_in_the_data(drawn):
    plots, figs = drawn
    names = list(plots)
    boxes = figs[names.index("boxplots_clipped")].axes[0]
    # the rest 1..5 padded by 12 % of 4 each side; astar's 33 a mark with its value
    assert boxes.get_ylim() == pytest.approx((1 - 0.48, 5 + 0.48))
    assert [t.get_text() for t in boxes.texts] == ["33"]
    assert ["turns", "astar", "0", "33.000000"] in rows(plots["boxplots_clipped"])
    differences = figs[names.index("differences_clipped")].axes[0]
    # every scene and interval but the 105 s: -4..1 s, padded by 12 % of 5
    assert differences.get_xlim() == pytest.approx((-4 - 0.6, 1 + 0.6))
    assert [t.get_text() for t in differences.texts] == ["105"]
    assert ["udwa+ - dwa", "s1", "105.000", "", ""] in rows(plots["differences_clipped"])


def test_a_long_route_is_shown_in_its_reach_not_the_whole_chart():
    """A 1 km route east across the north of a 10 x 10 km chart: the view is the route's box
    padded by 80 m each side (8 % of 1 km), widened to a width / height of 4: 1160 x 290 m,
    shifted inside the chart's northern edge; a wide view, so the legend goes below."""
    grid = Grid(np.zeros((100, 100), np.uint8), Affine(100.0, 0, 0, 0, -100.0, 10_000.0))
    captured = capture_figures(lambda: F.routes_on_grid(
        grid, {"astar": np.array([[4000.0, 9900], [5000, 9900]])}, (4000, 9900), (5000, 9900),
        "reach"))  # fmt: skip
    ax = captured[0].axes[0]
    assert ax.get_xlim() == pytest.approx((3920, 5080))
    assert ax.get_ylim() == pytest.approx((10_000 - 1160 / 4, 10_000))

def test_routes_data_are_every_vertex_then_start_and_goal(plots):
    got = rows(plots["routes"])
    assert got[0] == ["kind", "algorithm", "vertex", "x", "y"]
    assert got[1:4] == [["route", "wso", "0", "5.000", "5.000"],
                        ["route", "wso", "1", "5.000", "95.000"],
                        ["route", "wso", "2", "95.000", "95.000"]]  # fmt: skip
    assert got[4][:3] == ["route", "astar", "0"]
    assert got[-2:] == [["start", "", "0", "5.000", "5.000"], ["goal", "", "0", "95.000", "95.000"]]
    assert len(got) == 1 + 6 + 2


def test_display_keeps_the_strongest_class_of_each_block():
    cells = np.zeros((4, 6), np.uint8)
    cells[0, 0] = 2  # block (0, 0): margin
    cells[3, 2], cells[2, 3] = 2, 1  # block (1, 1): obstacle wins over margin
    rgb, f = display_rgb(cells, max_side=3)
    assert f == 2 and rgb.shape == (2, 3, 3)
    assert rgb[..., 0].tolist() == [[200, 255, 255], [255, 64, 255]]


def test_a_big_grid_draws_fast_and_keeps_a_one_cell_obstacle_line():
    cells = np.zeros((3000, 4000), np.uint8)
    cells[:, 2001] = 1  # one cell wide: a display pixel is a 3 x 3 block, each column kept
    grid = Grid(cells, Affine(2.0, 0, 500000.0, 0, -2.0, 4_000_000.0))
    rgb, f = display_rgb(cells)
    assert f == 3 and rgb.shape == (1000, 1334, 3) and (rgb[:, 667] == 64).all()
    begin = time.perf_counter()
    plot = F.routes_on_grid(grid, {"a": np.array([[500010.0, 3994000], [507990, 3994000]])},
                            (500010, 3994000), (507990, 3994000), "big")  # fmt: skip
    seconds = time.perf_counter() - begin
    print(f"routes_on_grid on 3000 x 4000 cells: {seconds:.2f} s, {len(plot.png)} bytes")
    # the route's box padded by 638.4 m, 9256.8 x 1276.8 m, widened to 9256.8 x 2314.2 (aspect
    # 4) and clipped to the chart's 8 km: 8000 x 2314.2 m (aspect 3.457), a map 7.165 - 1.0 =
    # 6.165 in wide, 1.783 in high, with 0.9 in of margins and one legend row, 0.32 in: 3.003 in
    assert pixels(plot.png).shape == (450, 1074, 3)


# --- convergence and box plots ----------------------------------------------------------------


def test_convergence_data_are_the_median_and_quartiles_over_seeds(plots):
    got = rows(plots["convergence"])
    assert got[0] == ["algorithm", "iteration", "median", "q1", "q3"]
    # iteration 1: seeds 3, 1, 2 -> median 2, quartiles 1.5 and 2.5 (linear); iteration 2:
    # 2, 1, 1.5 -> 1.5, 1.25, 1.75; iteration 3: all 1; one seed of astar: its own values
    assert got[1:4] == [["wso", "1", "2.000000", "1.500000", "2.500000"],
                        ["wso", "2", "1.500000", "1.250000", "1.750000"],
                        ["wso", "3", "1.000000", "1.000000", "1.000000"]]  # fmt: skip
    assert got[4:] == [["astar", str(i), v, v, v] for i, v in
                       ((1, "4.000000"), (2, "4.000000"), (3, "2.000000"))]  # fmt: skip
    img = pixels(plots["convergence"].png)
    assert all(near(img, hex_rgb(style(m).color), 30) > 300 for m in ("wso", "astar"))


def test_boxplot_data_are_every_value_by_metric_and_algorithm(plots):
    got = rows(plots["boxplots"])
    assert got[0] == ["metric", "algorithm", "seed_index", "value"]
    assert [r[:3] for r in got[1:]] == [
        ["length (m)", "wso", "0"], ["length (m)", "wso", "1"], ["length (m)", "wso", "2"],
        ["length (m)", "astar", "0"], ["length (m)", "astar", "1"],
        ["turns", "wso", "0"], ["turns", "wso", "1"], ["turns", "astar", "0"],
        ["turns", "astar", "1"]]  # fmt: skip
    assert [r[3] for r in got[1:6]] == ["1.000000", "2.000000", "3.000000", "2.000000",
                                        "4.000000"]  # fmt: skip


# --- encounter snapshots ----------------------------------------------------------------------


def test_snapshot_data_are_each_ship_as_drawn_with_its_domain_axes(plots):
    got = rows(plots["snapshots"])
    assert got[0] == ["state", "t", "ship", "x", "y", "heading", "domain_length_m",
                      "domain_width_m"]  # fmt: skip
    # own ship (10 m): 7 L x 3 L = 70 x 30; target (5 m): 35 x 15; at t = 5 s the own ship is
    # at (50, 0) heading east, the target at (60, 50) heading south
    assert got[3:5] == [["meeting", "5.000", "own", "50.000", "0.000", "90.000", "70.000",
                         "30.000"],
                        ["meeting", "5.000", "target", "60.000", "50.000", "180.000", "35.000",
                         "15.000"]]  # fmt: skip
    assert [r[0] for r in got[1:]] == ["preparatory"] * 2 + ["meeting"] * 2 + ["completion"] * 2


def test_snapshots_show_both_ships_and_the_grid(plots):
    img = pixels(plots["snapshots"].png)
    for look in ship_styles(["own", "target"]).values():
        assert near(img, hex_rgb(look.color), 40) > 100
    assert near(img, OBSTACLE_RGB, 3) > 300


@pytest.mark.parametrize("heading", [90.0, 0.0, 45.0])
def test_the_domain_ellipse_lies_along_the_heading_with_7_by_3_lengths(heading):
    """Drawn on a 400 px square axes over -50..50 m (4 px per metre), the ship (length 10) at
    the origin: its domain's semi-axes are 35 m along the heading and 15 m across. Points 30 m
    ahead and 12 m abeam are inside (tinted), 40 m ahead and 18 m abeam outside (white)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(4, 4), dpi=100)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_axis_off()
    ax.set_xlim(-50, 50)
    ax.set_ylim(-50, 50)
    draw_ship(ax, 0.0, 0.0, heading, 10.0, "#ff0000", hull_length=10.0)
    canvas.draw()
    img = np.asarray(canvas.buffer_rgba())[..., :3]
    ahead = np.array([np.sin(np.radians(heading)), np.cos(np.radians(heading))])  # compass
    abeam = np.array([ahead[1], -ahead[0]])

    def at(p):  # map metres -> the pixel's colour
        return img[int(round((50 - p[1]) * 4)), int(round((p[0] + 50) * 4))].astype(int)

    tinted, white, red = (255, 191, 191), (255, 255, 255), (255, 0, 0)
    for inside in (30 * ahead, -30 * ahead, 12 * abeam, -12 * abeam):
        assert np.abs(at(inside) - tinted).max() <= 3, inside
    for outside in (40 * ahead, -40 * ahead, 18 * abeam, -18 * abeam):
        assert np.abs(at(outside) - white).max() <= 3, outside
    assert np.abs(at(3 * ahead) - red).max() <= 3  # the hull, 10 m long, 3.2 m wide
    assert np.abs(at(4 * abeam) - tinted).max() <= 3  # abeam of the hull: the domain


def test_snapshot_times_come_from_the_encounters():
    trace = two_ship_trace()
    events = {"encounters": [
        {"class": "head-on", "onset_s": 2.0, "cpa_time_s": 6.0, "closest_distance_m": 30.0},
        {"class": "crossing-give-way", "onset_s": 3.0, "cpa_time_s": 8.0,
         "closest_distance_m": 28.3},
        {"class": "none", "onset_s": None, "cpa_time_s": None,
         "closest_distance_m": 1.0}]}  # fmt: skip
    assert F.snapshot_times(trace, events) == {"preparatory": 2.0, "meeting": 8.0,
                                               "completion": 10.0}  # fmt: skip
    # no encounter: the first step, the closest step (t = 8 s, by hand), the last step
    none = {"encounters": [{"class": "none", "closest_distance_m": 28.284}]}
    assert F.snapshot_times(trace, none) == {"preparatory": 0.0, "meeting": 8.0,
                                             "completion": 10.0}  # fmt: skip


def test_snapshots_of_a_real_run_from_its_events(tmp_path):
    """A short simulated head-on: the states come from its events and the snapshots draw."""
    from usvtool.sim.run import simulate
    from usvtool.sim.scenario import read_scenario

    scenario = tmp_path / "s.yaml"
    scenario.write_text("name: s\nsim: {dt: 0.1, duration: 30, goal_tolerance: 5}\n"
                        "own: {start: [0, 0], goal: [0, 200], heading: 0, speed: 4}\n"
                        "targets:\n  - {start: [0, 160], heading: 180, speed: 3, length: 2.5}\n"
                        "controller: {name: dwa}\n")  # fmt: skip
    run = simulate(read_scenario(scenario))
    trace, events = run.trace, json.loads(format_events(run.events))
    times = F.snapshot_times(trace, events)
    latched = [e for e in events["encounters"] if e["class"] != "none"]
    assert times["preparatory"] == min(e["onset_s"] for e in latched)
    assert times["completion"] == float(trace.t[-1])
    # the meeting is the closest approach of all: the trace's distance there is the smallest
    # minimum distance of the encounters
    i = int(np.flatnonzero(np.isclose(trace.t, times["meeting"]))[0])
    d = np.hypot(trace.x[i, 1] - trace.x[i, 0], trace.y[i, 1] - trace.y[i, 0])
    assert abs(d - min(e["closest_distance_m"] for e in latched)) < 1e-3
    plot = F.encounter_snapshots(trace, times, {s: 2.5 for s in trace.ships})
    assert len(rows(plot)) == 1 + 3 * 2


# --- runs against time and over the wind ------------------------------------------------------


def test_states_data_are_the_own_ship_with_the_heading_unwrapped():
    t = np.arange(4.0)
    states = [[[0, 0, 350, 1, 0]], [[1, 1, 5, 1, 0]], [[2, 2, 20, 1, 0]], [[3, 3, 340, 1, 0]]]
    plot = F.states_against_time(Trace.from_states(t, ["own"], states))
    # 350 -> 5 is a 15 degree turn to starboard, 20 -> 340 a 40 degree turn to port
    assert rows(plot) == [["t", "x", "y", "heading_unwrapped"],
                          ["0.000", "0.000", "0.000", "350.000"],
                          ["1.000", "1.000", "1.000", "365.000"],
                          ["2.000", "2.000", "2.000", "380.000"],
                          ["3.000", "3.000", "3.000", "340.000"]]  # fmt: skip
    assert near(pixels(plot.png), hex_rgb(style("own").color), 40) > 300


def test_nearest_distance_data_are_the_hand_computed_distances(plots):
    got = rows(plots["nearest"])
    assert got[0] == ["controller", "t", "distance_m"]
    assert got[1] == ["ccdwa", "0.000", "116.619"]  # sqrt(60^2 + 100^2)
    assert got[9] == ["ccdwa", "8.000", "28.284"]  # sqrt(20^2 + 20^2), the minimum
    assert got[12] == ["udwa", "0.000", "115.763"]  # own ship 1 m north: sqrt(60^2 + 99^2)
    assert len(got) == 1 + 2 * 11
    img = pixels(plots["nearest"].png)
    assert all(near(img, hex_rgb(style(c).color), 30) > 300 for c in ("ccdwa", "udwa"))


def test_preprocessing_shows_the_chart_and_counts_the_classes(plots):
    assert rows(plots["preprocessing"]) == [["class", "value", "cells", "percent"],
                                            ["navigable", "0", "364", "91.000"],
                                            ["obstacle", "1", "16", "4.000"],
                                            ["safety margin", "2", "20", "5.000"]]  # fmt: skip
    img = pixels(plots["preprocessing"].png)
    assert near(img, (255, 0, 0), 3) > 10_000 and near(img, (0, 0, 255), 3) > 10_000
    # the grid panel's obstacle (~ 10 000 px) is wholly outside the chart: hatched, not dark
    assert near(img, OBSTACLE_RGB, 3) < 2000
    assert near(img, PREVIEW_HATCH[0], 3) > 500
    alone = pixels(F.preprocessing(None, small_grid(), "grid").png)
    assert near(alone, (255, 0, 0), 3) == 0 and near(alone, OBSTACLE_RGB, 3) > 500


# --- bad input --------------------------------------------------------------------------------


@pytest.mark.parametrize("call, message", [
    (lambda: F.routes_on_grid(small_grid(), {"a": [1.0, 2.0]}, (0, 0), (1, 1), ""),
     "route 'a': has shape (2,)"),
    (lambda: F.routes_on_grid(small_grid(), {"a": [[0, 0], [np.nan, 1]]}, (0, 0), (1, 1), ""),
     "route 'a': holds NaN"),
    (lambda: F.convergence({"a": [[1, 2], [1]]}, ""), "'a': the seeds' curves have different"),
    (lambda: F.convergence({"astar": [[]]}, ""), "'astar': no convergence curve"),
    (lambda: F.boxplots({}, ""), "boxplots: no metric"),
    (lambda: F.encounter_snapshots(two_ship_trace(), {"a": 0}, {"own": 2.5}),
     "no length for ship 'target'"),
    (lambda: F.encounter_snapshots(two_ship_trace(), {"late": 11}, {"own": 1, "target": 1}),
     "time of 'late', 11 s, is outside the trace (0 to 10 s)"),
    (lambda: F.snapshot_times(two_ship_trace(), {"steps": []}), "no 'encounters' list"),
    (lambda: F.nearest_distance({"a": Trace.from_states([0], ["own"], [[[0, 0, 0, 1, 0]]])},
                                ""), "no ship but the own ship"),  # fmt: skip
])  # fmt: skip
def test_bad_input_is_one_line_naming_the_argument(call, message):
    with pytest.raises(UsvError) as info:
        call()
    assert message in str(info.value) and "\n" not in str(info.value)
