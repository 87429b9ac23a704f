"""The Imazu problem's case x controller grid: one cell per run, coloured by its outcome, with
its closest distance to a target and its compliant encounters of all written in it
(docs/report-imazu.md).

The outcome is the worst that befell the run, in the order of :data:`OUTCOMES`: it collided,
did not arrive (both failures, hatched so that grey print keeps them apart), or arrived with a
non-compliant encounter, with an encounter left without a verdict, with one compliant only
through an excused Rule 2 departure, or with every encounter compliant. Colours: Paul Tol's
*light* scheme and his vermillion (colour-blind safe; Tol, "Colour Schemes", 2021).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from usvtool.errors import UsvError
from usvtool.report.figures.canvas import Plot, csv_text, figure, fixed, png
from usvtool.report.figures.styles import MIN_FONT_PT, printed_width

#: Outcomes, worst first: (name, legend label, face colour, hatch, text colour).
OUTCOMES = (
    ("collided", "collided", "#CC3311", "xxx", "white"),
    ("not-arrived", "did not arrive (a failure)", "#EE8866", "///", "black"),
    ("noncompliant", "arrived, a rule failed", "#EEDD88", "", "black"),
    ("not-judged", "arrived, an encounter without verdict", "#DDDDDD", "", "black"),
    ("excused", "arrived, compliant through an excused Rule 2 departure", "#BBCC33", "", "black"),
    ("compliant", "arrived, every encounter compliant", "#44BB99", "", "black"),
)
OUTCOME_NAMES = tuple(o[0] for o in OUTCOMES)
#: The figure's width (inches): it prints at the report's full text width.
WIDTH = 7.2
#: Inches per case row.
ROW = 0.22


@dataclass(frozen=True)
class Cell:
    """One run of the grid: its outcome (:data:`OUTCOME_NAMES`), its closest centre distance to
    a target (m; None when unknown) and its COLREGs counts (compliant, compliant excused,
    non-compliant, not judged)."""

    outcome: str
    closest_m: float | None
    counts: tuple[int, int, int, int]


def outcome(arrived: bool, collided: bool, counts: Sequence[int]) -> str:
    """The run's outcome (module docstring) from whether it arrived and collided and its
    counts (compliant, compliant excused, non-compliant, not judged).

    >>> outcome(True, False, (2, 1, 0, 0)), outcome(False, False, (0, 0, 0, 3))
    ('excused', 'not-arrived')
    """
    _, excused, noncompliant, not_judged = counts
    if collided:
        return "collided"
    if not arrived:
        return "not-arrived"
    if noncompliant:
        return "noncompliant"
    if not_judged:
        return "not-judged"
    return "excused" if excused else "compliant"


def imazu_grid(cases: Sequence[str], labels: Sequence[str], controllers: Sequence[str],
               cells: dict[tuple[str, str], Cell], headers: Sequence[str]) -> Plot:  # fmt: skip
    """Cases down (``labels`` beside them), ``controllers`` across (``headers`` above them),
    one :class:`Cell` per (case, controller) of ``cells`` (a missing run left white, "no run"),
    its closest distance and its compliant encounters of all written in it ("41.2 m · 1/3");
    a legend of the outcomes below. Every text prints at >= :data:`MIN_FONT_PT` pt.

    Data: ``case,controller,outcome,closest_distance_m,compliant,compliant_excused,
    noncompliant,not_judged``, one row per cell drawn (distance 3 decimals, empty unknown).
    """
    if not cases or not controllers:
        raise UsvError("imazu_grid: no case or no controller")
    if len(labels) != len(cases) or len(headers) != len(controllers):
        raise UsvError("imazu_grid: one label per case and one header per controller")
    bad = sorted({c.outcome for c in cells.values()} - set(OUTCOME_NAMES))
    if bad:
        raise UsvError(f"imazu_grid: unknown outcome {', '.join(bad)}")
    from matplotlib.patches import Patch, Rectangle

    look = {o[0]: o for o in OUTCOMES}
    scale = WIDTH / printed_width(WIDTH)  # set sizes that print at MIN_FONT_PT and up
    text_pt = MIN_FONT_PT * scale
    rows = []
    with figure(WIDTH, ROW * len(cases) + 1.9) as fig:
        ax = fig.add_subplot()
        for i, case in enumerate(cases):
            for j, controller in enumerate(controllers):
                cell = cells.get((case, controller))
                if cell is None:
                    ax.text(j + 0.5, i + 0.5, "no run", ha="center", va="center",
                            fontsize=text_pt, color="0.4")  # fmt: skip
                    continue
                _, _, face, hatch, ink = look[cell.outcome]
                ax.add_patch(Rectangle((j, i), 1, 1, facecolor=face, edgecolor="white",
                                       hatch=hatch, linewidth=1.5))  # fmt: skip
                distance = "-" if cell.closest_m is None else f"{cell.closest_m:.1f} m"
                text = f"{distance} · {cell.counts[0]}/{sum(cell.counts)}"
                ax.text(j + 0.5, i + 0.5, text, ha="center", va="center", fontsize=text_pt,
                        color=ink, bbox={"facecolor": face, "edgecolor": "none",
                                         "pad": 0.6})  # fmt: skip
                exact = "" if cell.closest_m is None else fixed([cell.closest_m], 3)[0]
                rows.append((case, controller, cell.outcome, exact, *cell.counts))
        ax.set_xlim(0, len(controllers))
        ax.set_ylim(len(cases), 0)
        ax.set_xticks([j + 0.5 for j in range(len(controllers))], list(headers))
        ax.set_yticks([i + 0.5 for i in range(len(cases))], list(labels),
                      fontfamily="DejaVu Sans Mono")  # fmt: skip
        ax.xaxis.tick_top()
        ax.tick_params(length=0)
        ax.grid(False)
        for side in ax.spines.values():
            side.set_visible(False)
        handles = [Patch(facecolor=face, edgecolor="0.5", hatch=hatch, label=label)
                   for _, label, face, hatch, _ in OUTCOMES]  # fmt: skip
        fig.legend(handles=handles, loc="outside lower center", ncols=2, frameon=False)
        image = png(fig)
    header = ("case", "controller", "outcome", "closest_distance_m", "compliant",
              "compliant_excused", "noncompliant", "not_judged")  # fmt: skip
    return Plot(image, csv_text(header, rows))
