"""The Gymnasium environment's speed (usvtool.gym, docs/gym.md): environment steps per second
with three targets on one core, random actions, no policy; what a step's time goes to; and the
plain way beside it.

1. ``env.step`` with random actions (uniform in the action space, drawn beforehand from a
   seeded generator, so that no agent is timed) on the ten Imazu cases with three targets
   (13-22: 180 s at 0.1 s, 1 800 steps an episode unless it ends sooner), each reset drawing a
   case, the resets and the end-of-episode verdicts included: steps per second and microseconds
   a step, on the environment itself and through ``gymnasium.make`` (its wrappers: the order
   and passive checkers). The target of issue 32 is 5 000 steps per second.
2. Its parts, per step, timed one at a time on a step of such an episode: the voyage's
   ``observe`` (of which the encounter tracker's compiled update) and ``advance`` (of which the
   collision check), the observation, the command's clip, the reward's terms; per episode, the
   verdicts at its end and a reset.
3. The plain way beside it, on the same steps: the observation by NumPy calls on the targets'
   ``(k,)`` arrays (the obvious vectorised form; its vectors are checked equal to the
   observer's, bit for bit), and the tracker's NumPy reference (``usvtool.encounter.assess``
   then ``EncounterTracker.step``, what the compiled update replaced; its latched classes are
   checked equal).

Each figure is the best of ``--runs`` runs (this shared 2-core machine's timings vary by up to
two times between runs; the best is the repeatable one).

Usage: python benchmarks/bench_gym.py [--runs 5] [--steps 20000]
"""

from __future__ import annotations

import argparse
import copy
import math
import time

import gymnasium
import numpy as np

from usvtool import encounter
from usvtool.gym import ENV_ID, UsvEnv
from usvtool.gym import reward as terms
from usvtool.sim import run as sim_run
from usvtool.sim.observation import SLOT, command

KINDS = [str(k) for k in range(13, 23)]  # the Imazu cases with three targets


def best_of(runs: int, f) -> float:
    """The smallest of ``runs`` timings (s) of ``f()``."""
    best = math.inf
    for _ in range(runs):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def stepping(env, actions: list, steps: int):
    """``steps`` steps of ``env`` (reset with seed 0 first) with ``actions`` in turn."""

    def go():
        env.reset(seed=0)
        for i in range(steps):
            *_, terminated, truncated, _ = env.step(actions[i % len(actions)])
            if terminated or truncated:
                env.reset()

    return go


def per_call(runs: int, f, n: int = 2000) -> float:
    """Microseconds a call of ``f()``, the best of ``runs`` runs of ``n`` calls."""

    def loop():
        for _ in range(n):
            f()

    return best_of(runs, loop) / n * 1e6


def plain_observation(observer, own, targets, enc) -> np.ndarray:
    """The observation by NumPy calls on the targets' arrays (the plain way)."""
    lay, vessel = observer.layout, observer.world.vessel
    per_d = 1.0 / (vessel.max_speed * lay.time_scale)
    out = np.zeros(lay.size)
    c, s = np.cos(own.psi), np.sin(own.psi)
    g = observer.world.goal - np.array([own.x, own.y])
    dist = np.hypot(*g)
    out[:5] = [own.v / vessel.max_speed, own.omega / vessel.max_yaw_rate,
               (g[0] * c + g[1] * s) / dist, (g[1] * c - g[0] * s) / dist, dist * per_d]
    d = targets.pos - np.array([own.x, own.y])
    near = np.argsort(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1], kind="stable")[: lay.targets]
    slots = out[5: 5 + SLOT * near.size].reshape(near.size, SLOT)
    dx, dy = d[near, 0], d[near, 1]
    ux, uy = targets.vel[near, 0] - own.v * c, targets.vel[near, 1] - own.v * s
    slots[:, 0] = 1.0
    slots[:, 1], slots[:, 2] = (dx * c + dy * s) * per_d, (dy * c - dx * s) * per_d
    slots[:, 3] = (ux * c + uy * s) / vessel.max_speed
    slots[:, 4] = (uy * c - ux * s) / vessel.max_speed
    slots[:, 5] = targets.length[near] / vessel.length
    slots[:, 6] = near == (-1 if enc is None else enc.target)
    start = 5 + SLOT * lay.targets
    out[start + (0 if enc is None else encounter.CLASS_NAMES.index(enc.cls))] = 1.0
    out[start + len(encounter.CLASS_NAMES):] = 1.0  # open water
    return np.clip(out, *lay.bounds()).astype(np.float32)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--steps", type=int, default=20000)
    args = ap.parse_args()
    env = UsvEnv(family="imazu", kind=KINDS)
    low, high = env.action_space.low, env.action_space.high
    draws = np.random.default_rng(0).random((4096, 2))
    actions = (low + draws * (high - low)).tolist()

    print(f"1. steps per second, 3 targets (Imazu 13-22), random actions, one core, best of "
          f"{args.runs} runs of {args.steps} steps (resets and verdicts included):")  # fmt: skip
    made = gymnasium.make(ENV_ID, family="imazu", kind=KINDS)
    for label, e in (("UsvEnv", env), ("gymnasium.make", made)):
        t = best_of(args.runs, stepping(e, actions, args.steps)) / args.steps
        print(f"   {label:15} {1 / t:8.0f} steps/s  {t * 1e6:6.1f} us a step")
    made.close()

    # 2. the parts, on step 300 of case 13 (three targets close by, encounters latched)
    env.reset(seed=0, options={"kind": "13"})
    for i in range(300):
        env.step(actions[i])
    voyage, observer = env.voyage, env.observer
    own, targets, enc = env.view
    step, vessel, world = voyage.step, voyage.vessel, voyage.world
    state = (voyage.x, voyage.y, voyage.psi, voyage.v, voyage.omega, voyage.heading,
             voyage.made_good)  # fmt: skip
    motion, times, tracker = voyage.motion, voyage.times, voyage.tracker

    def observe():
        voyage.step = step
        voyage.observe()

    def update():
        tracker.update(times[step], (voyage.x, voyage.y), voyage.heading, voyage.made_good,
                       voyage.ahead[step], motion.heading[step], motion.speed[step])  # fmt: skip

    def advance():
        (voyage.x, voyage.y, voyage.psi, voyage.v, voyage.omega, voyage.heading,
         voyage.made_good) = state  # fmt: skip
        voyage.step, voyage.collision, voyage.arrived = step, None, False
        del voyage.states[step + 1:]
        voyage.advance(own.v, own.omega)

    def collision():
        sim_run._collision(voyage.setup, (voyage.x, voyage.y), voyage.ahead[step],
                           vessel.length, voyage.lengths)  # fmt: skip

    def reward():
        terms.violation(enc, own, targets, vessel, world.period, own.v, own.omega)
        terms.intrusion(voyage.x, voyage.y, voyage.psi, voyage.ahead[step], vessel.length)

    saved = copy.deepcopy((tracker.latched, tracker.onset_t, tracker.tcpa, tracker._prev_range))
    parts = [("voyage.observe", observe), ("  of which the tracker's update", update),
             ("voyage.advance", advance), ("  of which the collision check", collision),
             ("the observation", lambda: observer(own, targets, enc)),
             ("the command's clip", lambda: command(vessel, own, world.period, 1.0, 0.0)),
             ("the reward's terms", reward)]  # fmt: skip
    print("2. a step's parts (us a call, best of runs of 2000 calls):")
    for label, f in parts:
        print(f"   {label:32} {per_call(args.runs, f):6.1f}")
    advance()  # the voyage one step on, as it was
    tracker.latched, tracker.onset_t, tracker.tcpa, tracker._prev_range = saved
    reset_ms = best_of(args.runs, lambda: env.reset(options={"kind": "13", "scene": 0})) * 1e3

    # 3. the plain way, on every step of an episode of case 13
    env.reset(seed=0, options={"kind": "13"})
    views, i, done = [], 0, False
    while not done:
        views.append(env.view)
        *_, terminated, truncated, _ = env.step(actions[i % len(actions)])
        done, i = terminated or truncated, i + 1
    verdicts_ms = best_of(args.runs, env.verdicts) * 1e3
    print(f"   per episode: the verdicts of its {env.voyage.step} steps {verdicts_ms:.1f} ms, a "
          f"reset {reset_ms:.2f} ms (its scene read before)")  # fmt: skip
    observer = env.observer
    same = all(plain_observation(observer, *v).tobytes() == observer(*v).tobytes()
               for v in views)  # fmt: skip
    fast = best_of(args.runs, lambda: [observer(*v) for v in views]) / len(views) * 1e6
    slow = best_of(args.runs, lambda: [plain_observation(observer, *v) for v in views])
    slow = slow / len(views) * 1e6
    print(f"3. the plain way, {len(views)} steps of case 13 (us a step):")
    print(f"   observation: Python floats {fast:.1f}, NumPy calls {slow:.1f} "
          f"(x {slow / fast:.1f}), the same vectors: {same}")  # fmt: skip

    def tracked(compiled: bool):
        voyage_ = sim_run.start_voyage(env.scenario, env.voyage_seed)
        own_states = env.voyage.states
        latched = []
        for n, (x, y, heading, made_good, _) in enumerate(own_states):
            args_ = (voyage_.times[n], (x, y), heading, made_good, voyage_.ahead[n],
                     voyage_.motion.heading[n], voyage_.motion.speed[n])  # fmt: skip
            if compiled:
                voyage_.tracker.update(*args_)
            else:
                s = encounter.assess(*args_[1:])
                voyage_.tracker.step(args_[0], s.cls, s.dcpa, s.tcpa, s.range)
            latched.append(voyage_.tracker.latched.copy())
        return np.array(latched)

    same = np.array_equal(tracked(True), tracked(False))
    n = len(env.voyage.states)
    fast = best_of(args.runs, lambda: tracked(True)) / n * 1e6
    slow = best_of(args.runs, lambda: tracked(False)) / n * 1e6
    print(f"   tracker (with the loop's own cost): compiled update {fast:.1f}, NumPy assess + "
          f"step {slow:.1f} (x {slow / fast:.1f}), the same classes: {same}")  # fmt: skip
    env.close()


if __name__ == "__main__":
    main()
