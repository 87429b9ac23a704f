"""The three papers' published figures and improvement claims, as data (docs/papers.md).

Tables (:data:`TABLES`, by id): each :class:`PaperTable` holds one published table (or the
figures a paper gives in its text), its columns with the paper's headings and units, and one
:class:`Row` per method and case, with every cell as the paper prints it beside its float (None
where the paper gives nothing). Names are usvtool's: algorithms as the optimizer registry spells
them, controllers as the controller registry, cases as the bundled charts (routes), scenarios
(runs) and benchmark functions (functions) are named in the results table
(:mod:`usvtool.results`). A row is ``comparable`` when our case is built to the paper's setup, so
that the report may put our figure beside the paper's; otherwise the report shows the paper's
figure alone. ``notes`` say how cells of the converted (partly garbled) texts were read.

Claims (:data:`CLAIMS`): each improvement (or absolute) claim a paper makes, quoted with its
section: the metric (a column of ``usvtool metrics``, or ``final_cost``), the statistic over our
seeds that carries it, the better direction, the method that should win and the rivals it should
beat, and the cases it covers. A relative claim holds when, in every case, the method's
statistic is strictly better than each rival's; an absolute claim (no rivals) when every run of
the method in every case reaches ``target`` (a number, or the name of another metric of the same
run that the metric must equal).

>>> UDWA_TABLE_1.value("udwa", "emergency-head-on", "closest_distance_m")
59.48
>>> IWSO_DWA_TABLE_1.value("iwso", "F5", "mean")
1.03e-06
>>> IWSO_DWA_TABLE_1.value("issa", "F5", "mean") is None  # not in the paper
True
>>> [c.id for c in CLAIMS if c.paper == "udwa"][:2]
['udwa-larger-closest-distance', 'udwa-larger-average-distance']
"""

from __future__ import annotations

from dataclasses import dataclass

#: How a figure summarises runs: the paper's one figure (one run, or it does not say), the
#: lowest / highest / mean / sample variance / sample standard deviation over the runs, the
#: median (our summary where the paper gives one figure), the figure of the run whose fitness is
#: lowest, or every run (absolute claims).
STATISTICS = ("value", "min", "max", "mean", "variance", "std", "median", "of-best", "every")
BETTER = ("lower", "higher")


@dataclass(frozen=True)
class Paper:
    """One paper: its short id, the converted text's file name (in the project's papers
    directory, /work/shared/papers) and its citation."""

    id: str
    file: str
    citation: str


@dataclass(frozen=True)
class Column:
    """A column of a published table.

    ``heading`` and ``unit`` are the paper's (unit None: the paper gives none); ``metric`` is
    our counterpart (a column of ``usvtool metrics``, or ``final_cost``; None: we have none);
    ``statistic`` how the paper's figure summarises its runs (:data:`STATISTICS`); ``scale``
    converts ours to the paper's units: paper figure = ours x scale (100 for a per cent of our
    fraction, 1/60 for minutes of our seconds).
    """

    name: str
    heading: str
    unit: str | None
    metric: str | None
    statistic: str
    scale: float = 1.0


@dataclass(frozen=True)
class Row:
    """One method in one case: the paper's names beside ours, and one cell per column."""

    method: str
    paper_method: str
    case: str
    paper_case: str
    values: tuple[float | None, ...]
    printed: tuple[str | None, ...]
    comparable: bool = True


@dataclass(frozen=True)
class PaperTable:
    """A published table (``label``: "Table 2"), or the figures a section gives in its text
    (``label``: "Section 5.3"); ``kind`` is the results table's kind of its cases."""

    id: str
    paper: str
    label: str
    section: str
    caption: str
    kind: str
    columns: tuple[Column, ...]
    rows: tuple[Row, ...]
    setup: str
    notes: tuple[str, ...] = ()

    def column(self, name: str) -> Column:
        """The column called ``name``; KeyError when the table has none."""
        for c in self.columns:
            if c.name == name:
                return c
        raise KeyError(f"{self.id}: no column {name!r}")

    def row(self, method: str, case: str) -> Row | None:
        """The paper's row for ``method`` in ``case``; None when the paper has none."""
        return next((r for r in self.rows if r.method == method and r.case == case), None)

    def value(self, method: str, case: str, column: str) -> float | None:
        """The paper's figure, in its units; None when the paper gives none."""
        index = self.columns.index(self.column(column))
        row = self.row(method, case)
        return None if row is None else row.values[index]


@dataclass(frozen=True)
class Quote:
    """A passage of a paper, exact but for whitespace, and its section ("5.2", "Abstract")."""

    section: str
    text: str


@dataclass(frozen=True)
class Claim:
    """A claim of a paper (module docstring). ``paper_change``: per case, the relative change
    of the method against the (first) rival that the paper states, in per cent as printed (a
    decrease for ``better == "lower"``, an increase for ``"higher"``), None where it states none;
    empty when it states none at all. ``table``: the id of the paper's table of these cases,
    if any (it may have no column of the claim's metric: the text states the claim alone)."""

    id: str
    paper: str
    quotes: tuple[Quote, ...]
    kind: str
    metric: str
    statistic: str
    better: str
    method: str
    rivals: tuple[str, ...]
    cases: tuple[str, ...]
    table: str | None = None
    paper_change: tuple[str | None, ...] = ()
    target: float | str | None = None
    note: str = ""


PAPERS = {
    p.id: p
    for p in (
        Paper("iwso-dwa", "000_cf53896924b31e5f.txt",
              "Liang & Liu, Optimal Path Planning Method for Unmanned Surface Vehicles Based on "
              "Improved Shark-Inspired Algorithm, J. Mar. Sci. Eng. 2023, 11, 1386"),
        Paper("issa", "002_8767512603f69f43.txt",
              "Liu, Zhang, Ma & Pan, Path Planning of Unmanned Surface Vehicle Based on Improved "
              "Sparrow Search Algorithm, J. Mar. Sci. Eng. 2023, 11, 2292"),
        Paper("udwa", "004_99cdea7600e492d4.txt",
              "Yuan, Tong, He & Wang, Unmanned Vessel Collision Avoidance Algorithm by Dynamic "
              "Window Approach Based on COLREGs Considering the Effects of the Wind and Wave, "
              "J. Mar. Sci. Eng. 2023, 11, 1831"),
    )
}  # fmt: skip


def _row(method: str, paper_method: str, case: str, paper_case: str, *printed: str | None,
         comparable: bool = True) -> Row:  # fmt: skip
    """A row whose cells are numbers as printed (E notation for Table 1's "m x 10^e")."""
    values = tuple(None if p is None else float(p) for p in printed)
    return Row(method, paper_method, case, paper_case, values, tuple(printed), comparable)


# --- IWSO-DWA (paper 000) -------------------------------------------------------------------

_WSO_PAPER_NAMES = {"boa": "BOA", "gwo": "GWO", "mrfo": "MRFO", "woa": "WOA", "ssa": "SSA",
                    "wso": "WSO", "iwso": "IWSO"}  # fmt: skip

# Table 1 as printed, per function and algorithm: best, worst, mean, std (m x 10^e as "me e").
_TABLE_1 = {
    "F1": {
        "boa": ("9.16e-6", "2.99e-5", "2.00e-5", "5.34e-6"),
        "gwo": ("7.19e-20", "7.00e-18", "1.80e-18", "1.85e-18"),
        "mrfo": ("2.40e-269", "2.73e-255", "1.20e-256", "0.00e0"),
        "woa": ("2.20e-55", "8.42e-49", "3.44e-50", "1.68e-49"),
        "ssa": ("0.00e0", "2.26e-175", "9.03e-177", "0.00e0"),
        "wso": ("7.21e1", "3.75e2", "2.25e2", "7.07e1"),
        "iwso": ("0.00e0", "0.00e0", "0.00e0", "0.00e0"),
    },
    "F2": {
        "boa": ("1.85e-8", "5.21e-1", "5.52e-2", "1.31e-1"),
        "gwo": ("8.05e-12", "6.99e-11", "1.75e-11", "1.27e-11"),
        "mrfo": ("1.14e-136", "5.96e-127", "2.71e-128", "1.19e-127"),
        "woa": ("1.40e-35", "1.04e-31", "1.28e-32", "2.66e-32"),
        "ssa": ("0.00e0", "2.31e-61", "9.24e-63", "4.62e-62"),
        "wso": ("2.78e0", "7.02e0", "4.94e0", "1.17e0"),
        "iwso": ("0.00e0", "0.00e0", "0.00e0", "0.00e0"),
    },
    "F3": {
        "boa": ("8.23e-6", "2.74e-5", "1.81e-5", "4.48e-6"),
        "gwo": ("1.17e-5", "2.66e-2", "2.73e-3", "5.69e-3"),
        "mrfo": ("4.60e-261", "7.44e-245", "6.66e-246", "0.00e0"),
        "woa": ("2.10e4", "6.91e4", "4.73e4", "1.27e4"),
        "ssa": ("0.00e0", "5.76e-121", "2.31e-122", "1.15e-121"),
        "wso": ("3.76e2", "1.42e3", "8.60e2", "2.75e2"),
        "iwso": ("0.00e0", "0.00e0", "0.00e0", "0.00e0"),
    },
    "F4": {
        "boa": ("1.14e-3", "2.66e-3", "1.81e-3", "3.89e-4"),
        "gwo": ("1.54e-5", "2.81e-4", "8.91e-5", "5.82e-5"),
        "mrfo": ("1.10e-136", "7.69e-122", "3.25e-123", "1.54e-122"),
        "woa": ("3.57e-2", "8.50e1", "4.22e1", "2.65e1"),
        "ssa": ("0.00e0", "8.76e-97", "3.51e-98", "1.75e-97"),
        "wso": ("6.73e0", "1.17e1", "9.04e0", "1.35e0"),
        "iwso": ("0.00e0", "0.00e0", "0.00e0", "0.00e0"),
    },
    "F5": {
        "boa": ("2.88e1", "2.89e1", "2.89e1", "2.47e-2"),
        "gwo": ("2.57e1", "2.87e1", "2.67e1", "7.96e-1"),
        "mrfo": ("2.21e1", "2.51e1", "2.35e1", "5.87e-1"),
        "woa": ("2.76e1", "2.87e1", "2.80e1", "3.10e-1"),
        "ssa": ("2.35e-9", "5.60e-4", "8.45e-5", "1.50e-4"),
        "wso": ("8.02e2", "2.27e4", "7.75e3", "5.41e3"),
        "iwso": ("2.87e-7", "2.24e-6", "1.03e-6", "1.06e-6"),
    },
    "F6": {
        "boa": ("3.48e0", "6.28e0", "4.98e0", "6.48e-1"),
        "gwo": ("9.60e-5", "1.36e0", "6.08e-1", "3.91e-1"),
        "mrfo": ("3.32e-9", "1.71e-7", "2.70e-8", "3.38e-8"),
        "woa": ("7.01e-2", "9.51e-1", "3.29e-1", "2.07e-1"),
        "ssa": ("1.99e-10", "2.22e-6", "4.36e-7", "5.68e-7"),
        "wso": ("5.18e1", "4.60e2", "2.50e2", "1.05e2"),
        "iwso": ("9.98e-9", "2.35e-8", "1.88e-8", "7.65e-9"),
    },
    "F7": {
        "boa": ("8.60e-4", "6.09e-3", "3.13e-3", "1.28e-3"),
        "gwo": ("6.36e-4", "5.87e-3", "2.41e-3", "1.24e-3"),
        "mrfo": ("2.06e-5", "3.18e-4", "1.57e-4", "8.72e-5"),
        "woa": ("1.49e-4", "1.68e-2", "3.62e-3", "3.36e-3"),
        "ssa": ("5.74e-6", "9.01e-4", "2.88e-4", "2.25e-4"),
        "wso": ("1.55e-2", "1.15e-1", "4.02e-2", "2.27e-2"),
        "iwso": ("1.29e-5", "1.00e-4", "4.56e-5", "4.74e-5"),
    },
    "F8": {
        "boa": ("-1.71e7", "-6.46e4", "-1.48e6", "3.37e6"),
        "gwo": ("-7.42e3", "-4.57e3", "-6.18e3", "8.07e2"),
        "mrfo": ("-9.41e3", "-7.32e3", "-8.51e3", "5.36e2"),
        "woa": ("-1.26e4", "-7.05e3", "-9.84e3", "1.87e3"),
        "ssa": ("-1.26e4", "-5.63e3", "-8.76e3", "2.36e3"),
        "wso": ("-4.11e3", "-2.94e3", "-3.40e3", "2.90e2"),
        "iwso": ("-1.23e4", "-1.22e4", "-1.23e4", "7.79e1"),
    },
    "F9": {
        "boa": ("3.42e-8", "3.58e-4", "2.50e-5", "7.67e-5"),
        "gwo": ("1.65e-12", "2.03e1", "7.42e0", "5.76e0"),
        "mrfo": ("0.00e0", "0.00e0", "0.00e0", "0.00e0"),
        "woa": ("0.00e0", "5.68e-14", "2.27e-15", "1.14e-14"),
        "ssa": ("0.00e0", "0.00e0", "0.00e0", "0.00e0"),
        "wso": ("3.12e1", "1.73e2", "1.15e2", "3.90e1"),
        "iwso": ("0.00e0", "0.00e0", "0.00e0", "0.00e0"),
    },
    "F10": {
        "boa": ("6.63e-4", "1.87e-3", "1.35e-3", "2.77e-4"),
        "gwo": ("6.33e-11", "6.28e-10", "2.28e-10", "1.38e-10"),
        "mrfo": ("8.88e-16", "8.88e-16", "8.88e-16", "0.00e0"),
        "woa": ("8.88e-16", "1.51e-14", "5.58e-15", "2.85e-15"),
        "ssa": ("8.88e-16", "8.88e-16", "8.88e-16", "0.00e0"),
        "wso": ("3.80e0", "6.75e0", "5.25e0", "7.50e-1"),
        "iwso": ("8.88e-16", "8.88e-16", "8.88e-16", "0.00e0"),
    },
}
# Functions whose paper definition is not ours (the F6 note below).
_TABLE_1_OTHER_FUNCTIONS = ("F6",)

IWSO_DWA_TABLE_1 = PaperTable(
    id="iwso-dwa-table-1",
    paper="iwso-dwa",
    label="Table 1",
    section="2.2.4",
    caption="Optimization results of IWSO and other algorithms (BOA, GWO, MRFO, WOA, SSA, WSO) "
    "running on the CEC-2005 test function.",
    kind="functions",
    columns=(
        Column("best", "Best", None, "final_cost", "min"),
        Column("worst", "Worst", None, "final_cost", "max"),
        Column("mean", "Mean", None, "final_cost", "mean"),
        Column("std", "Std", None, "final_cost", "std"),
    ),
    rows=tuple(
        _row(algo, _WSO_PAPER_NAMES[algo], function, function, *cells,
             comparable=function not in _TABLE_1_OTHER_FUNCTIONS)
        for function, by_algo in _TABLE_1.items()
        for algo, cells in by_algo.items()
    ),
    setup="25 independent runs of each algorithm, 50 agents x 300 iterations (section 2.2.4 "
    "prints 'population size ... 300, and the search agent ... 50'; read as in "
    "docs/optimizers.md); the dimension is not stated (30 fits: IWSO's F8 mean -1.23e4 is near "
    "the 30-D minimum -12569.5 and BOA's, GWO's and WOA's F5 near Rosenbrock's 30-D plateau "
    "of 25-29). Our cases: usvtool.plan.functions F1-F10 by the same names; F6 differs.",
    notes=(
        "Every cell is printed as $m \\times 10^{e}$, in the converted text mostly as "
        "'m  imes 10^{e}' (the '\\t' of '\\times' lost); transcribed here as 'me e'.",
        "The function label sits on the second line (Worst) of each block of four; the block "
        "starts with Best. F9 and F10 follow 'Table 1. Cont.' under a repeated header.",
        "Std is printed as 0.00 x 10^0 where best and worst differ (MRFO F1 and F3, SSA F1): "
        "transcribed as printed (0.0).",
        "F6: the paper's values are not integers (IWSO's best 9.98e-9), which the step function "
        "sum(floor(x + 0.5)^2) of usvtool.plan.functions cannot give; the paper's F6 is likely "
        "sum(|x + 0.5|^2), as in Mirjalili's benchmark code: rows not comparable.",
        "BOA's F8 best (-1.71e7), worst (-6.46e4) and mean (-1.48e6) are below F8's 30-D "
        "minimum, -12569.5: that implementation left the box (docs/optimizers.md).",
        "The paper has no ISSA, PSO or pso-issa column.",
    ),
)

IWSO_DWA_TABLE_2 = PaperTable(
    id="iwso-dwa-table-2",
    paper="iwso-dwa",
    label="Table 2",
    section="5.2",
    caption="Comparison performance of the mentioned algorithms (BOA, GWO, MRFO, WOA, SSA, "
    "WSO, IWSO).",
    kind="routes",
    columns=(
        Column("length_m", "Shortest Path Length Cost", "m", "length_m", "value"),
        Column("turns", "Steering Cost", None, "turns", "value"),
        Column("mot", "Smoothness Cost (mot)", None, "mot", "value"),
        Column("planning_time_s", "Time Cost", "s", "planning_time_s", "value"),
    ),
    rows=tuple(
        _row(algo, _WSO_PAPER_NAMES[algo], env, paper_env, *cells)
        for env, paper_env, block in (
            ("env1", "ENV.1", {
                "boa": ("914.530", "8", "0.591", "2.056"),
                "gwo": ("802.370", "9", "0.456", "6.564"),
                "mrfo": ("777.267", "11", "0.794", "1.920"),
                "woa": ("801.650", "8", "0.455", "7.037"),
                "ssa": ("862.133", "5", "0.628", "3.472"),
                "wso": ("847.487", "7", "0.309", "5.416"),
                "iwso": ("710.873", "5", "0.215", "1.247"),
            }),
            ("env2", "ENV.2", {
                "boa": ("1144.975", "19", "3.097", "7.846"),
                "gwo": ("996.773", "11", "0.947", "2.228"),
                "mrfo": ("950.803", "11", "0.930", "2.256"),
                "woa": ("941.590", "11", "0.977", "3.355"),
                "ssa": ("959.620", "15", "2.220", "6.317"),
                "wso": ("1044.975", "11", "1.024", "5.490"),
                "iwso": ("927.925", "10", "0.926", "1.033"),
            }),
        )
        for algo, cells in block.items()
    ),
    setup="Two 500 m x 500 m environments, start (10, 10), goal (490, 490) (section 5.1), "
    "50 agents x 300 iterations; one figure per algorithm and environment (whether one run or "
    "an average, the paper does not say). Our env1 and env2 (charts/make_synthetic.py) are "
    "rebuilt in the spirit of its Figure 6, which the text lacks, with the same size and ends: "
    "compare orders and trends, not the values.",
    notes=(
        "The caption is garbled ('MRFC)\\t)'): read as MRFO.",
        "The environment labels sit on the second line of each block of seven (beside GWO); "
        "the blocks start with BOA: lines 1-7 are ENV.1, 8-14 ENV.2.",
        "Steering cost is the number of turns (section 5.2, 'the total number of turns').",
        "The section's percentages against WSO disagree with the table for mot: 'improved by "
        "30.22%' and '9.49%' where the table gives 30.42 % and 9.57 % (claim iwso-smoother).",
    ),
)

# Section 5.3: the eight encounters, as its text gives them (coordinates in the 500 m map).
IWSO_DWA_ENCOUNTERS = PaperTable(
    id="iwso-dwa-encounters",
    paper="iwso-dwa",
    label="Section 5.3",
    section="5.3",
    caption="Dynamic avoidance simulation experiment: the USV and the obstacle ship of each "
    "encounter, and the USV's turn.",
    kind="runs",
    columns=(
        Column("own_start_x", "starting point of USV, x", "m", None, "value"),
        Column("own_start_y", "starting point of USV, y", "m", None, "value"),
        Column("own_goal_x", "target point of USV, x", "m", None, "value"),
        Column("own_goal_y", "target point of USV, y", "m", None, "value"),
        Column("own_speed", "USV speed", "m/s", None, "value"),
        Column("target_start_x", "starting coordinate of the obstacle ship, x", "m", None,
               "value"),
        Column("target_start_y", "starting coordinate of the obstacle ship, y", "m", None,
               "value"),
        Column("target_speed", "obstacle ship speed", "m/s", None, "value"),
        Column("turn_deg", "the USV's turn (approximately)", "degrees", None, "value"),
    ),
    rows=(
        _row("gdwa", "IWSO-DWA", "env1-overtaking", "ENV.1 overtaking (Figure 11)",
             "260", "30", "260", "380", "4", "260", "120", "2", "65"),
        _row("gdwa", "IWSO-DWA", "env1-head-on", "ENV.1 head-on (Figure 13)",
             "260", "30", "260", "380", "4", "260", "350", "3", "70"),
        _row("gdwa", "IWSO-DWA", "env1-crossing-port", "ENV.1 port side crossing (Figure 15)",
             "260", "30", "260", "180", "4", "180", "110", "4", None),
        _row("gdwa", "IWSO-DWA", "env1-crossing-starboard", "ENV.1 starboard crossing "
             "(Figure 17)", "260", "30", "260", "180", "4", "330", "110", "4", "47"),
        _row("gdwa", "IWSO-DWA", "env2-overtaking", "ENV.2 overtaking (Figure 19)",
             "130", "180", "130", "380", "4", "130", "260", "2.5", "68"),
        _row("gdwa", "IWSO-DWA", "env2-head-on", "ENV.2 head-on (Figure 21)",
             "130", "180", "130", "380", "4", "130", "350", "2", "63"),
        _row("gdwa", "IWSO-DWA", "env2-crossing-port", "ENV.2 port side (Figure 23)",
             "130", "180", "130", "380", "4", "75", "260", "3", "80"),
        _row("gdwa", "IWSO-DWA", "env2-crossing-starboard", "ENV.2 starboard (Figure 25)",
             "130", "180", "130", "380", "4", "200", "260", "3", None),
    ),
    setup="Our charts/scenarios/env1-*.yaml and env2-*.yaml take these coordinates and speeds "
    "exactly, the obstacle ship's course from the text's 'bottom to top' (0), 'top to bottom' "
    "(180), 'left to right' (90) and 'right to left' (270), but on open water: the islands of "
    "our rebuilt env1.tif and env2.tif lie on these lines (charts/scenarios/README.md).",
    notes=(
        "Turns are to starboard ('upper right') in the text, approximately; the port crossing "
        "in ENV.1 and the starboard crossing in ENV.2 give no angle (None).",
        "The text gives no ship lengths and no durations; usvtool has no metric of the turn "
        "angle, so the report shows these figures alone.",
    ),
)

# --- ISSA (paper 002) -----------------------------------------------------------------------

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
        _row(algo, _ISSA_PAPER_NAMES[algo], "grid20", "20 x 20 grid environment", *cells)
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
        Row("issa", "Improved Sparrow Search Algorithm", "grid50",
            "Zhenjiang Port to Yangzhou Port, ENC grid, (2, 2) to (50, 50)",
            (63.97, 3.0, 2.99), ("63.97", "three", "2.99")),
    ),
    setup="One run of ISSA on the 50 x 50 grid of the Zhenjiang-Yangzhou channel chart, cell "
    "(2, 2) to cell (50, 50). Our grid50 is a river grid in its spirit (charts/make_synthetic.py),"
    " from (1.5, 1.5) to (49.5, 49.5), the centres of the same cells.",
    notes=("The turns are printed as a word: 'three instances of ruddering'.",),
)

# --- UDWA (paper 004) -----------------------------------------------------------------------

_EMERGENCIES = (("emergency-head-on", "Head-on"), ("emergency-crossing", "Crossing"),
                ("emergency-overtaking", "Overtaking"))  # fmt: skip
_UDWA_TABLE_1 = {  # closest, average, optimisation rate, per encounter
    "ccdwa": (("33.56", "54.80", None), ("18.16", "50.93", None), ("19.13", "37.93", None)),
    "udwa": (("59.48", "78.50", "43.25"), ("60.73", "66.90", "31.36"),
             ("40.40", "63.65", "67.81")),
}  # fmt: skip

UDWA_TABLE_1 = PaperTable(
    id="udwa-table-1",
    paper="udwa",
    label="Table 1",
    section="4.1",
    caption="Distance between our ship and the obstacle ship in the collision avoidance "
    "scenario obtained by the CCDWA and UDWA algorithms.",
    kind="runs",
    columns=(
        Column("closest_distance_m", "closest distance", "m", "closest_distance_m", "value"),
        Column("average_distance_m", "average distance", "m", "average_distance_m", "value"),
        Column("average_distance_rate", "optimization rate", "%", "average_distance_rate",
               "value", 100.0),
    ),
    rows=tuple(
        _row(controller, controller.upper(), case, paper_case, *cells)
        for controller, by_case in _UDWA_TABLE_1.items()
        for (case, paper_case), cells in zip(_EMERGENCIES, by_case, strict=True)
    ),
    setup="Three-ship emergencies (section 4.1) of 15 m, 20 t ships (Table 3); the paper gives "
    "no coordinates or speeds. Our emergency-*.yaml are built from its text, Table 3 and the "
    "onsets it states (12 s head-on, before 5 s crossing) (charts/scenarios/README.md).",
    notes=(
        "The table is transposed (figures down, encounters across) and prints the unit with "
        "each distance ('33.56 m'); rows here are controller x encounter.",
        "The optimization rate is that of the average distance, (UDWA - CCDWA) / CCDWA: "
        "(78.50 - 54.80) / 54.80 = 43.25 %; it is given once per encounter, on the udwa rows.",
        "One run per controller and encounter; the paper does not say how the average distance "
        "is taken (usvtool averages over the encounter's steps, docs/metrics.md).",
    ),
)

UDWA_WIND = PaperTable(
    id="udwa-wind",
    paper="udwa",
    label="Section 4.2",
    section="4.2",
    caption="Arrival times of the USVs in the two wind and wave fields (text and Figures 19, "
    "20).",
    kind="runs",
    columns=(
        Column("arrival_time_min", "arrives at the target point", "min", "arrival_time_s",
               "value", 1 / 60),
    ),
    rows=tuple(
        _row(controller, paper_controller, case, paper_case, printed, comparable=False)
        for case, paper_case, times in (
            ("wind-southeast-strong", "higher wind speed in the south (Figures 18a, 19)",
             ("48", "67")),
            ("wind-northwest-strong", "higher wind speed in the north (Figures 18b, 20)",
             ("52", "65")),
        )
        for (controller, paper_controller), printed in zip(
            (("udwa", "UDWA (red USV)"), ("dwa", "traditional DWA (blue USV)")), times,
            strict=True,
        )
    ),
    setup="The waters around Ikaria island, start in the south-west and goal in the north-east, "
    "runs of about an hour. Our wind-*-strong.yaml are a 700 m square whose two halves are "
    "split by the start-goal line, runs of about two minutes (charts/scenarios/README.md): "
    "only the direction of the difference compares, so no row is comparable.",
    notes=(
        "The text and the captions disagree. The text: 'As can be seen in Figure 19, the red "
        "USV ... arrives at the target point at 52 min in the windy and wavy environment with "
        "higher wind speed in the north, whereas the blue USV ... arrives ... at 65 min', then "
        "Figure 20 (north): 48 and 67 min. The captions' last snapshots: Figure 19 (south) "
        "'(d) 48 min. (e) 67 min', Figure 20 (north) '(d) 52 min. (e) 65 min'. Read with the "
        "captions and the text's own 'higher wind speed in the north' for 52/65: south 48/67, "
        "north 52/65. Either reading has UDWA earlier in both fields.",
        "The blue USV runs 'the traditional DWA algorithm': usvtool's dwa.",
    ),
)

TABLES = {
    t.id: t
    for t in (IWSO_DWA_TABLE_1, IWSO_DWA_TABLE_2, IWSO_DWA_ENCOUNTERS, ISSA_TABLE_3,
              ISSA_FIGURE_11, UDWA_TABLE_1, UDWA_WIND)
}  # fmt: skip

# --- claims ---------------------------------------------------------------------------------

_ENVS = ("env1", "env2")
_FUNCTIONS = tuple(f"F{i}" for i in range(1, 11))
_WSO_RIVALS = ("wso", "boa", "gwo", "mrfo", "woa", "ssa")
_ENCOUNTERS_53 = tuple(r.case for r in IWSO_DWA_ENCOUNTERS.rows)
_EMERGENCY_CASES = tuple(case for case, _ in _EMERGENCIES)
_WINDS = ("wind-southeast-strong", "wind-northwest-strong")

_ENV1_VS_WSO = Quote("5.2", "Compared with the WSO, the path length, steering times and time "
                     "cost planned by the IWSO decreased by 16.12%, 28.57% and 76.97%, "
                     "respectively.")  # fmt: skip
_ENV2_VS_WSO = Quote("5.2", "Compared with the WSO, the path length, steering times and time "
                     "cost planned by the IWSO are decreased by 11.2%, 9% and 81.19%, "
                     "respectively.")  # fmt: skip
_ISSA_SEC4 = ("Figure 10 and Table 3 demonstrate that the improved sparrow search algorithm "
              "achieves smaller fitness values than the traditional sparrow search algorithm, "
              "as evidenced by ")  # fmt: skip
_ISSA_VS_PSO = ("The enhanced sparrow search algorithm obtained smaller fitness values than the "
                "particle swarm search algorithm, as evidenced by ")  # fmt: skip
_UDWA_RATES = Quote("4.1", "The optimization rates in the head-on situation, crossing "
                    "situation, and overtaking situation are 43.25%, 31.36%, and 67.81%, "
                    "respectively.")  # fmt: skip


def _iwso_vs_wso(id_: str, metric: str, quotes, change, note: str = "") -> Claim:
    return Claim(id_, "iwso-dwa", quotes, "routes", metric, "median", "lower", "iwso",
                 ("wso",), _ENVS, "iwso-dwa-table-2", change, note=note)  # fmt: skip


def _issa(id_: str, rival: str, metric: str, statistic: str, quotes, change,
          note: str = "") -> Claim:  # fmt: skip
    return Claim(id_, "issa", quotes, "routes", metric, statistic, "lower", "issa", (rival,),
                 ("grid20",), "issa-table-3", change, note=note)  # fmt: skip


def _udwa(id_: str, metric: str, better: str, quotes, change=(), note: str = "") -> Claim:
    return Claim(id_, "udwa", quotes, "runs", metric, "median", better, "udwa", ("ccdwa",),
                 _EMERGENCY_CASES, "udwa-table-1", change, note=note)  # fmt: skip


_TABLE_2_NOTE = ("Table 2 gives one figure per algorithm and environment; we compare medians "
                 "over seeds. The abstract's 13.66%, 18.78%, 79.08% and 19.85% are the means of "
                 "the two environments' figures.")  # fmt: skip

CLAIMS: tuple[Claim, ...] = (
    _iwso_vs_wso("iwso-shorter", "length_m", (_ENV1_VS_WSO, _ENV2_VS_WSO), ("16.12", "11.2"),
                 _TABLE_2_NOTE),
    _iwso_vs_wso("iwso-fewer-turns", "turns", (_ENV1_VS_WSO, _ENV2_VS_WSO), ("28.57", "9"),
                 _TABLE_2_NOTE),
    _iwso_vs_wso(
        "iwso-smoother", "mot",
        (Quote("5.2", "And the path smoothness planned by the IWSO is improved by 30.22%."),
         Quote("5.2", "Meanwhile, the path smoothness planned by the IWSO is improved by "
                      "9.49%.")),
        ("30.22", "9.49"),
        "A lower mot is smoother (eq. 27). Table 2's own mot figures give 30.42 % (env1) and "
        "9.57 % (env2), not the text's 30.22 % and 9.49 %. " + _TABLE_2_NOTE),
    _iwso_vs_wso("iwso-faster", "planning_time_s", (_ENV1_VS_WSO, _ENV2_VS_WSO),
                 ("76.97", "81.19"),
                 "Planning times are the machine's: the paper's are MATLAB's on a 2.4 GHz "
                 "laptop. " + _TABLE_2_NOTE),
    Claim("iwso-lowest-fitness", "iwso-dwa",
          (Quote("5.2", "the proposed IWSO algorithm has demonstrated the fastest convergence "
                        "speed and highest accuracy of final convergence accuracy"),
           Quote("5.2", "the proposed IWSO algorithm reaches stability in about 15 iterations, "
                        "which excelled in both convergence speed and accuracy")),
          "routes", "fitness", "median", "lower", "iwso", _WSO_RIVALS, _ENVS,
          note="The final accuracy only: the convergence curves (Figures 8, 10) are not in the "
               "text and convergence speed is no metric of ours."),
    Claim("iwso-functions-lower-std", "iwso-dwa",
          (Quote("2.2.4", "its standard deviation is smaller than that of the WSO algorithm and "
                          "the other five meta-heuristic algorithms"),),
          "functions", "final_cost", "std", "lower", "iwso", _WSO_RIVALS, _FUNCTIONS,
          "iwso-dwa-table-1",
          note="Strictly smaller in every function: the paper's own Table 1 ties at 0.00 (MRFO "
               "on F1, F3, F9 and F10, SSA on F1, F9 and F10), and MRFO's and SSA's F1 and MRFO's "
               "F3 zeros are printed where best and worst differ."),
    Claim("iwso-functions-lower-mean", "iwso-dwa",
          (Quote("2.2.4", "which shows that IWSO algorithm is effective in improving WSO "
                          "algorithm"),),
          "functions", "final_cost", "mean", "lower", "iwso", ("wso",), _FUNCTIONS,
          "iwso-dwa-table-1",
          note="Our reading of 'effective in improving WSO' as a lower mean final cost on every "
               "function, as the paper's Table 1 has it."),
    Claim("gdwa-colregs", "iwso-dwa",
          (Quote("5.3", "the dynamic collision avoidance behavior of the USV conforms to the "
                        "COLREGs"),),
          "runs", "compliant", "every", "higher", "gdwa", (), _ENCOUNTERS_53,
          "iwso-dwa-encounters", target="judged",
          note="Said of each of the eight encounters; every judged encounter of each run must "
               "be compliant (docs/colregs.md)."),
    Claim("gdwa-no-collision", "iwso-dwa",
          (Quote("Abstract", "it can also help a USV avoid other ships dynamically in real "
                             "time"),),
          "runs", "collision", "every", "lower", "gdwa", (), _ENCOUNTERS_53,
          "iwso-dwa-encounters", target=0.0),
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
    _udwa("udwa-larger-closest-distance", "closest_distance_m", "higher",
          (Quote("4.1", "Comparing the CCDWA and UDWA algorithms, the distance between our ship "
                        "and the obstacle ship can be farther, which reduces the risk of "
                        "collision."),),
          note="In every emergency; Table 1: 33.56 / 59.48, 18.16 / 60.73, 19.13 / 40.40 m."),
    _udwa("udwa-larger-average-distance", "average_distance_m", "higher",
          (_UDWA_RATES,
           Quote("Abstract", "the UDWA algorithm optimized the distance to the obstacle ship by "
                             "43.25%, 31.36%, and 67.81%")),
          ("43.25", "31.36", "67.81"),
          "The rates are of the average distance (Table 1; usvtool's average_distance_rate)."),
    _udwa("udwa-less-domain-intrusion", "domain_intrusion_s", "lower",
          (Quote("4.1", "The passage from the direction of the risk can greatly reduce the "
                        "intrusion into the field of the other ships and the probability of "
                        "collision."),),
          note="Said of the head-on run; the text has CCDWA invade the other ships' domains in "
               "all three (Figures 8b, 11b, 14b). The domain: 7 x 3 ship lengths (section 4.1)."),
    _udwa("udwa-better-colregs", "compliant", "higher",
          (Quote("4.1", "The improved DWA algorithm follows the COLREGs rules better and has "
                        "better flexibility than the CCDWA algorithm"),),
          note="Counts of compliant encounters per run, Rule 2 departures excused as "
               "docs/colregs.md says; a tie (both fully compliant) does not hold."),
    Claim("udwa-earlier-arrival", "udwa",
          (Quote("5", "the UDWA algorithm that takes wind direction into account allows the "
                      "ship to reach the target point faster compared to the DWA algorithm"),),
          "runs", "arrival_time_s", "median", "lower", "udwa", ("dwa",), _WINDS, "udwa-wind",
          note="The paper's runs (48 against 67 min, 52 against 65 min) are not comparable "
               "with ours in size; the claim's direction is."),
)  # fmt: skip
