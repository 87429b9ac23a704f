"""Run optimizers on the benchmark functions and summarise them as in the IWSO paper's Table 1.

The stage API (``usvtool functions``): :func:`run_benchmark` runs what a
:class:`BenchmarkOptions` asks; its :class:`BenchmarkResult` gives the table
(:meth:`~BenchmarkResult.table`, :meth:`~BenchmarkResult.write_table`), one row per cell
(:meth:`~BenchmarkResult.rows`) and the command's summary (:meth:`~BenchmarkResult.summary`).

Every run's seed comes from ``SeedSequence([seed, crc32(algorithm), crc32(function), run])``,
spawned into one stream for the optimizer and one for F7's noise, so a result does not depend
on the order of the runs nor on how many worker processes share them.
"""

from __future__ import annotations

import os
import zlib
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass

import numpy as np

from usvtool.plan.benchmark_functions import FUNCTIONS, get_function
from usvtool.plan.optimizers import OPTIMIZERS, make_optimizer

STATS = ("best", "worst", "mean", "std")


@dataclass(frozen=True)
class Task:
    algorithm: str
    function: str
    run: int
    seed: int
    pop: int
    iters: int
    dim: int


@dataclass
class Cell:
    """Statistics of the final best costs of ``runs`` runs of one algorithm on one function."""

    function: str
    algorithm: str
    best: float
    worst: float
    mean: float
    std: float  # sample standard deviation (ddof = 1, MATLAB's std); 0 for one run
    optimum: float
    evaluations: float  # mean objective evaluations per run
    seconds: float  # mean wall-clock time per run (varies between machines and runs)


def run_seeds(seed: int, algorithm: str, function: str, run: int) -> list[np.random.SeedSequence]:
    """The optimizer's and the noise's seed sequences for one run."""
    key = [seed % 2**64, zlib.crc32(algorithm.encode()), zlib.crc32(function.encode()), run]
    return np.random.SeedSequence(key).spawn(2)


def run_one(task: Task) -> tuple[float, int, float]:
    """One run: (final best cost, evaluations, seconds)."""
    opt_seed, noise_seed = run_seeds(task.seed, task.algorithm, task.function, task.run)
    fn = get_function(task.function)
    optimizer = make_optimizer(
        task.algorithm, task.pop, task.iters, np.random.default_rng(opt_seed)
    )
    objective = fn.objective(np.random.default_rng(noise_seed))
    result = optimizer.minimize(objective, *fn.bounds(task.dim))
    return result.f, result.evaluations, result.seconds


@dataclass
class BenchmarkOptions:
    """Everything :func:`run_benchmark` can be told (the ``usvtool functions`` options)."""

    algorithms: Sequence[str] = ()  # optimizer names, in order (repeats dropped); () for all
    functions: Sequence[str] = ()  # F1..F10, any case, in order (repeats dropped); () for all
    runs: int = 25
    pop: int = 50
    iters: int = 300
    dim: int = 30
    seed: int = 0
    jobs: int = 1  # worker processes (the results do not depend on it)


@dataclass
class BenchmarkResult:
    """The cells of a benchmark, functions outer, algorithms inner, in the order asked."""

    cells: list[Cell]
    algorithms: list[str]
    functions: list[str]
    options: BenchmarkOptions
    table_output: str | None = None  # where write_table() put the table

    def table(self, timing: bool = False) -> str:
        """The Table 1 layout (:func:`format_table`)."""
        return format_table(self.cells, timing)

    def rows(self, timing: bool = False) -> list[dict]:
        """One dict per cell (:func:`cell_dict`)."""
        return [cell_dict(c, timing) for c in self.cells]

    def write_table(self, path: str | os.PathLike) -> None:
        """Write the table to ``path``, atomically, and record where."""
        from usvtool.atomic import write_text

        write_text(path, self.table())
        self.table_output = os.fspath(path)

    def summary(self) -> dict:
        """The ``usvtool functions`` summary (no timings: it is reproducible)."""
        o = self.options
        return {
            "command": "functions",
            "runs": o.runs,
            "pop": o.pop,
            "iters": o.iters,
            "dim": o.dim,
            "seed": o.seed,
            "algorithms": self.algorithms,
            "functions": self.functions,
            "table": self.table_output,
            "results": self.rows(),
        }


def run_benchmark(options: BenchmarkOptions | None = None) -> BenchmarkResult:
    """Every (function, algorithm) cell of ``options``."""
    opts = options or BenchmarkOptions()
    algorithms = list(dict.fromkeys(opts.algorithms)) or list(OPTIMIZERS)
    functions = list(dict.fromkeys(f.upper() for f in opts.functions)) or list(FUNCTIONS)
    cells = _run_cells(
        algorithms, functions, opts.runs, opts.pop, opts.iters, opts.dim, opts.seed, opts.jobs
    )
    return BenchmarkResult(cells, algorithms, functions, opts)


def _run_cells(
    algorithms: Sequence[str],
    functions: Sequence[str],
    runs: int,
    pop: int,
    iters: int,
    dim: int,
    seed: int,
    jobs: int,
) -> list[Cell]:
    """All (function, algorithm) cells, functions outer, in the order given."""
    tasks = [
        Task(a, f, r, seed, pop, iters, dim)
        for f in functions
        for a in algorithms
        for r in range(runs)
    ]
    if jobs > 1:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            out = list(pool.map(run_one, tasks, chunksize=max(1, len(tasks) // (4 * jobs))))
    else:
        out = [run_one(t) for t in tasks]
    cells = []
    for k in range(0, len(tasks), runs):
        f, ev, sec = np.array(out[k : k + runs], float).T
        t = tasks[k]
        cells.append(
            Cell(
                function=t.function,
                algorithm=t.algorithm,
                best=float(f.min()),
                worst=float(f.max()),
                mean=float(f.mean()),
                std=float(f.std(ddof=1)) if runs > 1 else 0.0,
                optimum=get_function(t.function).optimum(dim),
                evaluations=float(ev.mean()),
                seconds=float(sec.mean()),
            )
        )
    return cells


def cell_dict(cell: Cell, timing: bool = False) -> dict:
    """A cell as a dict; without the timing unless asked (it is not reproducible)."""
    d = asdict(cell)
    if not timing:
        del d["seconds"]
    return d


def format_table(cells: Sequence[Cell], timing: bool = False) -> str:
    """Table 1's layout: per function the best/worst/mean/std rows, one column per algorithm."""
    algorithms = list(dict.fromkeys(c.algorithm for c in cells))
    functions = list(dict.fromkeys(c.function for c in cells))
    by = {(c.function, c.algorithm): c for c in cells}
    width = max(10, *(len(a) + 1 for a in algorithms))
    head = f"{'Function':<9}{'':<7}" + "".join(f"{a.upper():>{width}}" for a in algorithms)
    lines = [head, "-" * len(head)]
    rows = [(stat.capitalize(), lambda c, s=stat: f"{getattr(c, s):>{width}.2e}") for stat in STATS]
    rows.append(("Evals", lambda c: f"{c.evaluations:>{width}.0f}"))
    if timing:
        rows.append(("s/run", lambda c: f"{c.seconds:>{width}.3f}"))
    for fn in functions:
        for i, (label, fmt) in enumerate(rows):
            cells_row = "".join(fmt(by[(fn, a)]) for a in algorithms)
            lines.append(f"{fn if i == 0 else '':<9}{label:<7}{cells_row}")
    return "\n".join(lines) + "\n"
