"""The style registry (usvtool/report/figures/styles.py): every registered method distinct and
colour-blind safe by construction, the 15 planning methods in three families, the same style for
a method whatever its place in a figure, a style of its own for every other method of the
registries' order the report is given (a plugin's, and their variants), a deterministic
fallback that never looks registered, and font sizes that print at >= 7 pt at the report's
width."""

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
CONTROLLERS = ("dwa", "gdwa", "ccdwa", "udwa", "udwa+", "vo", "sbmpc")
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
    shipped.discard("policy")  # a trained policy (docs/gym.md), drawn as a plugin's, as exec
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


@pytest.fixture
def order():
    """The order usvtool report passes (the stages' registries) with a plugin's optimizer, exact
    planner and controller in their places; the styles assigned from it, reset afterwards."""
    from usvtool.cli.report import stage_methods

    methods = list(stage_methods())
    cut = methods.index("anyangle")
    methods[cut:cut] = ["wide-pso"]  # a plugin optimizer: after the built-in ones
    methods.insert(methods.index("dwa"), "my-astar")  # a plugin exact planner
    methods.append("slow-dwa")  # a plugin controller
    S.assign(methods)
    yield methods
    S.assign(())


def test_a_method_without_a_hand_chosen_style_gets_one_of_its_own_from_the_order(order):
    """No hand-written list to keep up: every method of the registries (a plugin's, exec) and
    every optimizer's +s and +g has a style, distinct from every other and from the ships'."""
    optimizers = order[:order.index("anyangle")]
    names = [*order, *(f"{m}{v}" for m in optimizers for v in ("+s", "+g"))]
    looks = {m: key(S.style(m)) for m in names}
    ships = {key(S.style(f"target{k}")) for k in range(1, 7)} | {key(S.style("own"))}
    assert len(set(looks.values())) == len(names) and not set(looks.values()) & ships
    for m in ("wide-pso", "my-astar", "slow-dwa", "exec"):
        s = S.style(m)
        assert (s.family, s.label, s.linestyle) == (S.ASSIGNED_FAMILY, m, "-")
        assert s.color in S.FALLBACK_COLOURS and s.marker in S.FALLBACK_MARKERS
    # a plugin optimizer's variants: its colour and marker, a line of the variant's own
    plain, short, guided = map(S.style, ("wide-pso", "wide-pso+s", "wide-pso+g"))
    assert plain.color == short.color == guided.color and plain.marker == guided.marker
    assert (short.linestyle, guided.linestyle) == (S.VARIANT_LINES["+s"], S.VARIANT_LINES["+g"])
    assert S.ordered(["slow-dwa", "wide-pso+g", "dwa", "wide-pso", "iwso"]) == [
        "iwso", "dwa", "wide-pso", "wide-pso+g", "slow-dwa"]  # fmt: skip
    before = {m: S.style(m) for m in order}
    S.assign(list(order))  # the same order: the same styles
    assert {m: S.style(m) for m in order} == before


def test_48_methods_of_the_order_are_told_apart_and_the_others_fall_back():
    names = [f"plugin-{i}" for i in range(48)]
    try:
        S.assign(["iwso", *names, "dwa"])
        looks = [key(S.style(m)) for m in names]
        assert len(set(looks)) == 48 and not set(looks) & {key(s) for s in S.REGISTRY.values()}
        assert [S.style(m).color for m in names[:8]] == list(S.FALLBACK_COLOURS)  # by place
        stranger = S.style("a-label-of-exec")  # not of the order: the name's fallback
        assert stranger.family == S.FALLBACK_FAMILY and key(stranger) not in looks
    finally:
        S.assign(())
    assert S.style("plugin-0").family == S.FALLBACK_FAMILY  # dropped with the order


def test_make_report_styles_the_methods_of_the_order_it_is_given(monkeypatch, tmp_path):
    """ReportOptions.order (usvtool report gives the registries') decides the styles before
    any figure is drawn."""
    from types import SimpleNamespace

    from usvtool.report import build

    seen = {}

    class Drawn(Exception):
        pass

    def sections(results, workers):
        seen.update({m: S.style(m) for m in ("wide-pso", "slow-dwa")})
        raise Drawn

    monkeypatch.setattr(build, "load", lambda tables, order: SimpleNamespace(missing=[]))
    monkeypatch.setattr(build.evidence, "check", lambda results, allow: [])
    monkeypatch.setattr(build, "sections", sections)
    try:
        with pytest.raises(Drawn):
            build.make_report(build.ReportOptions(("metrics.csv",), str(tmp_path / "report"),
                                                  order=("iwso", "wide-pso", "dwa",
                                                         "slow-dwa")))  # fmt: skip
    finally:
        S.assign(())
    assert seen["wide-pso"].family == seen["slow-dwa"].family == S.ASSIGNED_FAMILY
    assert key(seen["wide-pso"]) != key(seen["slow-dwa"])


def test_a_figure_draws_a_plugin_method_in_its_style(order, monkeypatch):
    import matplotlib.axes

    from usvtool.report.figures.statistics import convergence

    drawn = {}
    plot = matplotlib.axes.Axes.plot

    def spy(ax, *args, **kwargs):
        drawn[kwargs.get("label", "").split(" (")[0]] = (kwargs.get("color"),
                                                          kwargs.get("linestyle"),
                                                          kwargs.get("marker"))  # fmt: skip
        return plot(ax, *args, **kwargs)

    monkeypatch.setattr(matplotlib.axes.Axes, "plot", spy)
    curves = {m: [[3.0, 2.0, 1.0], [3.0, 2.5, 1.5]] for m in ("pso", "wide-pso", "wide-pso+s")}
    convergence(curves, "plugins")
    assert drawn == {m: (S.style(m).color, S.style(m).linestyle, S.style(m).marker)
                     for m in curves}  # fmt: skip
    assert len(set(drawn.values())) == 3
