"""The own ship: its limits, kinematics (IWSO eq. 16) and dynamic window (IWSO eqs. 18–20).

Conventions (see docs/vessel.md): map metres, x east, y north, seconds. Inside the code
headings ``psi`` are mathematical radians, counter-clockwise from +x (east), and yaw rates
``omega`` rad/s with the same sign: ``omega > 0`` turns to port, a starboard turn is
``omega < 0`` (the UDWA paper calls ``omega > 0`` starboard: it counts clockwise). Users give
speeds in m/s and angular figures in degrees (deg/s, deg/s²): :func:`vessel_from` converts them
once. Equation numbers are those of the IWSO-DWA paper (``/work/shared/papers/000_*``).

Everything is vectorised: :func:`arcs` (and :func:`ramps`) move every velocity sample of the
window's grid over a horizon of ``steps`` periods, the work per yaw rate or speed in NumPy, the
positions in a compiled loop (:mod:`usvtool.sim.rollout_kernels`).

>>> ship = preset("udwa-usv")
>>> ship.max_speed, round(math.degrees(ship.max_yaw_rate), 9)
(7.0, 20.0)
>>> w = window(ship, 3.0, 0.0, 0.5)  # eq. 19: 3 ± 2 m/s² · 0.5 s, 0 ± 5 deg/s² · 0.5 s
>>> w.v_lo, w.v_hi, round(math.degrees(w.omega_hi), 9)
(2.0, 4.0, 2.5)
"""

from __future__ import annotations

import functools
import math
import numbers
from dataclasses import dataclass, fields
from typing import NamedTuple

import numpy as np

from usvtool.angles import wrap_pi
from usvtool.errors import UsvError

# The vessel's fields in user units, as presets and scenario overrides give them.
USER_UNITS = {
    "length": "m",
    "beam": "m",
    "deadweight": "t",
    "min_speed": "m/s",
    "max_speed": "m/s",
    "max_accel": "m/s^2",
    "max_decel": "m/s^2",
    "max_yaw_rate": "deg/s",
    "max_yaw_accel": "deg/s^2",
}
_DEGREES = ("max_yaw_rate", "max_yaw_accel")

PRESETS: dict[str, dict[str, float | None]] = {
    # IWSO-DWA paper (000), section 5.2, "the parameters of the DWA part". Its angular figures
    # are printed in "rad/s" and "rad/s²" but are degrees (60 rad/s is 9.5 turns a second).
    "iwso-dwa-usv": {
        "length": 2.5,  # not in the paper: the ISSA paper's YL-2500 (usvtool's --ship-length)
        "beam": 1.0,  # not in the paper
        "deadweight": None,  # not in the paper
        "min_speed": 1.0,  # v_min = 1 m/s
        "max_speed": 5.0,  # v_max = 5 m/s
        "max_accel": 0.7,  # v'_e = 0.7 m/s²
        "max_decel": 0.8,  # v'_f = 0.8 m/s²
        "max_yaw_rate": 60.0,  # ω_max = 60 "rad/s" = 60 deg/s; its ω_min = 10 is not a bound
        "max_yaw_accel": 75.0,  # ω'_e = 75 "rad/s²" = 75 deg/s² (ω'_f = 80: the lower one kept)
    },
    # UDWA paper (004), Table 3 "USV motion parameters".
    "udwa-usv": {
        "length": 15.0,  # not in the paper: a boat of about 20 t
        "beam": 4.5,  # not in the paper
        "deadweight": 20.0,  # "Deadweight of the ship 20 t"
        "min_speed": 0.0,  # "Minimum movement speed 0 m/s"
        "max_speed": 7.0,  # "Maximum movement speed 7 m/s"
        "max_accel": 2.0,  # "maximum acceleration 2 m/s²"
        "max_decel": 2.0,  # not in the paper: taken equal to the acceleration
        "max_yaw_rate": 20.0,  # "Maximum angular velocity ±20 deg/s"
        "max_yaw_accel": 5.0,  # "Maximum angular acceleration ±5 deg/s²"
    },
}


@dataclass(frozen=True)
class Vessel:
    """A ship's dimensions and motion limits, in SI units and radians.

    ``length``, ``beam`` (m), ``deadweight`` (t, or None when unknown), ``min_speed`` (>= 0) and
    ``max_speed`` (m/s), ``max_accel`` and ``max_decel`` (m/s², both > 0), ``max_yaw_rate``
    (rad/s: yaw rates lie in ``[-max_yaw_rate, max_yaw_rate]``) and ``max_yaw_accel`` (rad/s²,
    for speeding up and slowing down the turn alike). Build one from user units (degrees) with
    :func:`vessel_from`; a bad figure raises :class:`UsvError` naming the field.
    """

    length: float
    beam: float
    deadweight: float | None
    min_speed: float
    max_speed: float
    max_accel: float
    max_decel: float
    max_yaw_rate: float
    max_yaw_accel: float

    def __post_init__(self):
        _check(self.__dict__, "vessel")

    def user_units(self) -> dict[str, float | None]:
        """The figures in user units (degrees for the yaw limits), as :func:`vessel_from` takes
        them."""
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        for name in _DEGREES:
            out[name] = math.degrees(out[name])
        return out


def vessel_from(preset: str | None, overrides: dict | None = None, where: str = "vessel") -> Vessel:
    """A vessel from a preset name and inline ``overrides`` in user units (:data:`USER_UNITS`).

    With ``preset=None`` every field but ``deadweight`` must be given. Errors are one line
    starting with ``where`` (e.g. ``"scenario.yaml: own.vessel"``).

    >>> vessel_from("udwa-usv", {"max_speed": 5}).max_speed
    5.0
    >>> vessel_from("udwa-usv", {"max_yaw_rate": 0}, "s.yaml: own.vessel")
    Traceback (most recent call last):
    usvtool.errors.UsvError: s.yaml: own.vessel: max_yaw_rate must be > 0, not 0
    """
    overrides = dict(overrides or {})
    if preset is None:
        base: dict = {}
    elif preset in PRESETS:
        base = PRESETS[preset]
    else:
        raise UsvError(
            f"{where}: unknown vessel preset {preset!r} (known: {', '.join(sorted(PRESETS))})"
        )
    unknown = sorted(set(overrides) - set(USER_UNITS), key=str)
    if unknown:
        raise UsvError(
            f"{where}: unknown vessel field(s) {', '.join(map(repr, unknown))} "
            f"(known: {', '.join(USER_UNITS)})"
        )
    values = {"deadweight": None, **base, **overrides}
    missing = [name for name in USER_UNITS if name not in values]
    if missing:
        raise UsvError(f"{where}: no preset, so {', '.join(missing)} must be given")
    _check(values, where)
    values = {k: None if values[k] is None else float(values[k]) for k in USER_UNITS}
    for name in _DEGREES:
        values[name] = math.radians(values[name])
    return Vessel(**values)


def preset(name: str) -> Vessel:
    """The preset vessel ``name`` (:data:`PRESETS`)."""
    return vessel_from(name, {}, "vessel")


def _check(values: dict, where: str) -> None:
    """Refuse a non-number, NaN, infinite, zero or negative figure, naming it."""
    for name in USER_UNITS:
        value = values[name]
        if name == "deadweight" and value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise UsvError(f"{where}: {name} must be a number, not {value!r}")
        x = float(value)
        if math.isinf(x):
            raise UsvError(f"{where}: {name} must be finite, not {value}")
        if name == "min_speed":
            if not x >= 0:
                raise UsvError(f"{where}: {name} must be >= 0, not {value}")
        elif not x > 0:
            raise UsvError(f"{where}: {name} must be > 0, not {value}")
    if values["min_speed"] > values["max_speed"]:
        raise UsvError(
            f"{where}: min_speed ({values['min_speed']}) must not exceed "
            f"max_speed ({values['max_speed']})"
        )


# -- kinematics (eq. 16) ----------------------------------------------------------------------


def step(x, y, psi, v, omega, dt):
    """The pose after one period ``dt`` at constant ``(v, omega)``: eq. 16 integrated exactly.

    The ship runs an arc of radius ``v / omega`` (a straight line when ``omega = 0``): its chord
    has length ``v·dt·sinc(omega·dt / 2)`` and the direction ``psi + omega·dt / 2``. All arguments
    broadcast; the heading returned is wrapped into ``[-π, π)``.

    >>> [round(float(a), 6) for a in step(0.0, 0.0, 0.0, 2.0, math.pi / 2, 1.0)]  # r = 4/π
    [1.27324, 1.27324, 1.570796]
    """
    x, y, psi, v, omega = (np.asarray(a, float) for a in (x, y, psi, v, omega))
    turn = omega * dt
    chord = v * dt * np.sinc(turn / (2 * np.pi))  # np.sinc(t) = sin(πt) / (πt)
    mid = psi + turn / 2
    x, y, psi = np.broadcast_arrays(x + chord * np.cos(mid), y + chord * np.sin(mid), psi + turn)
    return x, y, wrap_pi(psi)


#: ``np.sinc``'s stand-in for a zero argument (the machine epsilon of float64); the compiled
#: fan (:func:`usvtool.sim.rollout_kernels.arc_fan`) takes it too.
SINC_ZERO = float(np.finfo(float).eps)


def step_one(x: float, y: float, psi: float, v: float, omega: float,
             dt: float) -> tuple[float, float, float]:  # fmt: skip
    """:func:`step` of one pose in Python floats (the own ship's step of a run): the same
    operations in the same order, ``np.sinc``'s ``sin(y) / y`` of ``y = pi t`` (its epsilon
    for ``y = 0``) and :func:`~usvtool.angles.wrap_pi`'s wrap, so the same bits, without the
    arrays' cost (0.3 us a step against 10).

    >>> step_one(0.0, 0.0, 0.0, 2.0, math.pi / 2, 1.0) == tuple(
    ...     float(a) for a in step(0.0, 0.0, 0.0, 2.0, math.pi / 2, 1.0))
    True
    """
    turn = omega * dt
    arg = math.pi * (turn / (2 * math.pi))
    arg = arg if arg != 0.0 else SINC_ZERO
    chord = v * dt * (math.sin(arg) / arg)
    mid = psi + turn / 2
    heading = (psi + turn + math.pi) % (2 * math.pi) - math.pi
    return x + chord * math.cos(mid), y + chord * math.sin(mid), heading


class Fan(NamedTuple):
    """The rollouts of a grid of velocity samples: every speed of ``speeds`` ``(V,)`` with every
    yaw rate of ``rates`` ``(R,)``, pair ``i·R + k`` the speed ``i`` and the rate ``k`` (the order
    of :func:`samples`), at ``t = dt, 2·dt, …`` (the start pose not included). Time-major:
    row ``j`` is the time ``(j + 1)·dt`` of every rollout, so the reductions over the horizon run
    along contiguous rows."""

    x: np.ndarray  # (steps, V·R) the predicted positions, east
    y: np.ndarray  # (steps, V·R) and north
    u: np.ndarray  # (steps, R) complex: each period's unit chord direction, per yaw rate
    radius: np.ndarray  # (steps,) the farthest any rollout is from the start at each time


def arcs(x0, y0, psi0, speeds, rates, dt: float, steps: int) -> Fan:
    """The rollouts of the samples held for ``steps`` periods: eq. 16 integrated exactly.

    Each period's exact chord (:func:`step`: length ``v·dt·sinc(omega·dt / 2)``, direction
    ``psi0 + omega·dt·(j - 1/2)`` in period ``j``) is summed, the directions by repeated complex
    multiplication, once per yaw rate: two complex exponentials per rate rather than
    transcendental functions at every step (each costs as much as a dozen multiplications). The
    chord's length is constant along a rollout, so the positions are it times the summed unit
    chords. ``np.sinc`` is exact at ``omega = 0`` (a straight line) and loses no precision near it.
    All of it in one compiled pass (:func:`usvtool.sim.rollout_kernels.arc_fan`, whose products
    are the same bits on every CPU).

    >>> fan = arcs(0, 0, 0, [1.0], [0.0, math.pi], 0.5, 2)  # straight on; half a circle
    >>> fan.x.round(6).tolist(), fan.y.round(6).tolist()
    ([[0.5, 0.31831], [1.0, 0.0]], [[0.0, 0.31831], [0.0, 0.63662]])
    """
    speeds, rates = _grid_axes(speeds, rates)
    u = np.empty((steps, rates.size), complex)
    x, y = np.empty((2, steps, speeds.size * rates.size))
    radius = _kernels().arc_fan(float(x0), float(y0), float(psi0), np.ascontiguousarray(speeds),
                     np.ascontiguousarray(rates), float(dt), u, x, y)  # fmt: skip
    return Fan(x, y, u, radius)


def toward(now, target, down, up, t):
    """The value that starts at ``now`` and moves toward ``target`` at ``down`` (per second,
    when falling) or ``up`` (when rising) for ``t`` seconds, then holds it. Arrays broadcast.

    >>> toward(2.0, np.array([7.0, 0.0, 2.5]), 1.0, 2.0, 1.0).tolist()
    [4.0, 1.0, 2.5]
    """
    compiled = _kernels()  # one compiled pass for the terms
    if isinstance(now, float) and isinstance(target, float) and isinstance(t, float):
        return compiled.toward_one(now, target, down, up, t)  # a ufunc's call costs 3 us
    # the NumPy ufunc under numba's (frozen: its one loop, the same) without its Python call
    return compiled.toward.ufunc(now, target, down, up, t)


def travelled(now, target, down, up, t):
    """The integral over ``[0, t]`` of :func:`toward`: the distance run (or the angle turned) by
    a speed (a yaw rate) ramping from ``now`` toward ``target``. Arrays broadcast.

    >>> travelled(3.0, np.array([7.0, 7.0]), 2.0, 2.0, np.array([1.0, 3.0])).tolist()  # 2 s ramp
    [4.0, 17.0]
    """
    return _kernels().travelled.ufunc(now, target, down, up, t)  # as toward's


def ramps(x0, y0, psi0, v0, omega0, speeds, rates, vessel: Vessel, dt: float, steps: int) -> Fan:
    """The rollouts of a trajectory-rollout window: each sample commanded now, the ship
    accelerating from ``(v0, omega0)`` toward it at her limits (:func:`toward`: ``max_accel`` /
    ``max_decel``, ``max_yaw_accel``), then holding it (Gerkey and Konolige 2008; ROS
    base_local_planner with ``dwa: false``).

    Each period's chord comes from the speed and the heading at its middle (the midpoint rule:
    exact for constant velocities, second order in ``dt`` while they change); the headings and
    the distance run at any time are exact, :func:`travelled`. The speeds' ramps are worked out
    once per speed, the headings once per yaw rate.

    >>> ship = preset("udwa-usv")  # 2 m/s²: 3 m/s rising to 7 in 2 s, straight on
    >>> ramps(0, 0, 0, 3.0, 0.0, [7.0], [0.0], ship, 0.5, 5).x.round(6).T.tolist()
    [[1.75, 4.0, 6.75, 10.0, 13.5]]
    """
    speeds, rates = _grid_axes(speeds, rates)
    t_mid = _midpoints(dt, steps)
    chord = dt * toward(v0, speeds, vessel.max_decel, vessel.max_accel, t_mid)  # (steps, V)
    turned = travelled(omega0, rates, vessel.max_yaw_accel, vessel.max_yaw_accel, t_mid)
    u = np.exp(1j * (psi0 + turned))  # (steps, R)
    x, y = np.empty((2, steps, speeds.size * rates.size))
    radius = _kernels().ramp_points(float(x0), float(y0), chord, u, x, y)
    return Fan(x, y, u, radius)


@functools.lru_cache(maxsize=16)
def _midpoints(dt: float, steps: int) -> np.ndarray:
    """The periods' middles ``(steps, 1)`` of :func:`ramps` (read-only: a run's every step
    shares them)."""
    t_mid = dt * (np.arange(steps) + 0.5)[:, None]
    t_mid.flags.writeable = False
    return t_mid


def _grid_axes(speeds, rates) -> tuple[np.ndarray, np.ndarray]:
    if _is_axis(speeds) and _is_axis(rates):  # a step's, from the window: as they are
        return speeds, rates
    return np.atleast_1d(np.asarray(speeds, float)), np.atleast_1d(np.asarray(rates, float))


def _is_axis(a) -> bool:
    """``a`` is a contiguous float64 vector (what :func:`_grid_axes` would make of it)."""
    return type(a) is np.ndarray and a.dtype == np.float64 and a.ndim == 1 and \
        a.flags.c_contiguous  # fmt: skip


# -- the dynamic window (eqs. 18-20) ----------------------------------------------------------


class Window(NamedTuple):
    """The velocities reachable in the next control period (m/s and rad/s)."""

    v_lo: float
    v_hi: float
    omega_lo: float
    omega_hi: float


def window(vessel: Vessel, v, omega, dt: float) -> Window:
    """The dynamic window: eq. 18 (absolute limits) intersected with eq. 19 (one period's
    acceleration).

    ``v ∈ [v - max_decel·dt, v + max_accel·dt] ∩ [min_speed, max_speed]`` and
    ``omega ∈ [omega - max_yaw_accel·dt, omega + max_yaw_accel·dt] ∩ [-max_yaw_rate,
    max_yaw_rate]``. When the current velocity lies so far outside the limits that the two do
    not meet (a ship at rest whose ``min_speed`` is above what one period's acceleration gives),
    the window shrinks to the reachable value nearest the limits: each limit is clipped into the
    reachable interval. Arrays broadcast.

    >>> window(preset("udwa-usv"), 7.0, 0.0, 0.25)[:2]  # at full speed: no faster
    (6.5, 7.0)
    >>> window(preset("iwso-dwa-usv"), 0.0, 0.0, 0.5)[:2]  # at rest, min_speed 1 out of reach
    (0.35, 0.35)
    """
    if not dt > 0:
        raise ValueError("dt must be > 0")
    scalar = isinstance(v, float) and isinstance(omega, float)
    if not scalar:
        v, omega = np.asarray(v, float), np.asarray(omega, float)
    v_down, v_up = v - vessel.max_decel * dt, v + vessel.max_accel * dt
    w_down, w_up = omega - vessel.max_yaw_accel * dt, omega + vessel.max_yaw_accel * dt

    def clip(limit, lo, hi):  # NumPy's dispatch costs more than the work on one ship's floats
        return min(max(limit, lo), hi) if scalar else _out(np.minimum(np.maximum(limit, lo), hi))

    return Window(
        clip(vessel.min_speed, v_down, v_up),
        clip(vessel.max_speed, v_down, v_up),
        clip(-vessel.max_yaw_rate, w_down, w_up),
        clip(vessel.max_yaw_rate, w_down, w_up),
    )


def admissible(v, omega, dist, vessel: Vessel) -> np.ndarray:
    """Eq. 20, the braking constraint: can the ship stop before the nearest obstacle?

    ``dist`` is the free distance (m) along the predicted trajectory to the nearest obstacle
    (``inf`` when there is none; negative or NaN counts as 0). Linear part, as printed:
    ``v <= sqrt(2·dist·max_decel)``. The printed angular part ``omega <= sqrt(2·dist·omega'_f)``
    mixes metres and radians; we read ``dist`` there as the angle the ship still turns through
    before the obstacle, ``dist·|omega| / v``, which gives ``|omega|·v <= 2·dist·max_yaw_accel``:
    braking along its arc, the ship must slow its turn at ``|omega| / v`` times its
    deceleration (docs/vessel.md). Arrays broadcast; returns a bool mask.

    >>> ship = preset("udwa-usv")  # max_decel 2 m/s², max_yaw_accel 5 deg/s²; 4 m to go
    >>> admissible([4.0, 4.1, 3.0, 3.0], np.radians([0, 0, 13, 14]), 4.0, ship).tolist()
    [True, False, True, False]
    """
    v = np.asarray(v, float)
    omega = np.asarray(omega, float)
    dist = np.fmax(np.asarray(dist, float), 0.0)  # NaN (e.g. 0 m/s times an infinite time) -> 0
    linear = v <= np.sqrt(2 * dist * vessel.max_decel)
    angular = np.abs(omega * v) <= 2 * dist * vessel.max_yaw_accel
    return linear & angular


#: Relative to the window's width: sample values this close to zero are zero (round-off).
ZERO_TOLERANCE = 1e-9


def samples(win: Window, n_v: int, n_omega: int, current=None) -> tuple[np.ndarray, np.ndarray]:
    """The velocities to evaluate: a regular ``n_v × n_omega`` grid over the window, as its two
    axes ``(speeds, rates)``, each sorted with no repeats; the samples are every pair of them
    (:class:`Fan`: the speed varying slowest).

    Both axes include the window's edges. When ``current = (v, omega)`` is given, its speed and
    yaw rate join the axes if they lie in the window (so holding course and speed is a
    candidate); a zero yaw rate (straight on) joins the yaw axis whenever the window holds it.

    >>> speeds, rates = samples(Window(1.0, 2.0, -0.2, 0.4), 2, 2)
    >>> speeds.tolist(), rates.tolist()
    ([1.0, 2.0], [-0.2, 0.0, 0.4])
    """
    if n_v < 2 or n_omega < 2:
        raise ValueError("samples: n_v and n_omega must be >= 2 (the grid includes both edges)")
    v_lo, v_hi, w_lo, w_hi = (float(a) for a in win)
    v_now, w_now = (None, None) if current is None else (float(a) for a in current)
    return _axis(v_lo, v_hi, n_v, [v_now]), _axis(w_lo, w_hi, n_omega, [0.0, w_now])


def _axis(lo: float, hi: float, n: int, extra) -> np.ndarray:
    """``n`` values from ``lo`` to ``hi`` and the ``extra`` ones inside, sorted, no repeats.

    Values within round-off of zero (``linspace`` gives -2.8e-17 for a zero between its edges)
    are zero: a yaw rate's sign is the side it turns to, and straight on must not count as a
    starboard turn.

    >>> float(np.linspace(-0.3, 0.2, 6)[3]), float(_axis(-0.3, 0.2, 6, [0.0])[3])
    (5.551115123125783e-17, 0.0)
    """
    inside = np.array([e for e in extra if e is not None], float)
    return _kernels().axis(float(lo), float(hi), int(n), inside, ZERO_TOLERANCE * (hi - lo))


def _out(a: np.ndarray):
    return float(a) if a.ndim == 0 else a


@functools.cache
def _kernels():
    """:mod:`usvtool.sim.rollout_kernels`, imported at the first call (numba's import: a run's,
    not the command line's) and then at the cost of a cached call, not an import's
    microseconds, every step."""
    from usvtool.sim import rollout_kernels

    return rollout_kernels
