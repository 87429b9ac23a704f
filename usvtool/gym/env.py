"""The Gymnasium environment: usvtool's scenes, stepped by an agent (docs/gym.md).

An episode is a :class:`usvtool.sim.run.Voyage`, the run ``usvtool simulate`` makes, with the
agent's actions in the controller's place: :meth:`UsvEnv.reset` draws the scene (a scenario
file of a list, or a scene of a family) from the environment's seeded generator and starts its
voyage; :meth:`UsvEnv.step` clips the action into the dynamic window
(:func:`usvtool.sim.observation.command`), advances the voyage one ``sim.dt`` and observes it
(:class:`usvtool.sim.observation.Observer`, which the ``policy`` controller uses too).
"""

from __future__ import annotations

import math
import shutil
import tempfile
import weakref
from collections import OrderedDict
from collections.abc import Mapping, Sequence
from pathlib import Path

import gymnasium
import numpy as np
from gymnasium import spaces

from usvtool.encounter import CLASS_NAMES
from usvtool.errors import UsvError
from usvtool.gym import reward as terms
from usvtool.gym.reward import Reward
from usvtool.sim import verdicts
from usvtool.sim.observation import Layout, Observer, command
from usvtool.sim.run import start_voyage
from usvtool.sim.scenario import read_scenario
from usvtool.sim.vessel import vessel_from

#: Scenes a family's environment keeps read (their files in its folder), the last used kept.
CACHED_SCENES = 32


class UsvEnv(gymnasium.Env):
    """usvtool's scenes as a Gymnasium environment (docs/gym.md).

    From scenario files, ``UsvEnv("charts/scenarios/emergency-crossing.yaml")`` or a list of
    them (one drawn per episode), or from a scene family, ``UsvEnv(family="emergency",
    kind="head-on")``: ``kind`` one kind, a list of kinds or None (all the family's), drawn per
    episode, ``options`` the family's options (docs/families.md), ``scenes`` the scene numbers
    drawn from (``N``: 0 to N - 1; a sequence: those; a family that is not seeded has scene 0
    only). ``layout`` the observation's (:class:`usvtool.sim.observation.Layout`), ``reward``
    its weights (:class:`usvtool.gym.reward.Reward`), ``seed``: the voyage's (the targets'
    noise) is drawn from the environment's generator too.

    ``reset(seed=..., options={"kind": K, "scene": N})`` (a family) or ``options={"scenario":
    I}`` (the I-th file) starts that scene instead of a drawn one.
    """

    metadata = {"render_modes": []}

    def __init__(self, scenario: str | Path | Sequence[str | Path] | None = None, *,
                 family: str | None = None, kind: str | Sequence[str] | None = None,
                 options: Mapping | None = None, scenes: int | Sequence[int] = 100,
                 layout: Layout | None = None, reward: Reward | None = None,
                 render_mode: str | None = None):  # fmt: skip
        if (scenario is None) == (family is None):
            raise UsvError("UsvEnv: give a scenario file (or a list of them) or a family")
        if render_mode is not None:
            raise UsvError(f"UsvEnv: no render mode, not {render_mode!r}")
        self.render_mode = None
        self.layout, self.weights = layout or Layout(), reward or Reward()
        self._dir: Path | None = None
        self._cache: OrderedDict = OrderedDict()
        self._written = 0
        if family is not None:
            from usvtool.sim.families import family as get_family

            self.family = get_family(family)
            kinds = self.family.kinds if kind is None else [kind] if isinstance(kind, str) \
                else list(kind)  # fmt: skip
            for k in kinds:
                if k not in self.family.kinds:
                    raise UsvError(f"UsvEnv: family {family} has no kind {k!r} (kinds: "
                                   f"{', '.join(self.family.kinds)})")  # fmt: skip
            self.kinds = tuple(kinds)
            numbers = range(scenes) if isinstance(scenes, int) else list(scenes)
            self.scenes = tuple(numbers) if self.family.seeded else (0,)
            if not self.kinds or not self.scenes:
                raise UsvError("UsvEnv: no kind or no scene to draw from")
            self.options = dict(options or {})
            self._dir = Path(tempfile.mkdtemp(prefix="usvtool-gym-"))
            self._finalizer = weakref.finalize(self, shutil.rmtree, self._dir, True)
            probe = [self._scene(self.kinds[0], self.scenes[0])]
            self.files = ()
        else:
            if options is not None or kind is not None:
                raise UsvError("UsvEnv: kind and options are a family's")
            paths = [scenario] if isinstance(scenario, str | Path) else list(scenario)
            if not paths:
                raise UsvError("UsvEnv: no scenario file")
            self.family, self.kinds, self.scenes, self.options = None, (), (), {}
            self.files = tuple(Path(p) for p in paths)
            probe = [self._file(i) for i in range(len(self.files))]
        vessels = [vessel_from(s.own.vessel, s.own.overrides, f"{s.path}: own") for s in probe]
        low = [min(v.min_speed for v in vessels), -max(v.max_yaw_rate for v in vessels)]
        high = [max(v.max_speed for v in vessels), max(v.max_yaw_rate for v in vessels)]
        #: (v, omega): m/s through the water and rad/s, positive to port; float64, the
        #: simulator's numbers (each step clips it into the episode vessel's window)
        self.action_space = spaces.Box(np.array(low), np.array(high), dtype=np.float64)
        obs_low, obs_high = self.layout.bounds()
        self.observation_space = spaces.Box(obs_low, obs_high, dtype=np.float32)
        self.voyage = self.observer = self.view = self.scenario = None

    # -- the scenes --------------------------------------------------------------------------

    def _file(self, i: int):
        key = ("file", i)
        if key not in self._cache:
            self._cache[key] = read_scenario(self.files[i])
        return self._cache[key]

    def _scene(self, kind: str, scene: int):
        """The scenario of scene ``scene`` of ``kind``, written in the environment's folder as
        ``usvtool simulate --family`` writes it, read back (the last :data:`CACHED_SCENES`
        kept, the others' files removed)."""
        from usvtool.sim.families import scene_files, write_scene

        key = (kind, scene)
        if key in self._cache:
            self._cache.move_to_end(key)
            return self._cache[key][0]
        made = self.family.scene(kind, scene, self.options)
        self._written += 1
        path = self._dir / f"scene-{self._written}.yaml"
        write_scene(made, path)
        self._cache[key] = (read_scenario(path), scene_files(made, path))
        while len(self._cache) > CACHED_SCENES:
            _, (_, files) = self._cache.popitem(last=False)
            for f in files:
                f.unlink(missing_ok=True)
        return self._cache[key][0]

    # -- the episode -------------------------------------------------------------------------

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        rng, options = self.np_random, dict(options or {})
        if self.family is not None:
            kind = options.pop("kind", None)
            scene = options.pop("scene", None)
            kind = self.kinds[int(rng.integers(len(self.kinds)))] if kind is None else kind
            scene = self.scenes[int(rng.integers(len(self.scenes)))] if scene is None else scene
            self.scenario = self._scene(kind, int(scene))
        else:
            i = options.pop("scenario", None)
            i = int(rng.integers(len(self.files))) if i is None else int(i)
            self.scenario = self._file(i)
        if options:
            raise UsvError(f"UsvEnv.reset: unknown option(s) {sorted(options)}")
        #: the voyage's seed (the targets' noise), drawn: usvtool simulate --seed's
        self.voyage_seed = int(rng.integers(2**31))
        self.voyage = start_voyage(self.scenario, self.voyage_seed)
        world = self.voyage.world
        self.observer = Observer(world, self.layout)
        self._dist = self._to_goal()
        self._dist0 = max(self._dist, self.scenario.sim.goal_tolerance)
        return self._observe(), self._info()

    def step(self, action):
        voyage = self.voyage
        if voyage is None or voyage.over:
            raise UsvError("UsvEnv.step: the episode is over (or not started): reset first")
        try:
            a_v, a_omega = (float(a) for a in action)
        except (TypeError, ValueError):
            a_v = a_omega = math.nan
        if not (math.isfinite(a_v) and math.isfinite(a_omega)):
            raise ValueError(f"an action is two finite numbers (v, omega), not {action!r}")
        own, targets, encounter = self.view
        world, w = voyage.world, self.weights
        vessel, dt = world.vessel, world.period
        v, omega = command(vessel, own, dt, a_v, a_omega)
        colregs = terms.violation(encounter, own, targets, vessel, dt, v, omega)
        voyage.advance(v, omega)
        dist = self._to_goal()
        parts = {
            "progress": w.progress * (self._dist - dist) / self._dist0,
            "domain": -w.domain * dt * terms.intrusion(voyage.x, voyage.y, voyage.psi,
                                                       voyage.ahead[voyage.step], vessel.length),
            "shore": 0.0,
            "colregs": -w.colregs * dt * colregs,
            "collision": -w.collision if voyage.collision is not None else 0.0,
            "arrival": w.arrival if voyage.arrived else 0.0,
            "verdict": 0.0,
        }  # fmt: skip
        if world.clearance is not None:
            c = float(world.clearance.at(np.array([voyage.x]), np.array([voyage.y]))[0])
            parts["shore"] = -w.shore * dt * max(0.0, 1.0 - c / vessel.length)
        self._dist = dist
        obs = self._observe()
        terminated = voyage.arrived or voyage.collision is not None
        truncated = voyage.over and not terminated
        info = self._info()
        if voyage.over:
            judged = self.verdicts()
            parts["verdict"] = -w.verdict * judged["non_compliant"]
            info.update(arrived=voyage.arrived, collision=None if voyage.collision is None
                        else ("map" if voyage.collision == -1
                              else self.scenario.targets[voyage.collision].name),
                        verdicts=judged)  # fmt: skip
        info["reward"] = parts
        return obs, float(sum(parts.values())), terminated, truncated, info

    def verdicts(self) -> dict:
        """The COLREGs verdicts of the run so far (:func:`usvtool.sim.verdicts.evaluate` on its
        trace, no Rule 2 records): the encounters ``judged``, ``compliant``, ``non_compliant``
        (what the reward's ``verdict`` term counts)."""
        voyage = self.voyage
        events = verdicts.evaluate(voyage.trace(), [voyage.vessel.length, *voyage.lengths],
                                   [])["events"]  # fmt: skip
        judged = [e["compliant"] for e in events if e["compliant"] is not None]
        return {"judged": len(judged), "compliant": sum(judged),
                "non_compliant": len(judged) - sum(judged)}  # fmt: skip

    def close(self):
        if self._dir is not None:
            self._finalizer()
            self._dir = None
        super().close()

    # -- helpers ------------------------------------------------------------------------------

    def _to_goal(self) -> float:
        goal = self.voyage.world.goal
        return math.hypot(self.voyage.x - goal[0], self.voyage.y - goal[1])

    def _observe(self) -> np.ndarray:
        #: what a controller sees at the current step (own, targets, encounter): the view the
        #: observation is made of, and a controller's decide() may take
        self.view = self.voyage.observe()
        return self.observer(*self.view)

    def _info(self) -> dict:
        encounter = self.view[2]
        return {"time": self.voyage.time, "step": self.voyage.step,
                "scenario": self.scenario.name,
                "encounter": CLASS_NAMES[0] if encounter is None else encounter.cls,
                "nearest_m": self.observer.nearest}  # fmt: skip
