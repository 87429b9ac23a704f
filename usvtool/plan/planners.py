"""The planners by name: how ``usvtool plan --algo NAME`` plans, resolved in one place
(:func:`resolve`).

A base planner is an optimizer of :data:`usvtool.plan.optimizers.OPTIMIZERS` (:class:`Optimize`:
it minimises the :class:`~usvtool.plan.problem.PathProblem` cost, :func:`optimize`) or an exact
planner of :data:`EXACT` (an :class:`ExactPlanner`, deterministic: ``anyangle``, the exact
any-angle shortest route; ``astar``, 8-connected A*: :mod:`usvtool.plan.exact`). Both registries
take plugins from the entry-point group ``usvtool.planners``, which they share
(:class:`usvtool.registry.Registry`): a class goes to the one of its base. A variant suffix
wraps a planner that takes it (:attr:`Planner.variants`; :data:`VARIANTS`): ``+s``
(:class:`Shortened`: route shortening of its result, :mod:`usvtool.plan.shorten`; the optimizers
and the built-in exact planners) and ``+g`` (:class:`Guided`, optimizers only: the optimizer on
the route-guided problem of :mod:`usvtool.plan.guided`). A name takes one suffix at most.

:func:`names` lists the base names in the order every listing uses (the optimizers in their
registry's order, then the exact planners); the CLI, the pipelines (``usvtool batch``) and the
report take their names from here.

>>> resolve("iwso+g").name, resolve("anyangle+s").seeded, split_algorithm("gwo")
('iwso+g', False, ('gwo', ''))
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from usvtool.collision import is_collision_free
from usvtool.errors import UsvError
from usvtool.plan import exact, guided, shorten
from usvtool.plan.optimizers import OPTIMIZERS, Optimizer, no_suffix
from usvtool.plan.problem import PathProblem
from usvtool.registry import Registry

if TYPE_CHECKING:
    from usvtool.plan.planner import PlanOptions

DEFAULT_WAYPOINTS = 3  # free waypoints of the faithful encoding when none are given


@dataclass(frozen=True)
class Request:
    """What a planner plans from: the problem (its grid, ends and encoding), the ends in cell
    coordinates, the options and the free waypoints they resolve to."""

    problem: PathProblem
    start: tuple[float, float]
    goal: tuple[float, float]
    options: PlanOptions
    waypoints: int | str


@dataclass(frozen=True)
class Planned:
    """A planner's answer: the route's cells, the parameters the route records, the
    convergence of the optimizer's run (metres; empty for the exact planners) and the
    1-based run that gave the route (None: not an optimizer's)."""

    cells: np.ndarray
    parameters: dict
    convergence: list[float] = field(default_factory=list)
    attempt: int | None = None


class Planner(ABC):
    """How to plan a route of one ``--algo`` name.

    ``seeded``: the route depends on the seed (the route records it); ``guided``: a ``+g``
    variant, which takes ``waypoints="auto"`` (its default) and only the waypoints encoding;
    ``optimizer``: the optimizer it runs (None: an exact planner); ``variants``: the suffixes
    of :data:`VARIANTS` it takes (``NAME+s``).
    """

    name: str = ""
    seeded: bool = True
    guided: bool = False
    optimizer: type[Optimizer] | None = None
    variants: tuple[str, ...] = ()

    @property
    def default_waypoints(self) -> int | str:
        """The free waypoints when none are given."""
        return DEFAULT_WAYPOINTS

    def problem_waypoints(self, waypoints: int | str) -> int:
        """The free waypoints of the :class:`PathProblem` the request holds."""
        return int(waypoints)

    def check_params(self, params: dict) -> None:
        """Refuse parameters the optimizer has not got (:meth:`Optimizer.check_params`). An
        exact planner takes none and ignores any, as a route matrix gives the same options to
        every algorithm."""
        if self.optimizer is not None:
            self.optimizer.check_params(params)

    @abstractmethod
    def plan(self, request: Request) -> Planned:
        """The route of ``request`` (its ends are checked: connected, apart)."""


class Optimize(Planner):
    """An optimizer of :data:`OPTIMIZERS` on the path problem (with its ``+s`` and ``+g``)."""

    variants = (shorten.SUFFIX, guided.SUFFIX)

    def __init__(self, optimizer: type[Optimizer]):
        self.optimizer = optimizer
        self.name = optimizer.name

    def plan(self, request: Request) -> Planned:
        o = request.options
        run = optimize(request.problem, self.optimizer, o)
        parameters = {**run.parameters, "encoding": o.encoding, "turn_weight": o.turn_weight}
        if o.encoding == "waypoints":
            parameters["waypoints"] = request.waypoints
        return replace(run, parameters=parameters)


class ExactPlanner(Planner):
    """An exact planner: deterministic (its route takes no seed), no optimizer, constructed
    without arguments; :meth:`plan` gives the route's cells (or :class:`UsvError`). It takes no
    variant unless it lists one in ``variants`` (the built-ins take ``+s``). A plugin registers
    a subclass under the entry-point group ``usvtool.planners`` (:data:`EXACT`)."""

    seeded = False


class AnyAngle(ExactPlanner):
    """The exact any-angle shortest route (:func:`usvtool.plan.exact.any_angle`)."""

    name = "anyangle"
    variants = (shorten.SUFFIX,)

    def plan(self, request: Request) -> Planned:
        p = request.problem
        cells = exact.any_angle(p.checker, p.grid.blocked, request.start, request.goal)
        return Planned(_found(self.name, cells), {"delta_cells": exact.DELTA})


class AStar(ExactPlanner):
    """The 8-connected A* route (:func:`usvtool.plan.exact.astar`)."""

    name = "astar"
    variants = (shorten.SUFFIX,)

    def plan(self, request: Request) -> Planned:
        cells = exact.astar(request.problem.grid.blocked, request.start, request.goal)
        return Planned(_found(self.name, cells), {})


def _found(name: str, cells: np.ndarray | None) -> np.ndarray:
    if cells is None:  # connectivity was checked: an exact planner must find a route
        raise UsvError(f"{name}: no route found between start and goal")
    return cells


class Variant(Planner):
    """A planner wrapping another (``inner``), named after it with ``suffix``."""

    suffix: str = ""

    def __init__(self, inner: Planner):
        self.inner = inner
        self.name = inner.name + self.suffix
        self.seeded = inner.seeded
        self.guided = inner.guided
        self.optimizer = inner.optimizer

    @classmethod
    def of(cls, inner: Planner, algo: str) -> Variant:
        """The variant of ``inner``, or :class:`UsvError` when it does not take it (``algo``
        named)."""
        if cls.suffix not in inner.variants:
            has = ", ".join(inner.variants) or "none"
            raise UsvError(f"{algo!r}: {inner.name} has no {cls.suffix} variant (its variants: "
                           f"{has})")  # fmt: skip
        return cls(inner)

    @property
    def default_waypoints(self) -> int | str:
        return self.inner.default_waypoints

    def problem_waypoints(self, waypoints: int | str) -> int:
        return self.inner.problem_waypoints(waypoints)


class Shortened(Variant):
    """``+s``: the inner planner's route shortened (:func:`usvtool.plan.shorten.shorten`)."""

    suffix = shorten.SUFFIX

    def plan(self, request: Request) -> Planned:
        planned = self.inner.plan(request)
        cells = shorten.shorten(request.problem.checker, planned.cells)
        return replace(planned, cells=cells, parameters={**planned.parameters, "shorten": True})


class Guided(Variant):
    """``+g``: the optimizer on the route-guided problem (waypoints about the stations of the
    exact any-angle route; ``waypoints="auto"``: K from the route)."""

    suffix = guided.SUFFIX

    def __init__(self, inner: Planner):
        super().__init__(inner)
        self.guided = True

    @property
    def default_waypoints(self) -> int | str:
        return guided.AUTO

    def problem_waypoints(self, waypoints: int | str) -> int:
        return 1  # the guided problem places its own waypoints

    def plan(self, request: Request) -> Planned:
        problem, o = request.problem, request.options
        checker = problem.checker
        route = exact.any_angle(checker, problem.grid.blocked, request.start, request.goal)
        station = guided.stations(checker, route, request.waypoints)
        clear = guided.clear_of_corners(checker, station)
        searched = (guided.GuidedProblem(problem, station) if clear is None
                    else guided.GuidedProblem(problem, clear, margin=True))  # fmt: skip
        if searched.waypoints:
            run = optimize(searched, self.optimizer, o)
        else:  # a straight station route: nothing to search
            run = Planned(searched.station, {})
        cells, kept = guided.settle(route, searched.station, run.cells)
        if not is_collision_free(problem.grid, problem.to_map(cells), checker):
            cells, kept = searched.station, True  # free in cells, not once in map metres
        parameters = {**run.parameters, "encoding": "guided", "turn_weight": o.turn_weight,
                      "waypoints": searched.waypoints, "guide_vertices": len(route),
                      "station_route": kept}  # fmt: skip
        return replace(run, cells=cells, parameters=parameters)


#: Every exact planner (:class:`ExactPlanner` classes) by name: the built-ins, then the
#: ``usvtool.planners`` plugins of that base (the group the optimizers' registry shares).
EXACT = Registry("exact planner", ExactPlanner, "usvtool.planners",
                 lambda cls: no_suffix(cls) or ("is seeded: an exact planner takes no seed"
                                                if cls.seeded else None),
                 shares=OPTIMIZERS)  # fmt: skip
for _cls in (AnyAngle, AStar):
    EXACT.register(_cls)
#: The variant suffixes and the wrappers they stand for.
VARIANTS: dict[str, type[Variant]] = {v.suffix: v for v in (Shortened, Guided)}


def planners() -> dict[str, Planner]:
    """Every base planner by name: the optimizers registered now, then the exact planners."""
    return {**{name: Optimize(cls) for name, cls in OPTIMIZERS.items()},
            **{name: cls() for name, cls in EXACT.items()}}  # fmt: skip


def names() -> list[str]:
    """Every base ``algo`` name, without the variant suffixes."""
    return [*OPTIMIZERS, *EXACT]


def split_algorithm(algo: str) -> tuple[str, str]:
    """``(base, suffix)`` of an ``algo`` name: ``("iwso", "+g")``, ``("astar", "")``.

    >>> split_algorithm("iwso+g"), split_algorithm("anyangle+s"), split_algorithm("gwo")
    (('iwso', '+g'), ('anyangle', '+s'), ('gwo', ''))
    """
    for suffix in VARIANTS:
        if algo.endswith(suffix):
            return algo[: -len(suffix)], suffix
    return algo, ""


def unknown(algo: str) -> str:
    """The refusal of an unknown ``algo`` name, listing the known ones."""
    return (f"unknown algorithm {algo!r} (known: {', '.join(names())}, each also with "
            f"{' or '.join(VARIANTS)})")  # fmt: skip


def resolve(algo: str) -> Planner:
    """The planner ``algo`` names (a base name, with at most one suffix of :data:`VARIANTS`);
    :class:`UsvError` for an unknown name or a variant its base has not got."""
    base, suffix = split_algorithm(algo)
    planner = planners().get(base)
    if planner is None:
        raise UsvError(unknown(algo))
    return VARIANTS[suffix].of(planner, algo) if suffix else planner


def optimize(problem: PathProblem | guided.GuidedProblem, optimizer: type[Optimizer],
             options: PlanOptions) -> Planned:  # fmt: skip
    """Minimise ``problem`` with ``optimizer``: up to ``options.attempts`` independent runs,
    stopping at the first whose best route is collision-free (else keeping the lowest-cost
    route).

    Why restarts: a population-based search converges on one basin per run, and on a hard
    chart a faithful optimizer's run can end in a colliding basin (docs/planning.md has the
    rates). Independent runs are the standard remedy (MoveIt's planning attempts; multi-start
    in the metaheuristics literature); they leave every run the published algorithm. Run 1
    uses ``seed`` itself, so ``attempts=1`` and the first attempt give the same route as
    before; run ``k`` > 1 uses child ``k - 2`` of ``SeedSequence(seed).spawn``, so the result
    depends on the seed alone.

    Returns the route's cells, its run's convergence (metres), the optimizer's parameters with
    ``attempts``, and the 1-based number of the run that gave the route.
    """
    o = options
    search = problem.search()
    children = np.random.SeedSequence(o.seed).spawn(o.attempts - 1)
    seeds = [o.seed, *(np.random.default_rng(child) for child in children)]
    best = None
    for attempt, run_seed in enumerate(seeds, start=1):
        try:
            run = optimizer(o.pop, o.iters, run_seed, **(o.params or {}))
        except ValueError as exc:
            raise UsvError(str(exc)) from None
        result = run.minimize(search, search.lower, search.upper)
        cells = problem.decode(search.to_problem(result.x))[0]
        fitness = float(problem.cost(cells[None], exact=True)[0])
        found = (fitness, cells, (result.history * search.unit).tolist(), result.params, attempt)
        if not problem.checker.collides(cells[:-1], cells[1:]).any():
            best = found  # free: kept even if a colliding run cost less (a free detour > S)
            break
        if best is None or fitness < best[0]:
            best = found
    _, cells, convergence, parameters, attempt = best
    return Planned(cells, {**parameters, "attempts": o.attempts}, convergence, attempt)
