"""The trajectory generators: which velocities a step samples and how each is rolled out.

A generator is the window strategy of a controller (its ``window`` parameter names one, as
Nav2's DWB names its trajectory generator): it samples the dynamic window
(:func:`usvtool.sim.vessel.window` and :func:`~usvtool.sim.vessel.samples`), rolls the samples
out (:class:`usvtool.sim.vessel.Fan`), and answers what the rest of the step asks of the
rollouts: the heading and the distance run at a time, and the command for the next control
period once a sample is chosen.

- ``period`` (:class:`PeriodWindow`): what one control period's accelerations reach (IWSO-DWA
  eq. 19 with the control period, Fox et al. 1997), every sample held from now on on exact arcs
  (eq. 16). As DWB's ``LimitedAccelGenerator`` (its ``use_dwa: true``).
- ``horizon`` (:class:`HorizonWindow`): what they reach within the horizon, each rollout
  approaching its sample at the limits and then holding it (trajectory rollout, Gerkey and
  Konolige 2008; DWB's ``StandardTrajectoryGenerator``), the command the ramp's first period.
"""

from __future__ import annotations

import functools

import numpy as np

from usvtool.sim import vessel as vessel_model


@functools.cache
def _kernels():
    """:mod:`usvtool.sim.rollout_kernels`, imported at the first call (numba's import: a run's,
    not the command line's) and then at the cost of a cached call, not an import's
    microseconds, every step."""
    from usvtool.sim import rollout_kernels

    return rollout_kernels


class PeriodWindow:
    """The dynamic window of one control period (see the module docstring)."""

    name = "period"
    #: the kernels of a step (:mod:`usvtool.sim.rollout_kernels`), loaded at the controller's reset
    kernels = ("period_sweep",)

    def __init__(self, world, times: np.ndarray):
        self.vessel, self.period, self.times = world.vessel, world.period, times
        self.span = world.period  # eq. 19's Delta t
        vessel = self.vessel
        #: the vessel's limits as :func:`usvtool.sim.rollout_kernels.window_axes` takes them
        self.limits = np.array([vessel.min_speed, vessel.max_speed, vessel.max_decel,
                                vessel.max_accel, vessel.max_yaw_rate, vessel.max_yaw_accel],
                               float)  # fmt: skip

    def sample(self, own, n_v: int, n_omega: int) -> tuple[np.ndarray, np.ndarray,
                                                           vessel_model.Fan]:  # fmt: skip
        """The step's samples, the pairs ``(v, omega)`` of :meth:`axes` (the speed varying
        slowest), and their rollouts (:meth:`fan`): the window and its axes in one compiled
        call (:func:`usvtool.sim.rollout_kernels.window_axes`)."""
        speeds, rates, v, omega = _kernels().window_axes(float(own.v), float(own.omega),
                                                         self.limits, float(self.span), n_v,
                                                         n_omega)  # fmt: skip
        return v, omega, self.fan(own, speeds, rates)

    def sweep(self, own, n_v: int, n_omega: int, targets: tuple, checks: tuple,
              goal: tuple[float, float]) -> tuple:  # fmt: skip
        """The step's samples rolled out and checked (:meth:`sample`, then
        :func:`usvtool.sim.rollout_kernels.sweep` of the fan with the ``targets``' positions,
        velocities and lengths, the run's ``checks`` and the ``goal``), all in one compiled call
        (:func:`usvtool.sim.rollout_kernels.period_sweep`): ``(v, omega, x, y, contact,
        static_first, clearance, intrudes, row, to_goal, near)``."""
        return _kernels().period_sweep(float(own.x), float(own.y), float(own.psi), float(own.v),
                                       float(own.omega), self.limits, float(self.span), n_v,
                                       n_omega, self.times, *targets, *checks,
                                       *goal)  # fmt: skip

    def axes(self, own, n_v: int, n_omega: int) -> tuple[np.ndarray, np.ndarray]:
        """The window's grid (:func:`usvtool.sim.vessel.samples`) as its speeds and yaw rates."""
        win = vessel_model.window(self.vessel, own.v, own.omega, self.span)
        return vessel_model.samples(win, n_v, n_omega, current=(own.v, own.omega))

    def fan(self, own, speeds: np.ndarray, rates: np.ndarray) -> vessel_model.Fan:
        return vessel_model.arcs(own.x, own.y, own.psi, speeds, rates, self._step(),
                                 self.times.size)  # fmt: skip

    def heading(self, own, omega: np.ndarray, t) -> np.ndarray:
        """The rollouts' headings at time ``t`` (rad, not wrapped)."""
        return own.psi + omega * t

    def run(self, own, v: np.ndarray, t) -> np.ndarray:
        """The distance the rollouts have run by time ``t``."""
        return v * t

    def command(self, own, v: float, omega: float) -> tuple[float, float]:
        """The velocity pair for the next period once sample ``(v, omega)`` is chosen."""
        return v, omega

    def _step(self) -> float:
        return float(self.times[0])


class HorizonWindow(PeriodWindow):
    """The trajectory-rollout window of the horizon (see the module docstring)."""

    name = "horizon"
    kernels = ("horizon_sweep", "toward_one", "travelled")

    def __init__(self, world, times: np.ndarray):
        super().__init__(world, times)
        self.span = float(times[-1])

    def fan(self, own, speeds: np.ndarray, rates: np.ndarray) -> vessel_model.Fan:
        return vessel_model.ramps(own.x, own.y, own.psi, own.v, own.omega, speeds, rates,
                                  self.vessel, self._step(), self.times.size)  # fmt: skip

    def sweep(self, own, n_v: int, n_omega: int, targets: tuple, checks: tuple,
              goal: tuple[float, float]) -> tuple:  # fmt: skip
        """:meth:`PeriodWindow.sweep` of the ramps (:meth:`sample` and the checks), in one
        compiled call (:func:`usvtool.sim.rollout_kernels.horizon_sweep`)."""
        return _kernels().horizon_sweep(float(own.x), float(own.y), float(own.psi), float(own.v),
                                        float(own.omega), self.limits, float(self.span), n_v,
                                        n_omega, self.times, *targets, *checks,
                                        *goal)  # fmt: skip

    def heading(self, own, omega: np.ndarray, t) -> np.ndarray:
        """The heading turned while the yaw rate ramps toward the sample's."""
        yaw = self.vessel.max_yaw_accel
        return own.psi + vessel_model.travelled(own.omega, omega, yaw, yaw, t)

    def run(self, own, v: np.ndarray, t) -> np.ndarray:
        """The distance run on the speed's ramp."""
        vessel = self.vessel
        return vessel_model.travelled(own.v, v, vessel.max_decel, vessel.max_accel, t)

    def command(self, own, v: float, omega: float) -> tuple[float, float]:
        """The first period of the ramp toward the sample."""
        vessel, dt = self.vessel, self.period
        return (
            float(vessel_model.toward(own.v, v, vessel.max_decel, vessel.max_accel, dt)),
            float(vessel_model.toward(own.omega, omega, vessel.max_yaw_accel,
                                      vessel.max_yaw_accel, dt)),
        )  # fmt: skip


#: The generators by the ``window`` parameter's value.
WINDOWS: dict[str, type[PeriodWindow]] = {w.name: w for w in (PeriodWindow, HorizonWindow)}
