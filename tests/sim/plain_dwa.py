"""The plain way: one velocity sample at a time, as PythonRobotics' ``dynamic_window_approach``
writes it (a Python loop over the samples, each trajectory stepped in a loop).

An independent oracle for the vectorised core of :mod:`usvtool.sim.controllers.base` (the tests
compare their choices) and the benchmark's baseline (benchmarks/bench_simulate.py). It shares
nothing with the core but the sample list and the grid's clearance lookup: its own stepping of
the arcs with ``math``, its own contact test, terms and normalisation, written from the
definitions in the core's docstring.
"""

from __future__ import annotations

import math


def choose(own, targets, samples, *, goal, length, times, weights, clearance=None):
    """(index of the chosen sample, its score, contact time per sample) for the ``dwa`` objective
    (speed, heading to the goal where the rollout comes closest to it, clearance capped at
    ``weights['dist_max']``; no goal tolerance, no domain), or the fallback
    when every sample meets a contact (longest contact time, then most starboard, then slowest;
    admissibility is left out: the tests build cases where it does not decide)."""
    dt = times[1] - times[0]
    rows = []
    for v, omega in samples:
        x, y, psi = own.x, own.y, own.psi
        contact, gap = math.inf, math.inf
        near = (math.inf, 0.0, 0.0, 0.0)  # distance to the goal, x, y, heading there
        for t in times:
            turn = omega * dt
            chord = v * dt * (math.sin(turn / 2) / (turn / 2) if turn else 1.0)
            x += chord * math.cos(psi + turn / 2)
            y += chord * math.sin(psi + turn / 2)
            psi += turn
            here = math.inf if clearance is None else clearance(x, y) - length / 2
            for (px, py), (vx, vy), other in zip(targets.pos, targets.vel, targets.length,
                                                 strict=True):  # fmt: skip
                d = math.hypot(x - (px + vx * t), y - (py + vy * t)) - (length + other) / 2
                here = min(here, d)
            gap = min(gap, here)
            if here <= 0 and contact == math.inf:
                contact = t
            to_goal = math.hypot(goal[0] - x, goal[1] - y)
            if to_goal < near[0]:
                near = (to_goal, x, y, psi)
        _, nx, ny, npsi = near  # the heading term where the rollout comes closest to the goal
        bearing = math.atan2(goal[1] - ny, goal[0] - nx)
        off = (bearing - npsi + math.pi) % (2 * math.pi) - math.pi
        dist = min(max(gap, 0.0), weights["dist_max"])
        rows.append((v, omega, contact, math.pi - abs(off), dist))
    free = [i for i, r in enumerate(rows) if r[2] == math.inf]
    if not free:
        best = min(range(len(rows)), key=lambda i: (-rows[i][2], rows[i][1], rows[i][0]))
        return best, None, [r[2] for r in rows]
    sums = [sum(rows[i][k] for i in free) for k in (0, 3, 4)]
    best, best_score = None, -math.inf
    for i in free:
        v, _, _, head, dist = rows[i]
        score = sum(
            w * value / total if total > 0 else 0.0
            for w, value, total in zip(
                (weights["w_velocity"], weights["w_heading"], weights["w_distance"]),
                (v, head, dist), sums, strict=True,
            )
        )  # fmt: skip
        if score > best_score:
            best, best_score = i, score
    return best, best_score, [r[2] for r in rows]
