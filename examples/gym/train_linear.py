"""Train a linear policy in usvtool's Gymnasium environment with the cross-entropy method,
NumPy only, seeded: the example of docs/gym.md, whose result usvtool ships as the ``policy``
controller's default (usvtool/sim/controllers/linear_policy.npz).

The policy is ``tanh(W obs + b)``: its two outputs in [-1, 1] are the speed (from the vessel's
``min_speed`` to ``max_speed``) and the yaw rate (times ``max_yaw_rate``), the ``.npz`` format
of :class:`usvtool.sim.controllers.policy.NetworkPolicy` (one layer). The cross-entropy method:
each iteration draws ``--population`` weight vectors from a diagonal normal, scores each by its
mean return over ``--episodes`` episodes (the same scenes for all of them in an iteration: the
environment reset with the iteration's seeds), refits the normal to the best ``--elite`` and
keeps the best mean seen. Scenes 0-99 of the family are the training scenes; evaluate on
others (docs/gym.md uses 100-106 of each kind).

    python examples/gym/train_linear.py -o usvtool/sim/controllers/linear_policy.npz

reproduces the shipped file byte for byte on the same machine (same NumPy), in about two
minutes on one core (1 min 50 s here).
"""

from __future__ import annotations

import argparse
import io
import json
import time
from pathlib import Path

import gymnasium
import numpy as np

import usvtool.gym  # noqa: F401  (registers usvtool/Encounter-v0)
from usvtool.sim.controllers.policy import NetworkPolicy


def returns(env, weights: np.ndarray, seeds: list[int]) -> float:
    """The mean return of the linear policy ``weights`` (flat: W then b) over episodes reset
    with ``seeds``."""
    base = env.unwrapped
    n_obs = base.observation_space.shape[0]
    w, b = weights[: 2 * n_obs].reshape(2, n_obs), weights[2 * n_obs:]
    total = 0.0
    for seed in seeds:
        obs, _ = env.reset(seed=seed)
        done = False
        while not done:
            out = np.tanh(w @ obs + b)
            v, omega = NetworkPolicy.command(base.voyage.vessel, out)
            obs, reward, terminated, truncated, _ = env.step((v, omega))
            total += reward
            done = terminated or truncated
    return total / len(seeds)


def save(path: Path, layout: dict, weights: np.ndarray, n_obs: int, meta: dict) -> None:
    """The policy as NetworkPolicy reads it; written in one go, its bytes a function of the
    arrays alone (np.savez stamps no time)."""
    buffer = io.BytesIO()
    np.savez(buffer, layout=np.array(json.dumps(layout, sort_keys=True)),
             W0=weights[: 2 * n_obs].reshape(2, n_obs), b0=weights[2 * n_obs:],
             training=np.array(json.dumps(meta, sort_keys=True)))  # fmt: skip
    path.write_bytes(buffer.getvalue())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", type=Path, required=True, help="the policy .npz")
    ap.add_argument("--family", default="emergency")
    ap.add_argument("--iterations", type=int, default=15)
    ap.add_argument("--population", type=int, default=20)
    ap.add_argument("--elite", type=int, default=5)
    ap.add_argument("--episodes", type=int, default=3)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--start", choices=("zero", "homing"), default="homing",
                    help="the first mean: zero weights, or a policy that heads for the goal")
    args = ap.parse_args()

    env = gymnasium.make("usvtool/Encounter-v0", family=args.family, scenes=100)
    n_obs = env.observation_space.shape[0]
    rng = np.random.default_rng(args.seed)
    mean, std = np.zeros(2 * n_obs + 2), np.full(2 * n_obs + 2, 0.5)
    if args.start == "homing":  # full speed, the yaw rate toward the goal (feature 3: the
        mean[n_obs + 3] = 3.0  # sine of the goal's bearing, positive to port)
        mean[2 * n_obs] = 3.0
    best, best_score, started = mean.copy(), -np.inf, time.perf_counter()
    for it in range(args.iterations):
        seeds = [int(s) for s in rng.integers(2**31, size=args.episodes)]
        population = mean + std * rng.standard_normal((args.population, mean.size))
        scores = np.array([returns(env, p, seeds) for p in population])
        elite = population[np.argsort(-scores, kind="stable")[: args.elite]]
        mean, std = elite.mean(axis=0), elite.std(axis=0) + 0.02
        score = returns(env, mean, seeds)
        if score > best_score:
            best, best_score = mean.copy(), score
        print(f"iteration {it + 1}: best of the population {scores.max():.3f}, mean "
              f"{scores.mean():.3f}, the elite's mean {score:.3f} "
              f"({time.perf_counter() - started:.0f} s)", flush=True)  # fmt: skip
    layout = env.unwrapped.layout.to_dict()
    meta = {"method": "cross-entropy", "family": args.family, "scenes": [0, 99],
            "iterations": args.iterations, "population": args.population, "elite": args.elite,
            "episodes": args.episodes, "seed": args.seed, "start": args.start,
            "best_score": round(best_score, 6)}
    save(args.output, layout, best, n_obs, meta)
    env.close()
    print(f"{args.output}: {args.output.stat().st_size} bytes, best mean return "
          f"{best_score:.3f}")


if __name__ == "__main__":
    main()
