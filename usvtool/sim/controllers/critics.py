"""The critics: the named terms a controller scores the rollouts of a step with.

Each critic gives every rollout a reward (larger is better); the core normalises it by its sum
over the candidates (the UDWA paper's eqs. 2-4) and adds it with the critic's ``scale`` (eq. 1,
IWSO-DWA eqs. 21 and 25), as Nav2's DWB sums its critics' scaled scores. A critic's ``name`` is
the term's, and its scale the controller's parameter ``w_<name>``.

- :class:`Velocity` (``velocity``): the sampled speed, or in weather the speed made good
  (IWSO-DWA eq. 21's vel, UDWA eq. 5);
- :class:`GoalHeading` (``heading``): pi less the misalignment with the goal where the rollout
  comes closest to it (Fox et al.'s heading, eq. 21's head);
- :class:`SubgoalHeading` (``heading``): pi less the misalignment of the final heading with the
  bearing to the sub-goal (IWSO-DWA eqs. 22-23);
- :class:`Distance` (``distance``): the clearance over the horizon, capped (eq. 21's dist);
- :class:`SubgoalPath` (``path``): the largest distance to the sub-goal over the samples less the
  rollout's (IWSO-DWA eq. 24).
"""

from __future__ import annotations

import functools
from abc import ABC, abstractmethod

import numpy as np


def heading_reward(off: np.ndarray, reached: np.ndarray) -> np.ndarray:
    """A heading critic's reward from the angle ``off`` (unwrapped) between the heading and the
    bearing: ``pi - |wrap_pi(off)|``, ``pi`` where the rollout reaches the goal; compiled
    (:func:`usvtool.sim.rollout_kernels.heading_reward`)."""
    return _kernels().heading_reward(np.ascontiguousarray(off, float), reached)


@functools.cache
def _kernels():
    """:mod:`usvtool.sim.rollout_kernels`, imported at the first call (numba's import: a run's,
    not the command line's) and then at the cost of a cached call, not an import's
    microseconds, every step."""
    from usvtool.sim import rollout_kernels

    return rollout_kernels


class Critic(ABC):
    """A scored term: ``scale`` times its normalised :meth:`reward`."""

    name: str = ""

    def __init__(self, scale: float):
        self.scale = scale
        self.world = None

    def reset(self, world) -> None:
        """Start a run in ``world`` (:class:`usvtool.sim.controllers.base.World`)."""
        self.world = world

    @abstractmethod
    def reward(self, own, r) -> np.ndarray:
        """The reward of every rollout of ``r`` (:class:`~usvtool.sim.controllers.base.Rollouts`)
        for the own ship ``own``, ``(N,)``."""


class Velocity(Critic):
    """The speed term: the sampled speed, or with ``weather`` the speed it makes good in the wind
    and waves at its final position (UDWA eq. 5) on its final heading."""

    name = "velocity"

    def __init__(self, scale: float, weather: bool):
        super().__init__(scale)
        self.weather = weather

    def reward(self, own, r) -> np.ndarray:
        world = self.world
        if not self.weather or world.weather is None:
            return r.v
        # the final positions as the rows of the rollouts (contiguous: the kernel takes them
        # as they are), the values of r.end's parts
        return world.weather.attainable_speed(
            r.v, r.psi_end, r.x[-1], r.y[-1], world.vessel.deadweight
        )


class GoalHeading(Critic):
    """Fox et al.'s heading term toward the goal, taken where the rollout comes closest to it
    (its end, unless it passes the goal on the way): pi less the angle between the heading there
    and the bearing from there to the goal; pi for a rollout that reaches the goal. Taken at the
    end, the rollouts of a ship near the goal end beyond it looking away, and the best score goes
    to turning back: with a 10 s horizon the ship circled the goal."""

    name = "heading"

    def reset(self, world) -> None:
        super().reset(world)
        self.goal = float(world.goal[0]), float(world.goal[1])

    def reward(self, own, r) -> np.ndarray:
        north, east = _kernels().offsets(r.near, *self.goal)  # from the closest points to the goal
        return heading_reward(np.arctan2(north, east) - r.psi_near, r.reached)  # the angle


class Distance(Critic):
    """The clearance term: the smallest distance to the grid or a target over the horizon, capped
    at ``cap`` (the controller's ``dist_max``): beyond it nothing near matters."""

    name = "distance"

    def __init__(self, scale: float, cap: float):
        super().__init__(scale)
        self.cap = cap

    def reward(self, own, r) -> np.ndarray:
        return np.minimum(np.maximum(r.clearance, 0.0), self.cap)  # np.clip's, less its dispatch


class RouteProgress:
    """The sub-goal along the global route: the first vertex not yet reached (within ``reach``
    metres, by default the distance the ship covers in one horizon at full speed) or passed (the
    own ship's projection on the leg beyond it); the goal once the route is done. Without a
    route the route is the straight line to the goal."""

    def __init__(self, reach: float | None, horizon: float):
        self.reach_param, self.horizon = reach, horizon

    def reset(self, world) -> None:
        route = world.route if world.route is not None else np.zeros((1, 2))
        self.route = np.vstack([route, world.goal])  # the goal closes the route
        self.next = min(1, len(self.route) - 1)
        reach = self.reach_param
        self.reach = reach if reach is not None else world.vessel.max_speed * self.horizon
        self._last = None  # (own, sub-goal) of the last call

    def subgoal(self, own) -> np.ndarray:
        """The current sub-goal, advancing past the vertices reached or passed (the same for
        the same state ``own``, once worked out: the step's critics share it)."""
        if self._last is not None and self._last[0] is own:
            return self._last[1]
        sub = self._advance(own)
        self._last = own, sub
        return sub

    def _advance(self, own) -> np.ndarray:
        here = np.array([own.x, own.y])
        while self.next < len(self.route) - 1:
            a, b = self.route[self.next - 1], self.route[self.next]
            leg = b - a
            passed = np.dot(here - a, leg) >= np.dot(leg, leg)
            if np.linalg.norm(b - here) > self.reach and not passed:
                break
            self.next += 1
        return self.route[self.next]


class _SubgoalCritic(Critic):
    """A critic of the sub-goal of ``progress`` (shared by the critics of one controller)."""

    def __init__(self, scale: float, progress: RouteProgress):
        super().__init__(scale)
        self.progress = progress

    def reset(self, world) -> None:
        super().reset(world)
        self.progress.reset(world)


class SubgoalHeading(_SubgoalCritic):
    """IWSO-DWA's ``head'`` (eq. 23): ``|theta_c - theta_st|``, theta_c the bearing from the own
    ship to the sub-goal (eq. 22, whose "tan" is read as ``atan2``), theta_st the rollout's final
    heading; as a reward pi less it, pi for a rollout that reaches the goal (its end may lie
    beyond it, looking away)."""

    name = "heading"

    def reward(self, own, r) -> np.ndarray:
        sub = self.progress.subgoal(own)
        theta_c = np.arctan2(sub[1] - own.y, sub[0] - own.x)  # eq. 22
        return heading_reward(theta_c - r.psi_end, r.reached)


class SubgoalPath(_SubgoalCritic):
    """IWSO-DWA's ``path`` (eq. 24): the distance from the rollout's point closest to the
    sub-goal (the end of a rollout through the sub-goal lies beyond it); as a reward, the largest
    over the samples less it."""

    name = "path"

    def reward(self, own, r) -> np.ndarray:
        sub = self.progress.subgoal(own)
        if sub[0] == self.world.goal[0] and sub[1] == self.world.goal[1]:
            to_sub = r.to_goal  # the route done (or none): the goal's, worked out already
        else:
            to_sub = _kernels().closest(r.x, r.y, float(sub[0]), float(sub[1]))[1]
        path = np.sqrt(to_sub)  # eq. 24
        return path.max() - path
