"""The frames of a GIF or MP4: a scene drawn with Matplotlib at fixed times, as RGB arrays.

One figure of ``width x height`` pixels at :data:`DPI` (Agg, Matplotlib's defaults and the
DejaVu font it ships: the same scene gives the same pixels in any process). The still parts
(the map, the route, the goal, the timeline with its verdict events and the distance to the
nearest ship) are drawn once; each frame restores them and draws the moving parts over them
(blitting): the wakes (one line collection), the hulls (one polygon collection, every ship's
outline computed at once with NumPy), the own ship's domain and the timeline's cursor. Then
Pillow writes the texts that change on the frame, in Matplotlib's own DejaVu fonts: the class
labels (one text per target in a class: the one loop over ships in a frame) and the clock with
the distance to the nearest ship. A Matplotlib text took 5-7 ms a frame to draw, most of a
frame's time.

What is drawn (docs/animate.md): every ship's hull outline to scale along her heading, at
least :data:`HULL_MIN_PX` pixels long; her wake, the last ``wake`` seconds of her track; the own
ship's domain ellipse (:func:`usvtool.encounter.domain_semi_axes`); the route (dashed) and the
goal (a star in its tolerance circle); the grid (or the chart's preview) beneath.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

from usvtool.encounter import CLASS_NAMES
from usvtool.report.animation.scene import MARK_KINDS, Scene

DPI = 100
#: The hull outline, bow toward +x, two units long (the report's snapshots' hull).
HULL = np.array([(1.0, 0.0), (0.3, 0.32), (-1.0, 0.32), (-1.0, -0.32), (0.3, -0.32)])
#: A hull shorter than this on screen is drawn this long (a 2.5 m boat on a 2 km view).
HULL_MIN_PX = 9.0
#: Wakes are drawn through at most this many points of the track.
WAKE_POINTS = 60
#: Height of the timeline strip, pixels.
TIMELINE_PX = 78
OWN_COLOUR = "#0072B2"
TARGET_COLOURS = ("#D55E00", "#AA3377", "#CCBB44", "#66CCEE", "#BBBBBB", "#228833", "#77AADD",
                  "#EE8866", "#EEDD88", "#FFAABB", "#99DDFF", "#44BB99", "#BBCC33", "#AAAA00")
#: Verdict events: colour and marker on the timeline (a Rule 2 departure is a span).
MARK_STYLE = {"onset": ("#E69F00", "v"), "manoeuvre": ("#0072B2", "D"),
              "release": ("#009E73", "^"), "rule2": ("#CC79A7", "s"),
              "collision": ("#D00000", "X")}  # fmt: skip
MAP_RGB = {0: (214, 234, 242), 1: (201, 185, 122), 2: (232, 221, 180)}


def ship_colours(k: int) -> list[str]:
    """The own ship blue, the targets in :data:`TARGET_COLOURS`' order, round again past it."""
    return [OWN_COLOUR] + [TARGET_COLOURS[i % len(TARGET_COLOURS)] for i in range(k - 1)]


def drawn_colours(k: int) -> list[str]:
    """The colours the frames of ``k`` ships draw in (``#rrggbb``): ships, verdict events, the
    map, the goal."""
    rgb = ["#{:02x}{:02x}{:02x}".format(*MAP_RGB[v]) for v in sorted(MAP_RGB)]
    return [*ship_colours(min(k, 1 + len(TARGET_COLOURS))),
            *(c for c, _ in MARK_STYLE.values()), *rgb, "#ffd700", "#595959",
            MAP_BACKGROUND.lower()]  # fmt: skip


def frame_times(scene: Scene, speed: float, fps: float) -> np.ndarray:
    """The frames' times: from the first step, ``speed / fps`` s of the run apart, and the
    last step."""
    t0, t1 = float(scene.trace.t[0]), float(scene.trace.t[-1])
    step = speed / fps
    n = int(np.floor((t1 - t0) / step + 1e-9)) + 1
    times = t0 + step * np.arange(n)
    return times if times[-1] >= t1 - 1e-9 else np.append(times, t1)


def states_at(scene: Scene, times: np.ndarray):
    """Positions ``(f, k)`` x and y, headings ``(f, k)`` and the step at or before each time
    ``(f,)``: linear between steps, the heading along the shorter arc."""
    tr = scene.trace
    i = np.clip(np.searchsorted(tr.t, times, side="right") - 1, 0, max(tr.n_steps - 2, 0))
    if tr.n_steps == 1:
        return tr.x[i], tr.y[i], tr.heading[i], i
    f = np.clip((times - tr.t[i]) / (tr.t[i + 1] - tr.t[i]), 0.0, 1.0)[:, None]
    x = tr.x[i] + f * (tr.x[i + 1] - tr.x[i])
    y = tr.y[i] + f * (tr.y[i + 1] - tr.y[i])
    turn = (tr.heading[i + 1] - tr.heading[i] + 180.0) % 360.0 - 180.0
    h = (tr.heading[i] + f * turn) % 360.0
    step = np.where(f[:, 0] >= 1.0, i + 1, i)
    return x, y, h, step


def hulls(x, y, heading, lengths) -> np.ndarray:
    """The hull outlines ``(k, 5, 2)`` of ships at ``x, y`` (k,) on compass ``heading`` (k,),
    ``lengths`` (k,) long."""
    a = np.radians(90.0 - np.asarray(heading, float))  # counter-clockwise from east
    c, s = np.cos(a), np.sin(a)
    half = np.asarray(lengths, float) / 2
    hx, hy = HULL[:, 0][None, :] * half[:, None], HULL[:, 1][None, :] * half[:, None]
    px = x[:, None] + hx * c[:, None] - hy * s[:, None]
    py = y[:, None] + hx * s[:, None] + hy * c[:, None]
    return np.stack([px, py], axis=-1)


def fit_view(view, width: float, height: float):
    """``view`` (left, bottom, right, top) widened about its centre to the aspect of a
    ``width x height`` pixel area."""
    left, bottom, right, top = view
    w, h = right - left, top - bottom
    scale = max(w / width, h / height)
    cx, cy = (left + right) / 2, (bottom + top) / 2
    return cx - scale * width / 2, cy - scale * height / 2, cx + scale * width / 2, \
        cy + scale * height / 2  # fmt: skip


@contextmanager
def _figure(width: int, height: int):
    import matplotlib as mpl
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    with mpl.rc_context():
        mpl.rcdefaults()
        mpl.rcParams.update({"font.size": 8, "axes.linewidth": 0.6, "path.simplify": False})
        fig = Figure(figsize=(width / DPI, height / DPI), dpi=DPI, facecolor="white")
        FigureCanvasAgg(fig)
        yield fig


def render(scene: Scene, width: int, height: int, times: np.ndarray,
           wake: float) -> Iterator[np.ndarray]:
    """The frames at ``times``, each an ``(height, width, 3)`` uint8 array (module docstring)."""
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.patches import Circle, Ellipse

    tr = scene.trace
    k = len(tr.ships)
    colours = ship_colours(k)
    xs, ys, hs, steps = states_at(scene, times)
    timeline = min(TIMELINE_PX, height // 3)
    map_h = height - timeline
    view = fit_view(scene.view, width, map_h)
    metres_per_px = (view[2] - view[0]) / width
    hull_lengths = np.maximum(scene.lengths, HULL_MIN_PX * metres_per_px)
    wake_steps = _wake_steps(tr.t, wake)
    with _figure(width, height) as fig:
        ax = fig.add_axes((0, timeline / height, 1, map_h / height))
        ax.set_axis_off()
        ax.set_xlim(view[0], view[2])
        ax.set_ylim(view[1], view[3])
        ax.add_patch(_frame_patch(ax))
        _draw_map(ax, scene, view)
        _draw_scale(ax, view, metres_per_px)
        if scene.route is not None:
            ax.plot(scene.route[:, 0], scene.route[:, 1], color="0.35", lw=0.9, ls=(0, (4, 3)),
                    zorder=1)  # fmt: skip
        if scene.goal is not None:
            if scene.goal_tolerance > 0:
                ax.add_patch(Circle(scene.goal, scene.goal_tolerance, fill=False, ec="0.2",
                                    lw=0.6, zorder=1))  # fmt: skip
            ax.plot(*scene.goal, marker="*", ms=11, color="gold", mec="black", mew=0.6,
                    zorder=1.5)  # fmt: skip
        if scene.title:
            ax.text(0.01, 0.985, scene.title, transform=ax.transAxes, va="top", fontsize=9,
                    parse_math=False, bbox={"fc": "white", "ec": "none", "alpha": 0.75,
                                            "pad": 2})  # a name's $ is no mathtext  # fmt: skip
        left = 62 / width  # room for the kinds' names
        tl = fig.add_axes((left, 0.3 * timeline / height, 0.985 - left, 0.62 * timeline / height))
        _draw_timeline(tl, scene)

        wakes = LineCollection([], colors=colours, linewidths=1.2, zorder=2, animated=True)
        ax.add_collection(wakes)
        domain = Ellipse((0, 0), 2 * scene.domain[0], 2 * scene.domain[1], fill=True,
                         fc=OWN_COLOUR, alpha=0.15, ec=OWN_COLOUR, ls="--", lw=0.8, zorder=2.5,
                         animated=True)  # fmt: skip
        ax.add_patch(domain)
        ships = PolyCollection([], facecolors=colours, edgecolors="black", linewidths=0.5,
                               zorder=3, animated=True)  # fmt: skip
        ax.add_collection(ships)
        cursor = tl.axvline(tr.t[0], color="black", lw=1.2, animated=True)
        dynamic = [(ax, wakes), (ax, domain), (ax, ships), (tl, cursor)]
        canvas = fig.canvas
        canvas.draw()
        background = canvas.copy_from_bbox(fig.bbox)
        fonts = _fonts()
        names = [str(n) for n in tr.ships]
        for f, t in enumerate(times.tolist()):
            i = int(steps[f])
            x, y, h = xs[f], ys[f], hs[f]
            lo = max(0, i - wake_steps)
            idx = np.unique(np.linspace(lo, i, min(WAKE_POINTS, i - lo + 1)).astype(int))
            trail = np.concatenate([np.stack([tr.x[idx].T, tr.y[idx].T], -1),
                                    np.stack([x, y], -1)[:, None]], axis=1)  # fmt: skip
            wakes.set_segments(trail)
            ships.set_verts(hulls(x, y, h, hull_lengths))
            domain.set_center((x[0], y[0]))
            domain.set_angle(90.0 - h[0])
            cursor.set_xdata([t, t])
            canvas.restore_region(background)
            for owner, artist in dynamic:
                owner.draw_artist(artist)
            rgb = np.asarray(canvas.buffer_rgba())[..., :3].copy()
            text = f"t {t - tr.t[0]:7.1f} s"
            if scene.nearest is not None:
                text += f"\nnearest {scene.nearest[i]:7.1f} m"
            shown = np.flatnonzero(scene.classes[i])  # the targets in a class
            at = ax.transData.transform(np.stack([x[shown] + hull_lengths[shown] / 2,
                                                  y[shown]], -1))  # fmt: skip
            labels = [(float(px) + LABEL_GAP_PX, height - float(py) - LABEL_GAP_PX,
                       f"{names[j]}: {CLASS_NAMES[scene.classes[i, j]]}"
                       if scene.latched[i, j] else CLASS_NAMES[scene.classes[i, j]],
                       bool(scene.latched[i, j]))
                      for j, (px, py) in zip(shown.tolist(), at, strict=True)]  # fmt: skip
            yield _write(rgb, labels, text, fonts, (width, map_h))


#: Labels start this many pixels right of and above the bow's abeam point.
LABEL_GAP_PX = 3


def _fonts():
    """The labels' fonts (regular, bold) and the clock's: Matplotlib's own DejaVu files, drawn by
    Pillow (a Matplotlib text costs 5-7 ms a frame to draw; Pillow's well under one)."""
    from pathlib import Path

    import matplotlib as mpl
    from PIL import ImageFont

    ttf = Path(mpl.get_data_path()) / "fonts" / "ttf"
    return (ImageFont.truetype(str(ttf / "DejaVuSans.ttf"), 10),
            ImageFont.truetype(str(ttf / "DejaVuSans-Bold.ttf"), 10),
            ImageFont.truetype(str(ttf / "DejaVuSansMono.ttf"), 13))  # fmt: skip


def _write(rgb: np.ndarray, labels, clock: str, fonts, area) -> np.ndarray:
    """``rgb`` with the class labels (x, y from the top left, text, bold) outlined in white, and
    the clock boxed at the bottom right of the map ``area`` (width, height) pixels."""
    from PIL import Image, ImageDraw

    image = Image.fromarray(rgb)
    draw = ImageDraw.Draw(image)
    width, height = area
    for x, y, text, bold in labels:
        if 0 <= x < width and 0 <= y < height:
            draw.text((x, y), text, font=fonts[bold], fill=(0, 0, 0), anchor="ld",
                      stroke_width=2, stroke_fill=(255, 255, 255))  # fmt: skip
    box = draw.multiline_textbbox((0, 0), clock, font=fonts[2], spacing=2)
    w, h = box[2] - box[0], box[3] - box[1]
    x0, y0 = width - w - 14, height - h - 12
    draw.rectangle((x0 - 4, y0 - 4, x0 + w + 4, y0 + h + 5), fill=(255, 255, 255),
                   outline=(128, 128, 128))  # fmt: skip
    draw.multiline_text((x0 - box[0], y0 - box[1]), clock, font=fonts[2], fill=(0, 0, 0),
                        spacing=2)  # fmt: skip
    return np.asarray(image)


def _wake_steps(t: np.ndarray, wake: float) -> int:
    if t.size < 2:
        return 0
    return int(round(wake / float(np.median(np.diff(t)))))


def _frame_patch(ax):
    from matplotlib.patches import Rectangle

    return Rectangle((0, 0), 1, 1, transform=ax.transAxes, fc=MAP_BACKGROUND, ec="none",
                     zorder=-1)  # fmt: skip


MAP_BACKGROUND = "#F4F4F4"


def map_rgb(cells: np.ndarray) -> np.ndarray:
    """The grid's cells as RGB (:data:`MAP_RGB`: water, obstacle, margin)."""
    lut = np.zeros((256, 3), np.uint8)
    for value, rgb in MAP_RGB.items():
        lut[value] = rgb
    return lut[cells]


def _draw_map(ax, scene: Scene, view) -> None:
    if scene.chart is not None:
        from usvtool.report.figures.raster import draw_chart

        draw_chart(ax, scene.chart, (view[0], view[1], view[2], view[3]))
        return
    if scene.grid is None:
        ax.add_patch(_water(ax))
        return
    g = scene.grid
    s, (gl, _, _, gt) = g.cell_size, g.bounds
    c0, c1 = max(0, int((view[0] - gl) // s)), min(g.width, int(-((gl - view[2]) // s)))
    r0, r1 = max(0, int((gt - view[3]) // s)), min(g.height, int(-((view[1] - gt) // s)))
    if c0 >= c1 or r0 >= r1:
        return
    extent = (gl + c0 * s, gl + c1 * s, gt - r1 * s, gt - r0 * s)
    ax.imshow(map_rgb(g.cells[r0:r1, c0:c1]), extent=extent, origin="upper",
              interpolation="nearest", zorder=0)  # fmt: skip


def _water(ax):
    from matplotlib.patches import Rectangle

    rgb = np.array(MAP_RGB[0]) / 255
    return Rectangle((0, 0), 1, 1, transform=ax.transAxes, fc=rgb, ec="none", zorder=0)


def _draw_scale(ax, view, metres_per_px: float) -> None:
    """A scale bar of a round length about 1/6 of the view's width, bottom left."""
    span = (view[2] - view[0]) / 6
    unit = 10 ** np.floor(np.log10(span))
    length = max(u * unit for u in (1, 2, 5) if u * unit <= span)
    x0 = view[0] + 12 * metres_per_px
    y0 = view[1] + 12 * metres_per_px
    ax.plot([x0, x0 + length], [y0, y0], color="black", lw=2, solid_capstyle="butt", zorder=5)
    text = f"{length / 1000:g} km" if length >= 1000 else f"{length:g} m"
    ax.text(x0 + length / 2, y0 + 4 * metres_per_px, text, ha="center", va="bottom",
            fontsize=7, zorder=5)  # fmt: skip


def _draw_timeline(tl, scene: Scene) -> None:
    """The verdict events on the run's time axis (one row per kind), the distance to the
    nearest ship behind them (grey, its own scale)."""
    t = scene.trace.t
    tl.set_xlim(t[0], max(t[-1], t[0] + 1e-3))
    tl.set_ylim(-0.6, len(MARK_KINDS) - 0.4)
    tl.set_yticks(range(len(MARK_KINDS)), MARK_KINDS, fontsize=6)
    tl.tick_params(axis="x", labelsize=7, pad=1, length=2)
    tl.tick_params(axis="y", length=0, pad=1)
    tl.set_xlabel("")
    tl.grid(False)
    for spine in ("top", "right"):
        tl.spines[spine].set_visible(False)
    if scene.nearest is not None and len(t) > 1:
        d = scene.nearest
        top = float(d.max()) or 1.0
        tl.fill_between(t, -0.6, -0.6 + (len(MARK_KINDS) - 0.2) * d / top, color="0.88", lw=0,
                        zorder=0)  # fmt: skip
    by_kind: dict[str, list] = {k: [] for k in MARK_KINDS}
    for m in scene.marks:
        by_kind[m.kind].append(m)
    for row, kind in enumerate(MARK_KINDS):
        colour, marker = MARK_STYLE[kind]
        marks = by_kind[kind]
        if not marks:
            continue
        if kind == "rule2":
            for m in marks:
                tl.plot([m.t, max(m.end, m.t + 0.05)], [row, row], color=colour, lw=5,
                        solid_capstyle="butt", zorder=2)  # fmt: skip
        else:
            tl.plot([m.t for m in marks], [row] * len(marks), ls="none", marker=marker,
                    color=colour, mec="black", mew=0.4, ms=6, zorder=2)  # fmt: skip
