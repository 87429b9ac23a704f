"""One style per method in every figure, and the print settings every figure is drawn with.

A method's :class:`Style` (colour, line style, marker, family, label) comes from its name alone,
never from its position in a figure, so ``anyangle`` looks the same on every chart. The colours
are colour-blind safe: Paul Tol's *muted* and *vibrant* schemes for the planners and the
Okabe-Ito palette for the controllers and ships (Tol, "Colour Schemes", SRON/EPS/TN/09-002,
2021; Okabe and Ito, "Color Universal Design", 2008). The 15 planning methods are told apart by
family first, in line style and marker (grey print keeps the family), then by colour:

- the papers' optimizers: solid line, circles;
- our variants (of IWSO, and SSA's redraw): dashed, squares;
- the exact planners: dash-dot, diamonds.

These hand-chosen styles are the built-in methods' (:data:`REGISTRY`). Every other method of
the stages' registries (a plugin's optimizer, exact planner or controller; ``exec``) gets one
from the order the report is given (``ReportOptions.order``, the registries' names:
:func:`assign`, which :func:`usvtool.report.build.make_report` calls): the ``k``-th of them
without a hand-chosen style takes colour ``k mod 8`` of Tol's *light* scheme (no hand-chosen
style uses it) and marker ``k div 8`` of six no hand-chosen style uses, on a solid line, so 48
such methods are told apart, and none is mistaken for a built-in one. A variant of a method
(``NAME+s``, ``NAME+g``) without a hand-chosen style takes its method's colour and marker on a
line of the variant's own (:data:`VARIANT_LINES`). A name the order does not hold (a program's
label, a method of a plugin not installed here) gets a style derived from its name's SHA-256:
the same palette on a dash-dot-dot line of its own, the same in every run. The report imports
no other stage: the order is all it knows of the registries.

Print size: the report's page (templates/style.css: A4, margins 16 mm x 14 mm) shows a figure
``max-width: 100%`` of the 182 mm text width, and WeasyPrint takes a PNG at 96 px an inch; a
figure ``w`` inches wide at :data:`DPI` prints ``min(w * DPI / 96, 182 mm)`` wide.
:func:`rc_params` sizes the fonts for that print width so that no text is under
:data:`MIN_FONT_PT`.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass

#: Resolution of every figure's PNG (dots an inch of the figure's size).
DPI = 150
#: The smallest text of a figure, in points at its printed size.
MIN_FONT_PT = 7.0
#: Pixels an inch of CSS (WeasyPrint's ``image-resolution: 1dppx``).
CSS_DPI = 96.0
#: The report's text width, inches: A4 (210 mm) less two 14 mm margins (templates/style.css).
PRINT_WIDTH_IN = (210.0 - 2 * 14.0) / 25.4
#: Printed sizes (pt) of the texts of a figure, each at least :data:`MIN_FONT_PT`.
PRINTED_PT = {"font.size": 8.0, "xtick.labelsize": 7.5, "ytick.labelsize": 7.5,
              "legend.fontsize": 7.5, "legend.title_fontsize": 7.5, "axes.labelsize": 8.0,
              "axes.titlesize": 8.5, "figure.titlesize": 9.0,
              "figure.labelsize": 8.0}  # fmt: skip


@dataclass(frozen=True)
class Style:
    """How one method is drawn: a Matplotlib colour, line style and marker, its family (the
    group its line style and marker show) and its legend label."""

    color: str
    linestyle: str | tuple
    marker: str
    family: str
    label: str

    def line(self) -> dict:
        """Keyword arguments of ``Axes.plot`` for a line in this style (no marker)."""
        return {"color": self.color, "linestyle": self.linestyle}


#: Families: (line style, marker) of each.
FAMILIES = {
    "paper optimizer": ("-", "o"),
    "our variant": ("--", "s"),
    "exact planner": ("-.", "D"),
}
#: Planning methods: family and colour (Tol muted for the papers' ten, Tol vibrant for ours and
#: the exact planners).
PLANNERS = {
    "wso": ("paper optimizer", "#332288"),
    "iwso": ("paper optimizer", "#88CCEE"),
    "ssa": ("paper optimizer", "#44AA99"),
    "issa": ("paper optimizer", "#117733"),
    "pso": ("paper optimizer", "#999933"),
    "pso-issa": ("paper optimizer", "#DDCC77"),
    "gwo": ("paper optimizer", "#CC6677"),
    "woa": ("paper optimizer", "#882255"),
    "mrfo": ("paper optimizer", "#AA4499"),
    "boa": ("paper optimizer", "#000000"),
    "iwso+s": ("our variant", "#EE7733"),
    "iwso+g": ("our variant", "#EE3377"),
    "ssa-redraw": ("our variant", "#009988"),
    "anyangle": ("exact planner", "#CC3311"),
    "astar": ("exact planner", "#0077BB"),
}
#: Controllers (Okabe-Ito): each its own colour, line style and marker, as their tracks overlap.
CONTROLLERS = {
    "dwa": ("controller", "#000000", "-", "X"),
    "gdwa": ("controller", "#E69F00", "--", "s"),
    "ccdwa": ("controller", "#56B4E9", "-.", "D"),
    "udwa": ("controller", "#009E73", ":", "v"),
    "udwa+": ("our controller variant", "#CC79A7", (0, (5, 1.5, 1, 1.5, 1, 1.5)), "P"),
    "vo": ("baseline controller", "#4477AA", (0, (1, 1)), "*"),
    "sbmpc": ("controller", "#EE6677", (0, (3, 1, 1, 1)), "d"),
}
#: The own ship (Okabe-Ito blue, the papers' blue boat) and the other ships in their order
#: (vermillion first, the papers' red obstacle ship).
OWN_SHIP = "#0072B2"
TARGETS = ("#D55E00", "#AA3377", "#CCBB44", "#66CCEE", "#BBBBBB", "#228833")
#: The methods without a hand-chosen style: Tol's light scheme (no hand-chosen colour), markers
#: no hand-chosen style uses; a method of the order on a solid line (:func:`assign`), a name
#: outside it on a line style of its own.
FALLBACK_COLOURS = ("#77AADD", "#EE8866", "#EEDD88", "#FFAABB", "#99DDFF", "#44BB99",
                    "#BBCC33", "#AAAA00")  # fmt: skip
FALLBACK_MARKERS = ("<", ">", "h", "p", "8", "H")
FALLBACK_LINESTYLE = (0, (4, 1.5, 1, 1.5, 1, 1.5, 1, 1.5))
FALLBACK_FAMILY = "unregistered"
ASSIGNED_LINESTYLE = "-"
ASSIGNED_FAMILY = "other method"
#: The line of a variant without a hand-chosen style (its method's colour and marker), by its
#: suffix; another suffix takes :data:`OTHER_VARIANT_LINE`. No hand-chosen style uses them.
VARIANT_LINES = {"+s": (0, (6, 2)), "+g": (0, (1, 1.5))}
OTHER_VARIANT_LINE = (0, (6, 2, 1, 2))


def _registry() -> dict[str, Style]:
    styles = {name: Style(colour, *FAMILIES[family], family, name)
              for name, (family, colour) in PLANNERS.items()}  # fmt: skip
    styles.update({name: Style(colour, ls, marker, family, name)
                   for name, (family, colour, ls, marker) in CONTROLLERS.items()})  # fmt: skip
    styles["own"] = Style(OWN_SHIP, "-", "^", "ship", "own ship")
    styles.update({f"target{k + 1}": Style(c, "-", "o", "ship", f"target {k + 1}")
                   for k, c in enumerate(TARGETS)})  # fmt: skip
    return styles


#: Every hand-chosen style (the built-in methods', the ships'), by name.
REGISTRY: dict[str, Style] = _registry()
#: The styles :func:`assign` gave the methods of the order without a hand-chosen one.
_ASSIGNED: dict[str, Style] = {}


def assign(order: Sequence[str]) -> None:
    """Give each method of ``order`` (the stages' registries' names in their order, as
    ``usvtool report`` passes them) without a hand-chosen style one of its own, by its place
    among those (the module's docstring); the styles assigned before are dropped. Called once a
    report, before its figures (drawn in forked processes, which inherit them).

    >>> assign(["iwso", "mine", "astar", "yours"])
    >>> [(s.color, s.marker) for s in map(style, ["mine", "yours"])]
    [('#77AADD', '<'), ('#EE8866', '<')]
    >>> assign(())
    """
    _ASSIGNED.clear()
    others = [m for m in dict.fromkeys(order) if m not in REGISTRY]
    n = len(FALLBACK_COLOURS)
    for k, method in enumerate(others):
        marker = FALLBACK_MARKERS[k // n % len(FALLBACK_MARKERS)]
        _ASSIGNED[method] = Style(FALLBACK_COLOURS[k % n], ASSIGNED_LINESTYLE, marker,
                                  ASSIGNED_FAMILY, method)  # fmt: skip


def style(method: str) -> Style:
    """The style of ``method``: its hand-chosen one, else the one :func:`assign` gave it, else,
    for a variant ``NAME+x`` of a method with one of those, that method's colour and marker on
    the variant's line, else the fallback derived from its name (deterministic: the same name
    gives the same style in every process)."""
    found = REGISTRY.get(method) or _ASSIGNED.get(method)
    if found is not None:
        return found
    base, plus, suffix = method.rpartition("+")
    inner = (REGISTRY.get(base) or _ASSIGNED.get(base)) if plus and base else None
    if inner is not None:
        line = VARIANT_LINES.get(plus + suffix, OTHER_VARIANT_LINE)
        return Style(inner.color, line, inner.marker, inner.family, method)
    digest = int.from_bytes(hashlib.sha256(method.encode("utf-8")).digest()[:8], "big")
    colour = FALLBACK_COLOURS[digest % len(FALLBACK_COLOURS)]
    marker = FALLBACK_MARKERS[digest // len(FALLBACK_COLOURS) % len(FALLBACK_MARKERS)]
    return Style(colour, FALLBACK_LINESTYLE, marker, FALLBACK_FAMILY, method)


def ordered(methods) -> list[str]:
    """``methods`` in the styles' order (families together: the papers' optimizers, our
    variants, the exact planners, the controllers, then the methods :func:`assign` styled, each
    variant without a style of its own after its method), the others after, as given.

    >>> ordered(["astar", "mine", "iwso+s", "wso", "pso+g", "pso"])
    ['wso', 'pso', 'pso+g', 'iwso+s', 'astar', 'mine']
    """
    rank = {name: i for i, name in enumerate([*REGISTRY, *_ASSIGNED])}
    methods = list(methods)

    def key(m: str) -> tuple:
        if m in rank:
            return (rank[m], "", methods.index(m))
        base, plus, suffix = m.rpartition("+")
        if plus and base in rank:
            return (rank[base], plus + suffix, methods.index(m))
        return (len(rank), "", methods.index(m))

    return sorted(methods, key=key)


def ship_styles(ships) -> dict[str, Style]:
    """Styles of a trace's ships, by name: the own ship (``own``) blue, the others in their order
    ``target1``, ``target2``, … (their label their own name), the fallback past the last."""
    out, k = {}, 0
    for ship in ships:
        if ship == "own":
            out[ship] = REGISTRY["own"]
        else:
            k += 1
            base = style(f"target{k}")
            out[ship] = Style(base.color, base.linestyle, base.marker, base.family, ship)
    return out


def printed_width(width_in: float) -> float:
    """Inches a figure ``width_in`` wide at :data:`DPI` prints at in the report's page.

    >>> round(printed_width(9.6), 3), round(printed_width(3.2), 3)
    (7.165, 5.0)
    """
    return min(width_in * DPI / CSS_DPI, PRINT_WIDTH_IN)


def rc_params(width_in: float) -> dict:
    """Matplotlib rc settings of a figure ``width_in`` wide: :data:`DPI`, and the font sizes of
    :data:`PRINTED_PT` scaled by ``width_in / printed_width`` so that they print at those
    sizes (a 9.6 in figure prints at 7.165 in: its 7.5 pt ticks are set at 10.05 pt)."""
    scale = width_in / printed_width(width_in)
    rc = {key: round(pt * scale, 2) for key, pt in PRINTED_PT.items()}
    rc.update({"figure.dpi": DPI, "savefig.dpi": DPI, "font.family": "DejaVu Sans"})
    return rc


def apply_rc(width_in: float) -> None:
    """Set :func:`rc_params` of a figure ``width_in`` wide in Matplotlib's current rcParams
    (inside an ``rc_context``, so that they are restored)."""
    import matplotlib as mpl

    mpl.rcParams.update(rc_params(width_in))
