"""The smallest effect of interest of each metric a claim may judge (docs/statistics.md, "The
smallest effects of interest"): the equivalence margin of :func:`usvtool.report.equivalence.
tost`, and the yardstick of "too small to matter" when reading an effect.

A metric's margin is in its own units: an ``absolute`` amount, a ``share`` of the rival's
median (|median|), or both, the larger winning (:func:`margin`): max(absolute, share x
|rival's median|). Declared for the metrics of :data:`usvtool.pipeline.CLAIM_METRICS` (the
results table's columns, docs/metrics.md) per kind of job, each with a one-line reason; the
figures quoted in the reasons are of ``make report``'s batch (``build/batch/metrics.csv`` and
``timings.csv``). A failure rate's margin (``arrived``, ``collision``, ``controller_failed``,
``collision_free``) is a difference of proportions, for reading
:func:`usvtool.report.rates.compare_failures`' interval; TOST is not run on rates.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Margin:
    """``absolute`` in the metric's units, ``share`` of the rival's |median|; the margin is the
    larger of the two (either may be 0)."""

    absolute: float
    share: float
    reason: str


_RATE = Margin(0.10, 0.0, "10 percentage points of runs failing (3 of a family's 30 scenes): "
                          "a smaller difference is one or two runs")  # fmt: skip
_COUNT = Margin(1.0, 0.0, "a count of encounters: a shift under one encounter is no encounter "
                          "handled differently")  # fmt: skip
_TIME = Margin(0.005, 0.10, "a tenth of the rival's time, never under 5 ms (5 times the 1 ms "
                            "the timings are written to): timings on a shared machine vary "
                            "from run to run (IQR 3-70 % of the median, env1)")  # fmt: skip
_SMOOTHNESS = Margin(0.0, 0.10, "smoothness (IWSO eq. 27) has no physical unit: a tenth of the "
                                "rival's, under one optimizer's own spread over seeds (IWSO "
                                "env1: IQR 0.66 of a median 1.07)")  # fmt: skip
_TURNS = Margin(1.0, 0.0, "turns are counted: a shift under one turn saves no turn")

#: kind of job -> metric -> its smallest effect of interest.
MARGINS: dict[str, dict[str, Margin]] = {
    "routes": {
        "length_m": Margin(0.0, 0.01, "1 % of the rival's route (7 m of env1's 700 m): a "
                                      "shorter passage saves time and fuel in proportion, and "
                                      "1 % is about one optimizer's own spread over seeds "
                                      "(IWSO env1: IQR 8.9 m of 711 m)"),
        "length_ratio": Margin(0.01, 0.0, "the route length's 1 %, as a ratio to the optimum"),
        "turns": _TURNS,
        "mot": _SMOOTHNESS,
        "fitness": Margin(0.0, 0.01, "the path problem's cost is the route's length in metres "
                                     "plus penalties: as the length, 1 % of the rival's"),
        "collision_free": _RATE,
        "attempt": Margin(1.0, 0.0, "optimizer runs are counted: under one run is no rerun"),
        "planning_time_s": _TIME,
        "wall_time_s": _TIME,
    },
    "runs": {
        "arrived": _RATE,
        "collision": _RATE,
        "controller_failed": _RATE,
        "length_m": Margin(0.0, 0.01, "1 % of the rival's track, as a route's length"),
        "turns": _TURNS,
        "mot": _SMOOTHNESS,
        "arrival_time_s": Margin(0.0, 0.01, "1 % of the rival's passage (1.2 s of the wind "
                                            "family's 125 s), under the spread of one "
                                            "controller's arrival over the 30 wind fields (IQR "
                                            "1.3-1.7 s); the papers claim 20-28 %"),
        "closest_distance_m": Margin(0.0, 0.05, "5 % of the rival's closest approach (about "
                                                "2 m at the emergency family's 20-55 m), under "
                                                "the udwa boat's beam (4.5 m): a clearance no "
                                                "one would act on"),
        "average_distance_m": Margin(0.0, 0.05, "5 % of the rival's average distance, as the "
                                                "closest approach"),
        "domain_intrusion_s": Margin(1.0, 0.0, "one second inside the ship domain (10 steps "
                                               "of the default dt 0.1 s); a share would be 0, "
                                               "the families' medians being 0"),
        "encounters": _COUNT,
        "judged": _COUNT,
        "compliant": _COUNT,
        "compliant_excused": _COUNT,
        "noncompliant": _COUNT,
        "not_judged": _COUNT,
        "closest_distance_rate": Margin(0.05, 0.0, "5 points of the reference's closest "
                                                   "approach, as closest_distance_m"),
        "average_distance_rate": Margin(0.05, 0.0, "5 points of the reference's average "
                                                   "distance, as average_distance_m"),
        "wall_time_s": _TIME,
    },
    "functions": {
        "final_cost": Margin(1e-8, 0.01, "1 % of the rival's absolute cost (the costs span 20 "
                                         "orders of magnitude over F1-F10: only a share compares), "
                                         "never under 1e-8, below which the CEC 2014 benchmark "
                                         "(Liang, Qu and Suganthan 2013, its technical report) "
                                         "counts an error as 0; F8's optimum is -12 569.5, so its "
                                         "share is of the cost, not the error"),
        "wall_time_s": _TIME,
    },
}  # fmt: skip


def margin(kind: str, metric: str, rival_median: float) -> float:
    """The margin of ``metric`` of ``kind`` against a rival whose median is ``rival_median``:
    max(absolute, share x |rival_median|); KeyError for an undeclared metric."""
    declared = MARGINS[kind][metric]
    return max(declared.absolute, declared.share * abs(rival_median))
