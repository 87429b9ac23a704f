"""What a learned policy sees and may command: the observation of a control step as one flat
``float32`` vector, and the command clipped to what the vessel reaches in one period.

Gymnasium-free (NumPy only): the environment :mod:`usvtool.gym` builds its observations with
:class:`Observer`, and the ``policy`` controller (:mod:`usvtool.sim.controllers.policy`) builds
the same ones from the same :class:`~usvtool.sim.controllers.Own`,
:class:`~usvtool.sim.controllers.Targets` and :class:`~usvtool.sim.controllers.Encounter` that
every controller gets, so a policy trained in the environment steers ``usvtool simulate``'s
runs as it steered the episodes. What a controller sees, no more: no time, no future positions.

Units. ``D = max_speed * time_scale`` (m, :attr:`Layout.time_scale` = 30 s at full speed) for
distances, ``max_speed`` for speeds, ``max_yaw_rate`` for yaw rates, the own ship's length for
lengths; positions and velocities in the own ship's frame: ``fwd`` along her heading, ``left``
to port (the mathematical convention of the simulation: a positive yaw rate turns to port).
Every feature is clipped into its bounds (:meth:`Layout.bounds`), which the environment's
``observation_space`` states.

The vector (``K`` = :attr:`Layout.targets` slots, 3 by default; 38 values then):

====================  =====  ==================================================================
feature               size   value (bounds)
====================  =====  ==================================================================
speed                 1      ``v / max_speed`` (0, 1): the speed through the water last commanded
yaw rate              1      ``omega / max_yaw_rate`` (-1, 1)
goal bearing          2      cos and sin of the goal's bearing from the heading (-1, 1; sin > 0:
                             to port)
goal distance         1      ``distance / D`` (0, 10)
target slots          7 K    the ``K`` targets nearest by centre distance, nearest first (ties:
                             the lower index first); each ``mask`` (1 for a target, 0 for an
                             empty slot, its other values 0), ``fwd / D`` and ``left / D`` of
                             its position (-10, 10), ``fwd`` and ``left`` of its velocity
                             relative to the own ship's (target's minus own) over
                             ``max_speed`` (-10, 10), its length over the own ship's (0, 20),
                             and ``urgent`` (1 for the target of the encounter below, else 0)
encounter             6      one-hot of the most urgent latched encounter's class, ``none``
                             first (:data:`usvtool.encounter.CLASS_NAMES`: none, head-on,
                             crossing-give-way, crossing-stand-on, overtaking, overtaken)
map clearance         6      the map's clearance (:class:`usvtool.clearance.Clearance`: the
                             distance to the nearest obstacle or margin cell) over ``C =
                             max_speed * clearance_scale`` (10 s at full speed), capped at 1,
                             at the own ship and at the points ``max_speed * probe_time`` (5 s
                             at full speed) ahead at -60, -30, 0, 30, 60 deg from her heading
                             (positive to port); all 1 on open water (0, 1)
====================  =====  ==================================================================

>>> from usvtool.sim.controllers import Encounter, Own, Targets, World
>>> from usvtool.sim.vessel import preset
>>> world = World(preset("udwa-usv"), np.array([420.0, 0.0]))  # heading east, the goal ahead
>>> obs = Observer(world)(Own(0.0, 0.0, 0.0, 7.0, 0.0), Targets(np.array([[105.0, 0.0]]),
...     np.array([[-7.0, 0.0]]), np.array([15.0])), Encounter("head-on", 0))
>>> obs.shape, obs[:5].tolist(), obs[5:12].tolist()
((38,), [1.0, 0.0, 1.0, 0.0, 2.0], [1.0, 0.5, 0.0, -2.0, 0.0, 1.0, 1.0])
>>> obs[26:32].tolist(), obs[32:].tolist()  # head-on; open water
([0.0, 1.0, 0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 1.0, 1.0, 1.0, 1.0])
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from usvtool.encounter import CLASS_NAMES

#: The observation's format; a stored policy (.npz) records it with its layout.
VERSION = 1
#: Values of one target slot: mask, position fwd and left, relative velocity fwd and left,
#: length ratio, urgent.
SLOT = 7
#: Relative bearings (deg, positive to port) of the clearance probes ahead.
PROBE_BEARINGS_DEG = (-60.0, -30.0, 0.0, 30.0, 60.0)
_CLASS_INDEX = {name: i for i, name in enumerate(CLASS_NAMES)}


@dataclass(frozen=True)
class Layout:
    """The observation's shape and scales: ``targets`` slots; distances in ``time_scale``
    seconds at full speed, clearances in ``clearance_scale`` seconds, the probes
    ``probe_time`` seconds ahead."""

    targets: int = 3
    time_scale: float = 30.0
    clearance_scale: float = 10.0
    probe_time: float = 5.0

    def __post_init__(self):
        if isinstance(self.targets, bool) or not isinstance(self.targets, int) \
                or self.targets < 0:  # fmt: skip
            raise ValueError(f"targets must be an integer >= 0, not {self.targets!r}")
        for name in ("time_scale", "clearance_scale", "probe_time"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a finite number > 0, not {value!r}")

    @property
    def size(self) -> int:
        """The vector's length: 5 + 7 K + 6 + 6."""
        return 5 + SLOT * self.targets + len(CLASS_NAMES) + 1 + len(PROBE_BEARINGS_DEG)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """``(low, high)`` of every feature (``float32``), the table of the module docstring."""
        slot_low = [0.0, -10.0, -10.0, -10.0, -10.0, 0.0, 0.0]
        slot_high = [1.0, 10.0, 10.0, 10.0, 10.0, 20.0, 1.0]
        n_map = 1 + len(PROBE_BEARINGS_DEG)
        low = [0.0, -1.0, -1.0, -1.0, 0.0, *slot_low * self.targets,
               *[0.0] * len(CLASS_NAMES), *[0.0] * n_map]  # fmt: skip
        high = [1.0, 1.0, 1.0, 1.0, 10.0, *slot_high * self.targets,
                *[1.0] * len(CLASS_NAMES), *[1.0] * n_map]  # fmt: skip
        return np.array(low, np.float32), np.array(high, np.float32)

    def to_dict(self) -> dict:
        return {"version": VERSION, **asdict(self)}

    @classmethod
    def from_dict(cls, d: dict) -> Layout:
        """The layout a policy was trained with (``ValueError`` for another format)."""
        d = dict(d)
        version = d.pop("version", None)
        if version != VERSION:
            raise ValueError(f"observation version {version!r}, not {VERSION} (this usvtool's)")
        return cls(**d)


class Observer:
    """The observations of one run in ``world`` (a :class:`~usvtool.sim.controllers.World`),
    laid out as ``layout`` says: ``observer(own, targets, encounter)`` is the vector."""

    def __init__(self, world, layout: Layout | None = None):
        self.world, self.layout = world, layout or Layout()
        vessel = world.vessel
        lay = self.layout
        self.size = lay.size
        self.low, self.high = lay.bounds()
        self._speed = float(vessel.max_speed)
        self._yaw = float(vessel.max_yaw_rate)
        self._per_d = 1.0 / (vessel.max_speed * lay.time_scale)
        self._per_speed = 1.0 / vessel.max_speed
        self._per_length = 1.0 / vessel.length
        self._goal = (float(world.goal[0]), float(world.goal[1]))
        self._clearance = world.clearance
        self._per_c = 1.0 / (vessel.max_speed * lay.clearance_scale)
        self._probe = vessel.max_speed * lay.probe_time
        self._probe_angles = np.radians(np.array(PROBE_BEARINGS_DEG))
        self._enc = 5 + SLOT * lay.targets  # where the encounter's one-hot starts
        self._map = self._enc + len(CLASS_NAMES)

    def __call__(self, own, targets, encounter=None) -> np.ndarray:
        # Python floats: on a few targets each NumPy call costs more than all the arithmetic
        x, y, psi, v = float(own.x), float(own.y), float(own.psi), float(own.v)
        c, s = math.cos(psi), math.sin(psi)
        per_d, per_speed = self._per_d, self._per_speed
        gx, gy = self._goal[0] - x, self._goal[1] - y
        dist = math.hypot(gx, gy)
        out = [v / self._speed, float(own.omega) / self._yaw,
               (gx * c + gy * s) / dist if dist > 0 else 1.0,
               (gy * c - gx * s) / dist if dist > 0 else 0.0,
               min(dist * per_d, 10.0)]  # fmt: skip
        k = self.layout.targets
        pos = targets.pos.tolist()
        #: the nearest target's centre distance (m; inf without targets), for the env's info
        self.nearest = math.inf
        if pos:
            ranges = [(px - x) * (px - x) + (py - y) * (py - y) for px, py in pos]
            order = sorted(range(len(pos)), key=ranges.__getitem__)  # stable: ties by index
            self.nearest = math.sqrt(ranges[order[0]])
            vel, length = targets.vel.tolist(), targets.length.tolist()
            urgent = -1 if encounter is None else encounter.target
            ux0, uy0 = v * c, v * s
            for j in order[:k]:
                dx, dy = pos[j][0] - x, pos[j][1] - y
                ux, uy = vel[j][0] - ux0, vel[j][1] - uy0
                out += [1.0, _clip((dx * c + dy * s) * per_d, 10.0),
                        _clip((dy * c - dx * s) * per_d, 10.0),
                        _clip((ux * c + uy * s) * per_speed, 10.0),
                        _clip((uy * c - ux * s) * per_speed, 10.0),
                        min(length[j] * self._per_length, 20.0), 1.0 if j == urgent else 0.0]
        out += [0.0] * (self._enc - len(out))  # the empty slots
        onehot = [0.0] * len(CLASS_NAMES)
        onehot[0 if encounter is None else _CLASS_INDEX[encounter.cls]] = 1.0
        out += onehot
        if self._clearance is None:
            out += [1.0] * (1 + len(PROBE_BEARINGS_DEG))
        else:
            a = psi + self._probe_angles
            px = np.concatenate([[x], x + self._probe * np.cos(a)])
            py = np.concatenate([[y], y + self._probe * np.sin(a)])
            out += np.minimum(self._clearance.at(px, py) * self._per_c, 1.0).tolist()
        return np.array(out, np.float32)


def _clip(value: float, bound: float) -> float:
    """``value`` within ``[-bound, bound]``."""
    return -bound if value < -bound else bound if value > bound else value


def command(vessel, own, period: float, v: float, omega: float) -> tuple[float, float]:
    """``(v, omega)`` clipped into what the vessel reaches in one ``period`` from ``own``'s
    speed and yaw rate (the dynamic window, :func:`usvtool.sim.vessel.window`'s bounds: her
    limits intersected with one period's accelerations; tests/gym/test_policy.py compares).
    The simulator applies a command as given (:meth:`usvtool.sim.run.Voyage.advance`), so the
    environment and the ``policy`` controller clip here; a command inside the window (every DWA
    controller's) is returned as it is.

    >>> from usvtool.sim.controllers import Own
    >>> from usvtool.sim.vessel import preset
    >>> command(preset("udwa-usv"), Own(0, 0, 0, 7.0, 0.0), 0.1, 0.0, 1.0)
    (6.8, 0.008726646259971648)
    """
    # vessel.window's bounds, its very expressions, in Python floats (its call costs more)
    now, turn, dt = float(own.v), float(own.omega), float(period)
    v_down, v_up = now - vessel.max_decel * dt, now + vessel.max_accel * dt
    w_down, w_up = turn - vessel.max_yaw_accel * dt, turn + vessel.max_yaw_accel * dt
    v_lo, v_hi = min(max(vessel.min_speed, v_down), v_up), min(max(vessel.max_speed, v_down), v_up)
    w_lo = min(max(-vessel.max_yaw_rate, w_down), w_up)
    w_hi = min(max(vessel.max_yaw_rate, w_down), w_up)
    return min(max(float(v), v_lo), v_hi), min(max(float(omega), w_lo), w_hi)
