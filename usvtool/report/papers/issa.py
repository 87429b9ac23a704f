"""The ISSA paper (paper 002: Liu, Zhang, Ma & Pan, J. Mar. Sci. Eng. 2023, 11, 2292) as data:
its Table 3 (50 runs on the 20 x 20 grid), the figures of its ENC grid run (Figure 11) and its
claims (docs/papers.md).
"""

from __future__ import annotations

from usvtool.report.papers.schema import (
    Claim,
    Column,
    Paper,
    PaperRow,
    PaperTable,
    Precondition,
    Quote,
    printed_row,
)

PAPER = Paper("issa", "002_8767512603f69f43.txt",
              "Liu, Zhang, Ma & Pan, Path Planning of Unmanned Surface Vehicle Based on Improved "
              "Sparrow Search Algorithm, J. Mar. Sci. Eng. 2023, 11, 2292")  # fmt: skip

_ISSA_PAPER_NAMES = {"pso-issa": "Particle Swarm Search Algorithm",
                     "ssa": "Traditional Sparrow Search Algorithm",
                     "issa": "Improved Sparrow Search Algorithm"}  # fmt: skip

ISSA_TABLE_3 = PaperTable(
    id="issa-table-3",
    paper="issa",
    label="Table 3",
    section="4",
    caption="Data comparison of 50 simulation experiments.",
    kind="routes",
    columns=(
        Column("best_fitness", "Optimum fitness value", None, "fitness", "min"),
        Column("turns", "Number of Turns", None, "turns", "of-best"),
        Column("mean_fitness", "Mean value", None, "fitness", "mean"),
        Column("mean_time_s", "Mean time", None, "planning_time_s", "mean"),
        Column("fitness_variance", "Variance", None, "fitness", "variance"),
    ),
    rows=tuple(
        printed_row(algo, _ISSA_PAPER_NAMES[algo], "grid20", "20 x 20 grid environment", *cells)
        for algo, cells in (
            ("pso-issa", ("33.68", "11", "35.96", "0.60", "17.03")),
            ("ssa", ("33.17", "10", "35.34", "0.67", "18.62")),
            ("issa", ("29.81", "3", "30.11", "0.94", "9.33")),
        )
    ),
    setup="50 runs of each algorithm on a 20 x 20 grid from cell (1, 1) to cell (20, 20), "
    "100 sparrows (particles) x 500 iterations (Tables 1, 2); fitness = path length + 0.4 per "
    "right-angle turn + 0.2 per obtuse one (section 3). PSO is the paper's (c1 = c2 = 2.5, "
    "w = 1), usvtool's pso-issa. Our grid20 is drawn in the spirit of its Figure 10, which the "
    "text lacks (charts/make_synthetic.py): compare trends, not the values.",
    runs=50,
    notes=(
        "The table is transposed (metrics down, algorithms across); rows here are algorithms.",
        "'the 2020 grid environment model' is the 20 x 20 grid (the '\\times' lost).",
        "The text prints 'path length plus right angle turns minus 0.4 and obtuse angle turns "
        "minus 0.2' (sign garbled): section 3 makes them turning costs, 0.4 and 0.2, added.",
        "'Number of Turns' is an integer per algorithm: read as the turns of the optimum "
        "(lowest-fitness) route, not a mean over the 50 runs.",
        "Units: fitness in grid cells (1 m cells in our grid20); 'Mean time' in s (the text: "
        "'0.27 s slower').",
        "Variance: the paper does not say sample or population (MATLAB's var is the sample).",
        "Section 4 says 'One of the simulation outcomes' has PSO's 'adaptation value ... 0.00', "
        "a misprint (Table 3: 33.68).",
    ),
)

ISSA_FIGURE_11 = PaperTable(
    id="issa-figure-11",
    paper="issa",
    label="Figure 11",
    section="4",
    caption="Result of the improved algorithm in ENC grid environment (the figures of the "
    "text).",
    kind="routes",
    columns=(
        Column("fitness", "adaptation value", None, "fitness", "value"),
        Column("turns", "instances of ruddering", None, "turns", "value"),
        Column("planning_time_s", "iteration time", "s", "planning_time_s", "value"),
    ),
    rows=(
        PaperRow("issa", "Improved Sparrow Search Algorithm", "grid50",
            "Zhenjiang Port to Yangzhou Port, ENC grid, (2, 2) to (50, 50)",
            (63.97, 3.0, 2.99), ("63.97", "three", "2.99")),
    ),
    setup="One run of ISSA on the 50 x 50 grid of the Zhenjiang-Yangzhou channel chart, cell "
    "(2, 2) to cell (50, 50). Our grid50 is a river grid in its spirit (charts/make_synthetic.py),"
    " from (1.5, 1.5) to (49.5, 49.5), the centres of the same cells.",
    notes=("The turns are printed as a word: 'three instances of ruddering'.",),
)

TABLES = (ISSA_TABLE_3, ISSA_FIGURE_11)

# --- claims ---------------------------------------------------------------------------------

_ISSA_SEC4 = ("Figure 10 and Table 3 demonstrate that the improved sparrow search algorithm "
              "achieves smaller fitness values than the traditional sparrow search algorithm, "
              "as evidenced by ")  # fmt: skip
_ISSA_VS_PSO = ("The enhanced sparrow search algorithm obtained smaller fitness values than the "
                "particle swarm search algorithm, as evidenced by ")  # fmt: skip


def _issa(id_: str, rival: str, metric: str, statistic: str, quotes, change,
          note: str = "") -> Claim:  # fmt: skip
    reachable = (Precondition("turns-reachable", "Table 3's routes turn 3-11 times; the "
                              "paper's encoding (a vertex per grid column, the batch's "
                              "--encoding columns) gives a route of the 20 x 20 grid 22 "
                              "points, up to 20 turns"),) if metric == "turns" else ()  # fmt: skip
    return Claim(id_, "issa", quotes, "routes", metric, statistic, "lower", "issa", (rival,),
                 ("grid20",), "issa-table-3", change, note=note,
                 preconditions=reachable)  # fmt: skip


CLAIMS: tuple[Claim, ...] = (
    _issa("issa-lower-mean-fitness", "ssa", "fitness", "mean",
          (Quote("Abstract", "the average fitness value of the path planned by improved sparrow "
                             "search algorithm is reduced by 14.8%"),),
          ("14.8",),
          "Section 4 says 'the 6.3 percent decrease in the average fitness value'; Table 3 "
          "gives 14.80 %, as the abstract."),
    _issa("issa-lower-variance", "ssa", "fitness", "variance",
          (Quote("Abstract", "the variance is reduced by 49.9%"),
           Quote("4", "the enhanced sparrow search algorithm is more stable, as demonstrated by "
                      "a comparison of variance data"),
           Quote("5", "Compared with the results of mean variance, the robustness of the "
                      "algorithm is improved and the routes obtained are more stable")),
          ("49.9",)),
    _issa("issa-lower-best-fitness", "ssa", "fitness", "min",
          (Quote("4", _ISSA_SEC4 + "the 10.13 percent decrease in the optimal fitness value"),),
          ("10.13",)),
    _issa("issa-fewer-turns", "ssa", "turns", "of-best",
          (Quote("4", _ISSA_SEC4 + "the 10.13 percent decrease in the optimal fitness value, "
                                   "the 70 percent decrease in the number of turns"),
           Quote("5", "The improved sparrow search algorithm can reduce the inflection point of "
                      "the track")),
          ("70",), "The turns of the lowest-fitness route (Table 3's reading)."),
    _issa("issa-vs-pso-lower-best-fitness", "pso-issa", "fitness", "min",
          (Quote("4", _ISSA_VS_PSO + "the 11.49% reduction in the optimal fitness value"),),
          ("11.49",),
          "The introduction attributes the 11.49%, 72.7% and 7.92% to the comparison with the "
          "traditional sparrow search algorithm; section 4 and Table 3 to PSO."),
    _issa("issa-vs-pso-fewer-turns", "pso-issa", "turns", "of-best",
          (Quote("4", _ISSA_VS_PSO + "the 11.49% reduction in the optimal fitness value, 72.7% "
                                     "reduction in the number of cycles"),),
          ("72.7",), "'cycles' are the turns (11 against 3 in Table 3)."),
    _issa("issa-vs-pso-lower-mean-fitness", "pso-issa", "fitness", "mean",
          (Quote("4", "7.92% reduction in the average fitness value"),),
          ("7.92",), "Table 3 gives 16.27 % ((35.96 - 30.11) / 35.96), not 7.92 %."),
)  # fmt: skip
