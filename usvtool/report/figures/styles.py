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

A method not in the registry (a user's new optimizer) gets a style derived from its name's
SHA-256: a colour of Tol's *light* scheme and a marker no registered method uses, on a
dash-dot-dot line of its own, so it is the same in every run and never mistaken for a
registered method.

Print size: the report's page (templates/style.css: A4, margins 16 mm x 14 mm) shows a figure
``max-width: 100%`` of the 182 mm text width, and WeasyPrint takes a PNG at 96 px an inch; a
figure ``w`` inches wide at :data:`DPI` prints ``min(w * DPI / 96, 182 mm)`` wide.
:func:`rc_params` sizes the fonts for that print width so that no text is under
:data:`MIN_FONT_PT`.
"""

from __future__ import annotations

import hashlib
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
}
#: The own ship (Okabe-Ito blue, the papers' blue boat) and the other ships in their order
#: (vermillion first, the papers' red obstacle ship).
OWN_SHIP = "#0072B2"
TARGETS = ("#D55E00", "#AA3377", "#CCBB44", "#66CCEE", "#BBBBBB", "#228833")
#: The fallback: Tol's light scheme (no registered colour), markers no registered style uses,
#: and a line style of its own.
FALLBACK_COLOURS = ("#77AADD", "#EE8866", "#EEDD88", "#FFAABB", "#99DDFF", "#44BB99",
                    "#BBCC33", "#AAAA00")  # fmt: skip
FALLBACK_MARKERS = ("<", ">", "h", "p", "8", "H")
FALLBACK_LINESTYLE = (0, (4, 1.5, 1, 1.5, 1, 1.5, 1, 1.5))
FALLBACK_FAMILY = "unregistered"


def _registry() -> dict[str, Style]:
    styles = {name: Style(colour, *FAMILIES[family], family, name)
              for name, (family, colour) in PLANNERS.items()}  # fmt: skip
    styles.update({name: Style(colour, ls, marker, family, name)
                   for name, (family, colour, ls, marker) in CONTROLLERS.items()})  # fmt: skip
    styles["own"] = Style(OWN_SHIP, "-", "^", "ship", "own ship")
    styles.update({f"target{k + 1}": Style(c, "-", "o", "ship", f"target {k + 1}")
                   for k, c in enumerate(TARGETS)})  # fmt: skip
    return styles


#: Every registered method's style, by name.
REGISTRY: dict[str, Style] = _registry()


def style(method: str) -> Style:
    """The style of ``method``: its registered one, else the fallback derived from its name
    (deterministic: the same name gives the same style in every process)."""
    if method in REGISTRY:
        return REGISTRY[method]
    digest = int.from_bytes(hashlib.sha256(method.encode("utf-8")).digest()[:8], "big")
    colour = FALLBACK_COLOURS[digest % len(FALLBACK_COLOURS)]
    marker = FALLBACK_MARKERS[digest // len(FALLBACK_COLOURS) % len(FALLBACK_MARKERS)]
    return Style(colour, FALLBACK_LINESTYLE, marker, FALLBACK_FAMILY, method)


def ordered(methods) -> list[str]:
    """``methods`` in the registry's order (families together: the papers' optimizers, our
    variants, the exact planners, then the controllers), unregistered ones after, as given.

    >>> ordered(["astar", "mine", "iwso+s", "wso"])
    ['wso', 'iwso+s', 'astar', 'mine']
    """
    rank = {name: i for i, name in enumerate(REGISTRY)}
    methods = list(methods)
    return sorted(methods, key=lambda m: (rank.get(m, len(rank)), methods.index(m)))


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
