#!/usr/bin/env python3
"""A reference client of usvtool's process controller, protocol 1 (docs/protocol.md), in Python
with the standard library only.

    usvtool simulate charts/scenarios/env1-head-on.yaml \\
        --controller "exec:python3 examples/exec/client.py" -o trace.csv

The rule ("starboard on a close CPA"), the same as examples/exec/client.c's:

- the aim is the goal, or with a route the first of its points not yet within ``reach`` (the
  goal tolerance, at least two ship lengths) of the own ship, taken in order;
- a target is a *threat* when it is not abaft the own ship's beam by more than 22.5 degrees
  (a relative bearing within 112.5 degrees of the bow: not one overtaking her, whose give-way
  ship she is not), its closest point of approach is ahead in time (0 < tcpa <= HORIZON s) and
  closer than ``2 (L_own + L_target)`` (lengths in metres); a threat stays one until its tcpa
  is no longer positive (it has passed);
- while there is a threat the course is the bearing to the aim less TURN degrees (a turn to
  starboard: angles are counter-clockwise), otherwise the bearing to the aim; the speed is the
  vessel's top speed.

The reply is a course-and-speed reference that usvtool's autopilot tracks; with ``--velocity``
the client tracks the course itself (the same shaped proportional controller as the autopilot)
and replies with a velocity pair within the limits; with ``--trivial`` it replies with the
present speed and yaw rate (no decision: the protocol's overhead, benchmarks/bench_protocol.py).
It writes one line to its standard error at the start and one at the end (usvtool keeps them:
``--controller-log``), and exits at the end of its input.
"""

import json
import math
import sys

HORIZON = 120.0  # s: a CPA within this time can be a threat
STEP = math.radians(15.0)  # the courses tried: the aim's, then 15, 30, ... degrees to starboard
TURNS = 6  # ... up to 90 degrees
GAIN = 0.5  # 1/s: the heading controller's proportional gain (--velocity)


def threat(own, target, course, speed, own_length):
    """Whether ``target`` [x, y, vx, vy, length], not abaft the own ship's beam by more than
    22.5 degrees, comes closer than 2 (L_own + L_target) within HORIZON seconds when the own
    ship [x, y, psi, v, omega] sails ``course`` at ``speed``."""
    x, y, psi = own[0], own[1], own[2]
    px, py = target[0] - x, target[1] - y
    if abs(math.remainder(math.atan2(py, px) - psi, 2 * math.pi)) > math.radians(112.5):
        return False
    wx, wy = target[2] - speed * math.cos(course), target[3] - speed * math.sin(course)
    w2 = wx * wx + wy * wy
    if w2 < 1e-12:
        return False
    tcpa = -(px * wx + py * wy) / w2
    dcpa = math.hypot(px + tcpa * wx, py + tcpa * wy)
    return 0 < tcpa <= HORIZON and dcpa < 2 * (own_length + target[4])


def track(own, course, vessel, dt):
    """The yaw rate that turns onto ``course`` (the autopilot's shaped P controller)."""
    error = math.remainder(course - own[2], 2 * math.pi)
    accel = vessel["max_yaw_accel"]
    linear = accel / (GAIN * GAIN)
    if abs(error) <= linear:
        rate = GAIN * error
    else:
        rate = math.copysign(math.sqrt(2 * accel * (abs(error) - linear / 2)), error)
    rate = min(max(rate, -abs(error) / dt), abs(error) / dt)
    rate = min(max(rate, own[4] - accel * dt), own[4] + accel * dt)
    return min(max(rate, -vessel["max_yaw_rate"]), vessel["max_yaw_rate"])


class Client:
    def __init__(self, hello):
        self.vessel, self.dt = hello["vessel"], hello["dt"]
        self.goal = hello["goal"]
        self.route = hello["route"] or [self.goal]
        self.next = 0  # the route point aimed at
        self.reach = max(hello["goal_tolerance"], 2 * self.vessel["length"])

    def aim(self, own):
        while self.next < len(self.route) - 1:
            x, y = self.route[self.next]
            if math.hypot(x - own[0], y - own[1]) > self.reach:
                break
            self.next += 1
        return self.route[self.next]

    def decide(self, own, targets):
        ax, ay = self.aim(own)
        aim = math.atan2(ay - own[1], ax - own[0])
        speed, length = self.vessel["max_speed"], self.vessel["length"]
        for k in range(TURNS + 1):
            course = aim - k * STEP
            if not any(threat(own, t, course, speed, length) for t in targets):
                return course, speed
        return course, speed


def main(argv):
    mode = argv[1] if len(argv) > 1 else "--course"
    if mode not in ("--course", "--velocity", "--trivial"):
        sys.exit(f"client.py: unknown option {mode} (--course, --velocity or --trivial)")
    hello = json.loads(sys.stdin.readline())
    if hello.get("protocol") != 1:
        sys.exit(f"client.py: protocol {hello.get('protocol')} is not 1")
    client = Client(hello)
    print(f"client.py: protocol 1, seed {hello['seed']}, {mode[2:]} replies, goal {hello['goal']}",
          file=sys.stderr, flush=True)
    out = sys.stdout
    out.write('{"protocol":1}\n')
    out.flush()
    steps = 0
    for line in sys.stdin:
        message = json.loads(line)
        own = message["own"]
        if mode == "--trivial":
            reply = {"v": own[3], "omega": own[4]}
        else:
            course, speed = client.decide(own, message["targets"])
            if mode == "--course":
                reply = {"course": course, "speed": speed}
            else:
                v = min(speed, own[3] + client.vessel["max_accel"] * client.dt)
                v = max(v, own[3] - client.vessel["max_decel"] * client.dt)
                reply = {"v": v, "omega": track(own, course, client.vessel, client.dt)}
        out.write(json.dumps(reply) + "\n")
        out.flush()
        steps += 1
    print(f"client.py: end of input after {steps} steps", file=sys.stderr, flush=True)


if __name__ == "__main__":
    main(sys.argv)
