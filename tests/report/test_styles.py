"""The style registry (usvtool/report/figures/styles.py): every registered method distinct and
colour-blind safe by construction, the 15 planning methods in three families, the same style for
a method whatever its place in a figure, a deterministic fallback that never looks registered,
and font sizes that print at >= 7 pt at the report's width."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import matplotlib.colors as mcolors
import pytest

from usvtool.report.figures import styles as S

ROOT = Path(__file__).resolve().parents[2]
PLANNERS = ("wso", "iwso", "ssa", "issa", "pso", "pso-issa", "gwo", "woa", "mrfo", "boa",
            "iwso+s", "iwso+g", "ssa-redraw", "anyangle", "astar")  # fmt: skip
CONTROLLERS = ("dwa", "gdwa", "ccdwa", "udwa", "udwa+")
#: Okabe-Ito (2008) and Paul Tol's bright, muted, vibrant and light schemes (2021), by hand.
SAFE = {"#000000", "#E69F00", "#56B4E9", "#009E73", "#F0E442", "#0072B2", "#D55E00", "#CC79A7",
        "#4477AA", "#EE6677", "#228833", "#CCBB44", "#66CCEE", "#AA3377", "#BBBBBB",
        "#332288", "#88CCEE", "#44AA99", "#117733", "#999933", "#DDCC77", "#CC6677", "#882255",
        "#AA4499", "#0077BB", "#33BBEE", "#009988", "#EE7733", "#CC3311", "#EE3377",
        "#77AADD", "#EE8866", "#EEDD88", "#FFAABB", "#99DDFF", "#44BB99", "#BBCC33",
        "#AAAA00"}  # fmt: skip


def key(s: S.Style) -> tuple:
    return (s.color, str(s.linestyle), s.marker)


def test_every_registered_method_has_a_style_of_its_own():
    assert set(PLANNERS + CONTROLLERS + ("own", "target1")) <= set(S.REGISTRY)
    keys = [key(s) for s in S.REGISTRY.values()]
    assert len(set(keys)) == len(keys)
    # within the figures they share, no two methods even share a colour
    for group in (PLANNERS, CONTROLLERS, ("own", *(f"target{k}" for k in range(1, 7)))):
        colours = [S.style(m).color for m in group]
        assert len(set(colours)) == len(group), group


def test_every_built_in_method_of_the_registries_has_a_style_of_its_own():
    """The hand-written list drifted once (ssa-redraw, registered, was drawn in the fallback
    style of an unknown method): every optimizer (with the +s and +g variants the report
    shows), exact planner and controller usvtool ships is in it."""
    from usvtool.plan.optimizers import OPTIMIZERS
    from usvtool.plan.planners import EXACT
    from usvtool.registry import BUILT_IN
    from usvtool.sim.controllers import CONTROLLERS

    shipped = {name for registry in (OPTIMIZERS, CONTROLLERS) for name in registry
               if registry.origin(name)[0] == BUILT_IN}  # fmt: skip
    shipped.discard("exec")  # a program's runs are named by its label, drawn as a plugin's
    assert shipped | set(EXACT) | {"iwso+s", "iwso+g"} <= set(S.REGISTRY)


def test_every_colour_is_of_a_colour_blind_safe_palette():
    assert {s.color for s in S.REGISTRY.values()} | set(S.FALLBACK_COLOURS) <= SAFE


def test_the_planners_are_three_families_told_apart_by_line_and_marker():
    families = {m: S.style(m).family for m in PLANNERS}
    assert [m for m in PLANNERS if families[m] == "paper optimizer"] == list(PLANNERS[:10])
    assert [m for m in PLANNERS if families[m] == "our variant"] == ["iwso+s", "iwso+g",
                                                                      "ssa-redraw"]  # fmt: skip
    assert [m for m in PLANNERS if families[m] == "exact planner"] == ["anyangle", "astar"]
    looks = {f: {(str(S.style(m).linestyle), S.style(m).marker) for m in PLANNERS
                 if families[m] == f} for f in set(families.values())}  # fmt: skip
    assert all(len(v) == 1 for v in looks.values())  # one look a family
    assert len(set().union(*looks.values())) == 3  # three looks


@pytest.mark.slow  # a fresh interpreter
def test_the_fallback_is_deterministic_here_and_in_a_fresh_process():
    new = S.style("my-new-optimizer")
    assert new == S.style("my-new-optimizer")
    assert new.family == S.FALLBACK_FAMILY and new.label == "my-new-optimizer"
    code = ("from usvtool.report.figures.styles import style; s = style('my-new-optimizer'); "
            "print(s.color, s.marker)")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env={"PYTHONHASHSEED": "123"}).stdout.split()  # fmt: skip
    assert out == [new.color, new.marker]


def test_the_fallback_never_looks_like_a_registered_method():
    registered = {key(s) for s in S.REGISTRY.values()}
    colours = {s.color for s in S.REGISTRY.values()}
    markers = {s.marker for s in S.REGISTRY.values()}
    names = [f"method-{i}" for i in range(200)]
    fallbacks = [S.style(n) for n in names]
    assert not {key(s) for s in fallbacks} & registered
    assert not {s.color for s in fallbacks} & colours
    assert not {s.marker for s in fallbacks} & markers
    # the name decides: 200 names spread over several colours and markers
    assert len({s.color for s in fallbacks}) == len(S.FALLBACK_COLOURS)
    assert len({s.marker for s in fallbacks}) == len(S.FALLBACK_MARKERS)


def test_every_style_draws_in_matplotlib():
    import matplotlib.lines as mlines

    for s in [*S.REGISTRY.values(), S.style("zzz")]:
        assert mcolors.is_color_like(s.color)
        line = mlines.Line2D([0, 1], [0, 1], linestyle=s.linestyle, marker=s.marker)
        assert line.get_marker() == s.marker


def test_ships_take_the_own_style_then_the_targets_in_order():
    got = S.ship_styles(["own", "blocker", "target"])
    assert got["own"] == S.style("own")
    assert got["blocker"].color == S.style("target1").color and got["blocker"].label == "blocker"
    assert got["target"].color == S.style("target2").color


def test_the_print_width_is_that_of_the_stylesheet():
    css = (ROOT / "templates" / "style.css").read_text(encoding="utf-8")
    page = re.search(r"@page\s*{[^}]*size:\s*A4;\s*margin:\s*(\d+)mm\s+(\d+)mm", css)
    assert page, "templates/style.css: no A4 @page with 'margin: Vmm Hmm'"
    assert S.PRINT_WIDTH_IN == pytest.approx((210 - 2 * int(page.group(2))) / 25.4)
    assert re.search(r"figure img\s*{[^}]*max-width:\s*100%", css)


@pytest.mark.parametrize("width", [3.0, 4.7, 7.0, 9.6, 12.9])
def test_every_font_prints_at_least_7_pt(width):
    assert S.DPI >= 150 and S.MIN_FONT_PT >= 7
    rc = S.rc_params(width)
    printed = min(width * S.DPI / 96, (210 - 28) / 25.4)  # inches on the page, by hand
    sizes = [v for k, v in rc.items() if "size" in k]
    assert len(sizes) == len(S.PRINTED_PT)
    assert min(sizes) * printed / width >= S.MIN_FONT_PT - 0.01
    assert rc["savefig.dpi"] == S.DPI
