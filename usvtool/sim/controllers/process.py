"""``exec``: a controller that is a program of any language, run as a process speaking protocol
1 (docs/protocol.md): JSON lines over its standard input and output.

At the run's first step the controller sends the program a *hello* (the protocol's version, the
seed, the control period, the vessel's limits, the goal, the route and the map's file and
transform) and waits ``hello_deadline`` seconds for its acknowledgement; then, each control
period, one *step* message (the own ship's state, the targets as a built-in controller sees
them, the encounter that sets the side rule) and ``deadline`` seconds for one reply line: a
velocity command ``{"v", "omega"}`` within the vessel's limits, or a course-and-speed reference
``{"course", "speed"}`` that :func:`autopilot` turns into one. The end of the run is the end of
the program's input (EOF).

Anything else ends the run as *controller failed* (:class:`ControllerFailed`, one line that the
simulator prefixes with the step): no reply within the deadline (waited for with ``poll`` on the
pipe, no thread), the program gone (its exit status or signal), a reply that is not JSON or not
one of the two forms, a value that is not a finite number, or out of the vessel's limits beyond
a round-off tolerance of :data:`TOLERANCE` (relative) of the limit.

The program's standard error goes to an unnamed temporary file and is kept (its first
:data:`LOG_LIMIT` bytes) when the run ends: :meth:`ProcessController.log`, which ``usvtool
simulate`` writes to ``--controller-log FILE`` or relays on its own stderr.

:meth:`ProcessController.close` ends the program however the run ended: the end of its input
and :data:`GRACE_S` seconds to exit, then SIGTERM to its process group (the program runs in a
session of its own, so that a Ctrl-C meant for usvtool does not reach it first), :data:`GRACE_S`
seconds more, then SIGKILL; it is always waited for, so no zombie is left. A program whose
run failed (late, garbage) gets SIGTERM at once.
"""

from __future__ import annotations

import json
import math
import os
import re
import select
import shutil
import signal
import subprocess
import tempfile
import time

import numpy as np

from usvtool.errors import UsvError
from usvtool.params import POSITIVE, Param
from usvtool.sim.controllers.base import (
    Controller,
    ControllerFailed,
    Decision,
    Encounter,
    Own,
    Targets,
    World,
)
from usvtool.yamlfile import show

#: The protocol's version (docs/protocol.md): the hello's ``protocol``, which the program's
#: acknowledgement repeats.
PROTOCOL = 1
#: Relative round-off tolerance of the limit checks (a value within it of a limit is clipped to
#: the limit; beyond it the run fails).
TOLERANCE = 1e-9
#: The longest reply line (bytes): a longer one is a failure, not a memory hog.
MAX_LINE = 1 << 16
#: Bytes of the program's standard error kept (the rest is counted, not kept).
LOG_LIMIT = 1 << 20
#: Seconds the program has to exit after the end of its input, and again after SIGTERM.
GRACE_S = 1.0
#: What a run's label may be (a method's name in a pipeline and the report).
_LABEL = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$")
_ENCODE = json.JSONEncoder(separators=(",", ":"), allow_nan=False).encode


class ProcessController(Controller):
    """A program run as a process, speaking protocol 1 (the module docstring; docs/protocol.md).

    Parameters: ``command`` (the program and its arguments, a list of strings: run without a
    shell, in the current directory, a program without a ``/`` looked up on ``PATH``),
    ``deadline`` (s, per step reply, default 1), ``hello_deadline`` (s, for the hello's
    acknowledgement, which includes the program's start-up, default 10), ``heading_gain`` (1/s,
    the autopilot's, :func:`autopilot`) and ``label`` (the controller's name in the run's
    summary and events, so the method's name in the results and the report; default ``exec``).
    """

    name = "exec"
    parameters = {
        "command": Param([], "the program and its arguments (--controller exec:PROGRAM "
                         "ARGS...)", required=True),
        "deadline": Param(1.0, "seconds for each step's reply", POSITIVE),
        "hello_deadline": Param(10.0, "seconds for the hello's acknowledgement, the program's "
                                "start-up included", POSITIVE),
        "heading_gain": Param(0.5, "the autopilot's proportional gain (1/s) for course-and-"
                              "speed replies", POSITIVE),
        "label": Param("exec", "the runs' controller name: the method in the results"),
    }  # fmt: skip

    def __init__(self, **params):
        super().__init__(**params)
        p = self.params
        command = p["command"]
        if (not isinstance(command, list | tuple) or not command
                or not all(isinstance(w, str) and w and "\0" not in w for w in command)):
            raise UsvError(f"exec: command must be a non-empty list of non-empty strings, not "
                           f"{show(command)} (--controller exec:PROGRAM ARGS...)")  # fmt: skip
        p["command"] = list(command)
        label = p["label"]
        if not isinstance(label, str) or not _LABEL.match(label):
            raise UsvError(f"exec: label must be a name (letters, digits, _ . + -), not "
                           f"{show(label)}")  # fmt: skip
        from usvtool.sim.controllers import CONTROLLERS

        if label != self.name and label in CONTROLLERS:
            raise UsvError(f"exec: label {label!r} is another controller's name")
        program = command[0]
        found = shutil.which(program) if "/" not in program else (
            program if os.path.isfile(program) and os.access(program, os.X_OK) else None)
        if found is None:
            where = "on PATH" if "/" not in program else "(or not executable)"
            raise UsvError(f"exec: command: program {show(program)} not found {where}")
        self.name = label  # the run's controller, in its summary and events
        self._process: subprocess.Popen | None = None
        self._stderr = None
        self._log: str | None = None

    # -- the run ----------------------------------------------------------------------------

    def reset(self, world: World) -> None:
        """Start the program (the hello is sent with the first step, so that its failures are
        the run's, at step 0); a program that cannot start is a :class:`UsvError`."""
        self.close()
        super().reset(world)
        self._stderr = tempfile.TemporaryFile()
        try:
            self._process = subprocess.Popen(
                self.params["command"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                stderr=self._stderr, bufsize=0, close_fds=True, start_new_session=True,
            )  # fmt: skip
        except OSError as exc:
            self._stderr.close()
            self._stderr = None
            raise UsvError(f"exec: cannot run {show(self.params['command'][0])}: "
                           f"{exc.strerror or exc}") from None  # fmt: skip
        self._in, self._out = self._process.stdin.fileno(), self._process.stdout.fileno()
        os.set_blocking(self._in, False)
        os.set_blocking(self._out, False)
        self._readable, self._writable = select.poll(), select.poll()
        self._readable.register(self._out, select.POLLIN)
        self._writable.register(self._in, select.POLLOUT)
        self._buffer = b""
        self._step = 0
        self._greeted = False
        self._failed = False
        self._log = None

    def decide(self, own: Own, targets: Targets, encounter: Encounter | None = None) -> Decision:
        """Send the step, read the reply, check it (see the module docstring)."""
        try:
            if not self._greeted:
                self._hello()
            self._send(self._step_message(own, targets, encounter), self.params["deadline"])
            v, omega = self._command(self._receive(self.params["deadline"]), own)
        except ControllerFailed:
            self._failed = True
            raise
        self._step += 1
        return Decision(v, omega)

    def close(self) -> None:
        """End the program (the module docstring) and keep its standard error."""
        process, self._process = self._process, None
        if process is None:
            return
        try:
            if not self._failed:
                process.stdin.close()  # EOF: the end of the run
                try:
                    process.wait(GRACE_S)
                except subprocess.TimeoutExpired:
                    pass
            if process.poll() is None:
                _signal_group(process, signal.SIGTERM)
                try:
                    process.wait(GRACE_S)
                except subprocess.TimeoutExpired:
                    _signal_group(process, signal.SIGKILL)
                    process.wait()
        finally:
            for pipe in (process.stdin, process.stdout):
                try:
                    pipe.close()
                except OSError:
                    pass
            if process.poll() is None:  # interrupted above: never leave it running
                process.kill()
                process.wait()
            self._log = self._read_log()

    def log(self) -> str | None:
        """The program's standard error of the last run (once it has ended), None before."""
        return self._log

    # -- the protocol -----------------------------------------------------------------------

    def _hello(self) -> None:
        world = self.world
        self._send((_ENCODE(hello(world, self.params)) + "\n").encode(),
                   self.params["hello_deadline"])  # fmt: skip
        reply = self._receive(self.params["hello_deadline"], "the hello's acknowledgement")
        if reply != {"protocol": PROTOCOL}:
            raise ControllerFailed(f"{self.name}: the hello's acknowledgement must be "
                                   f'{{"protocol": {PROTOCOL}}}, not {_excerpt(reply)}')
        self._greeted = True

    def _step_message(self, own: Own, targets: Targets, encounter: Encounter | None) -> bytes:
        rows = np.column_stack([targets.pos, targets.vel, targets.length]).tolist()
        seen = "null" if encounter is None else (
            f'{{"class":"{encounter.cls}","target":{int(encounter.target)}}}')  # fmt: skip
        x, y, psi, v, omega = (float(own.x), float(own.y), float(own.psi), float(own.v),
                               float(own.omega))  # fmt: skip
        t = self._step * self.world.period
        return (f'{{"type":"step","step":{self._step},"t":{t!r},"own":[{x!r},{y!r},{psi!r},'
                f'{v!r},{omega!r}],"targets":{_ENCODE(rows)},"encounter":{seen}}}\n').encode()

    def _send(self, message: bytes, deadline: float) -> None:
        if self._buffer:
            raise ControllerFailed(f"{self.name}: it wrote more than one line for one message "
                                   f"({_excerpt(self._buffer)})")  # fmt: skip
        end = time.monotonic() + deadline
        view = memoryview(message)
        while view:
            try:
                view = view[os.write(self._in, view):]
                continue
            except BlockingIOError:
                pass
            except BrokenPipeError:
                raise ControllerFailed(f"{self.name}: {self._gone()} (its input is closed)") \
                    from None  # fmt: skip
            left = end - time.monotonic()
            if left <= 0 or not self._writable.poll(math.ceil(left * 1e3)):
                raise ControllerFailed(f"{self.name}: it read no input within its deadline of "
                                       f"{deadline:g} s")  # fmt: skip

    def _receive(self, deadline: float, what: str = "its reply"):
        """The next line, parsed; within ``deadline`` seconds."""
        end = time.monotonic() + deadline
        buffer = self._buffer
        while (cut := buffer.find(b"\n")) < 0:
            if len(buffer) > MAX_LINE:
                raise ControllerFailed(f"{self.name}: {what} is longer than {MAX_LINE} bytes "
                                       "without a line end")  # fmt: skip
            left = end - time.monotonic()
            if left <= 0 or not self._readable.poll(math.ceil(left * 1e3)):
                raise ControllerFailed(f"{self.name}: no reply within its deadline of "
                                       f"{deadline:g} s")  # fmt: skip
            try:
                chunk = os.read(self._out, 1 << 16)
            except BlockingIOError:
                continue
            if not chunk:
                raise ControllerFailed(f"{self.name}: {self._gone()} before {what}")
            buffer += chunk
        line, self._buffer = buffer[:cut], buffer[cut + 1:]
        try:
            return json.loads(line, parse_constant=_no_constant)
        except _NotJson as exc:
            raise ControllerFailed(f"{self.name}: {what} holds {exc}, which is not JSON: "
                                   f"{_excerpt(line)}") from None  # fmt: skip
        except ValueError:  # JSONDecodeError, UnicodeDecodeError
            raise ControllerFailed(f"{self.name}: {what} is not JSON: {_excerpt(line)}") \
                from None  # fmt: skip

    def _command(self, reply, own: Own) -> tuple[float, float]:
        """(v, omega) of a reply, checked against the vessel's limits: a velocity pair of
        floats strictly within them at once, anything else by :meth:`_checked`."""
        if type(reply) is dict and len(reply) == 2:
            v, omega = reply.get("v"), reply.get("omega")
            if type(v) is float and type(omega) is float:
                vessel, dt = self.world.vessel, self.world.period
                reach = vessel.max_yaw_accel * dt
                if (max(vessel.min_speed, own.v - vessel.max_decel * dt) <= v
                        <= min(vessel.max_speed, own.v + vessel.max_accel * dt)
                        and max(-vessel.max_yaw_rate, own.omega - reach) <= omega
                        <= min(vessel.max_yaw_rate, own.omega + reach)):  # fmt: skip
                    return v, omega
        return self._checked(reply, own)

    def _checked(self, reply, own: Own) -> tuple[float, float]:
        """(v, omega) of any reply, each check in turn, naming what is wrong."""
        if not isinstance(reply, dict):
            raise ControllerFailed(f"{self.name}: its reply is not a JSON object: "
                                   f"{_excerpt(reply)}")  # fmt: skip
        keys = set(reply)
        if keys not in ({"v", "omega"}, {"course", "speed"}):
            raise ControllerFailed(f"{self.name}: its reply holds {sorted(keys)}: give v and "
                                   "omega, or course and speed")  # fmt: skip
        for key, value in reply.items():
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ControllerFailed(f"{self.name}: {key} must be a number, not "
                                       f"{_excerpt(value)}")  # fmt: skip
            if not math.isfinite(value):
                raise ControllerFailed(f"{self.name}: {key} must be finite, not {value}")
        vessel, dt = self.world.vessel, self.world.period
        if "course" in reply:
            speed = self._within(float(reply["speed"]), vessel.min_speed, vessel.max_speed,
                                 "speed", "m/s", "the vessel's speeds")  # fmt: skip
            return autopilot(own, float(reply["course"]), speed, vessel, dt,
                             self.params["heading_gain"])  # fmt: skip
        v = self._within(float(reply["v"]), vessel.min_speed, vessel.max_speed, "v", "m/s",
                         "the vessel's speeds")  # fmt: skip
        v = self._within(v, own.v - vessel.max_decel * dt, own.v + vessel.max_accel * dt, "v",
                         "m/s", f"what one period's acceleration reaches from {own.v!r}")
        omega = self._within(float(reply["omega"]), -vessel.max_yaw_rate, vessel.max_yaw_rate,
                             "omega", "rad/s", "the vessel's yaw rates")  # fmt: skip
        reach = vessel.max_yaw_accel * dt
        omega = self._within(omega, own.omega - reach, own.omega + reach, "omega", "rad/s",
                             f"what one period's yaw acceleration reaches from {own.omega!r}")
        return v, omega

    def _within(self, value: float, low: float, high: float, key: str, unit: str,
                what: str) -> float:  # fmt: skip
        """``value`` clipped into [low, high] when within the tolerance of it, else a failure."""
        slack = TOLERANCE * max(1.0, abs(low), abs(high))
        if not low - slack <= value <= high + slack:
            raise ControllerFailed(f"{self.name}: {key} {value!r} {unit} is outside {what}, "
                                   f"[{low:.6g}, {high:.6g}] {unit}")  # fmt: skip
        return min(max(value, low), high)

    def _gone(self) -> str:
        """How the program ended (it closed its output: wait a moment for its status)."""
        try:
            status = self._process.wait(GRACE_S)
        except subprocess.TimeoutExpired:
            return "the program closed its output"
        if status < 0:
            try:
                return f"the program was killed by {signal.Signals(-status).name}"
            except ValueError:
                return f"the program was killed by signal {-status}"
        return f"the program exited with status {status}"

    def _read_log(self) -> str | None:
        stderr, self._stderr = self._stderr, None
        if stderr is None:
            return None
        with stderr:
            size = stderr.seek(0, os.SEEK_END)
            stderr.seek(0)
            text = stderr.read(LOG_LIMIT).decode("utf-8", errors="replace")
        if size > LOG_LIMIT:
            text += f"\n[usvtool: {size - LOG_LIMIT} more bytes of its stderr not kept]\n"
        return text


def hello(world: World, params: dict) -> dict:
    """The hello of protocol 1 (docs/protocol.md) for a run in ``world``."""
    vessel, grid = world.vessel, None
    if world.clearance is not None:
        grid = world.clearance.grid
    return {
        "type": "hello",
        "protocol": PROTOCOL,
        "seed": int(world.seed),
        "dt": float(world.period),
        "vessel": {
            "length": float(vessel.length),
            "beam": float(vessel.beam),
            "min_speed": float(vessel.min_speed),
            "max_speed": float(vessel.max_speed),
            "max_accel": float(vessel.max_accel),
            "max_decel": float(vessel.max_decel),
            "max_yaw_rate": float(vessel.max_yaw_rate),
            "max_yaw_accel": float(vessel.max_yaw_accel),
        },
        "goal": [float(v) for v in world.goal],
        "goal_tolerance": float(world.goal_tolerance),
        "route": None if world.route is None else np.asarray(world.route, float).tolist(),
        "map": None if grid is None else map_facts(grid, world.map_file),
        "deadline": float(params["deadline"]),
    }


def map_facts(grid, path) -> dict:
    """The hello's ``map``: the grid's file, size, affine transform and CRS."""
    crs = grid.crs
    epsg = None
    if crs is not None:
        try:
            epsg = crs.to_epsg()
        except Exception:  # noqa: BLE001 (pyproj's lookup failing is "no EPSG code")
            epsg = None
    t = grid.transform
    return {
        "file": None if path is None else str(os.path.abspath(path)),
        "width": int(grid.width),
        "height": int(grid.height),
        "transform": [float(t.a), float(t.b), float(t.c), float(t.d), float(t.e), float(t.f)],
        "crs_wkt": None if crs is None else crs.to_wkt(),
        "epsg": None if epsg is None else int(epsg),
    }


def autopilot(own: Own, course: float, speed: float, vessel, dt: float,
              gain: float) -> tuple[float, float]:  # fmt: skip
    """The velocity pair of the next period that tracks a course-and-speed reference within the
    vessel's limits (docs/protocol.md, "The autopilot").

    Speed: toward ``speed`` by at most one period's acceleration or deceleration. Heading: a
    proportional controller on the heading error ``e`` (wrapped to [-pi, pi]) giving the yaw
    rate ``gain * e``, shaped, as ArduPilot's ``sqrt_controller`` (libraries/AP_Math/
    control.cpp) shapes its P controllers, so that the turn can always be stopped at the
    course with the yaw acceleration ``a``: beyond ``|e| = a / gain**2`` the rate is
    ``sqrt(2 a (|e| - a / (2 gain**2)))``, the fastest rate from which braking at ``a`` ends on
    the course; never more than the error takes in one period; then clipped to one period's
    yaw acceleration from the present yaw rate and to the vessel's yaw rate. The rate reference
    saturated in rate and acceleration is the heading autopilot's reference model of Fossen,
    *Handbook of Marine Craft Hydrodynamics and Motion Control* (Wiley 2011), chapter 10 (after
    Van Amerongen 1982), here without its damping terms: the simulated ship takes the yaw rate
    as commanded.

    >>> from usvtool.sim.vessel import preset
    >>> ship = preset("udwa-usv")
    >>> v, omega = autopilot(Own(0.0, 0.0, 0.0, 5.0, 0.0), -math.pi / 2, 7.0, ship, 0.1, 0.5)
    >>> round(v, 3), omega == -ship.max_yaw_accel * 0.1
    (5.2, True)
    """
    v = min(max(speed, own.v - vessel.max_decel * dt), own.v + vessel.max_accel * dt)
    v = min(max(v, vessel.min_speed), vessel.max_speed)
    error = math.remainder(course - own.psi, 2 * math.pi)
    accel = vessel.max_yaw_accel
    linear = accel / (gain * gain)
    if abs(error) <= linear:
        rate = gain * error
    else:
        rate = math.copysign(math.sqrt(2 * accel * (abs(error) - linear / 2)), error)
    rate = min(max(rate, -abs(error) / dt), abs(error) / dt)
    rate = min(max(rate, own.omega - accel * dt), own.omega + accel * dt)
    rate = min(max(rate, -vessel.max_yaw_rate), vessel.max_yaw_rate)
    return v, rate


class _NotJson(ValueError):
    """NaN, Infinity or -Infinity in a reply: Python's json reads them, JSON has none."""


def _no_constant(name: str):
    raise _NotJson(name)


def _excerpt(value) -> str:
    """A reply (bytes or parsed) as a short quoted excerpt for an error line."""
    if isinstance(value, bytes):
        value = value.decode("utf-8", errors="replace")
    return show(value)


def _signal_group(process: subprocess.Popen, signum: int) -> None:
    """``signum`` to the program's process group (its own session: its children too), while
    the program itself is not yet reaped (so the group's id is still its own)."""
    try:
        os.killpg(process.pid, signum)
    except (ProcessLookupError, PermissionError):
        pass
