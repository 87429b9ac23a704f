"""Global path planning: the path problem, optimizers, exact planners, benchmark functions.

Entry points (docs/api.md): :func:`plan_route` plans a route on a navigation grid
(``usvtool plan``, :mod:`.planner`); :func:`run_benchmark` runs the optimizers on the benchmark
functions F1-F10 (``usvtool functions``, :mod:`.benchrun`). Each takes its options and gives a
result with the command's ``summary()``.
"""

from usvtool.plan.benchrun import BenchmarkOptions, BenchmarkResult, run_benchmark
from usvtool.plan.planner import PlanOptions, PlanResult, plan_route

__all__ = ["BenchmarkOptions", "BenchmarkResult", "PlanOptions", "PlanResult", "plan_route",
           "run_benchmark"]  # fmt: skip
