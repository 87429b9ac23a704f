"""``exec``, a controller that is a program (usvtool/sim/controllers/process.py, docs/protocol.md):
the reference clients of examples/exec/ end to end, the protocol's messages, and every way a
program can fail, each ending its run as controller failed, one line naming the step, with no
process left behind."""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from usvtool.errors import UsvError
from usvtool.sim import vessel as vessel_model
from usvtool.sim.controllers import Own, make_controller
from usvtool.sim.controllers.process import PROTOCOL, autopilot
from usvtool.sim.families import imazu
from usvtool.sim.run import SimOptions, simulate
from usvtool.sim.scenario import parse, read_scenario

ROOT = Path(__file__).resolve().parents[2]
CLIENT_PY = ROOT / "examples" / "exec" / "client.py"
CLIENT_C = ROOT / "examples" / "exec" / "client.c"
SCENARIOS = ROOT / "charts" / "scenarios"
PY = [sys.executable, str(CLIENT_PY)]


@pytest.fixture(scope="module")
def client_c(tmp_path_factory) -> Path:
    """The C client, built with the machine's cc -O2 into a temporary folder."""
    cc = shutil.which("cc")
    if cc is None:
        pytest.skip("no C compiler (cc) on this machine: the C client cannot be built")
    out = tmp_path_factory.mktemp("cbuild") / "client"
    subprocess.run([cc, "-O2", "-Wall", "-Werror", "-o", str(out), str(CLIENT_C), "-lm"],
                   check=True)  # fmt: skip
    return out


def run(scenario, command, seed=1, **params):
    return simulate(scenario, SimOptions(controller="exec",
                                         params={"command": list(map(str, command)), **params},
                                         seed=seed))  # fmt: skip


def gone(pid: int) -> bool:
    """The process is no more (neither running nor a zombie: reaped)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    return False


# -- the reference clients -----------------------------------------------------------------


@pytest.mark.parametrize("which", ["python", "c"])
def test_a_client_runs_a_bundled_scenario_to_its_goal(which, request):
    command = PY if which == "python" else [request.getfixturevalue("client_c")]
    result = run(read_scenario(SCENARIOS / "env1-head-on.yaml"), command)
    s = result.summary()
    assert s["arrived"] and s["collision"] is None and s["controller_failed"] is None
    assert s["controller"] == "exec" and s["parameters"]["command"] == list(map(str, command))
    assert s["closest_distance_m"] > 5  # it turned away from the head-on target
    assert result.trace.x.shape[0] == round(s["time_s"] / 0.1) + 1
    name = "client.py" if which == "python" else "client.c"
    lines = result.controller_log.splitlines()
    assert lines[0].startswith(f"{name}: protocol 1, seed 1")
    assert lines[-1] == f"{name}: end of input after {round(s['time_s'] / 0.1)} steps"


@pytest.mark.parametrize("which", ["python", "c"])
def test_a_client_follows_the_route_of_the_hello_through_a_map(which, request):
    """env1-static: the straight line to the goal crosses the islands; the route does not."""
    command = PY if which == "python" else [request.getfixturevalue("client_c")]
    s = run(read_scenario(SCENARIOS / "env1-static.yaml"), command).summary()
    assert s["arrived"] and s["collision"] is None and s["controller_failed"] is None


def test_both_clients_and_both_reply_forms_steer_alike(client_c):
    """The Python client's course-and-speed replies through usvtool's autopilot and the C
    client's own velocity pairs (the autopilot's formula) give the same run, to the bit."""
    scenario = read_scenario(SCENARIOS / "emergency-head-on.yaml")
    runs = [run(scenario, PY), run(scenario, [client_c]), run(scenario, [*PY, "--velocity"]),
            run(scenario, [client_c, "--course"])]  # fmt: skip
    assert runs[0].summary()["arrived"]
    for other in runs[1:]:
        assert np.array_equal(other.trace.x, runs[0].trace.x)
        assert np.array_equal(other.trace.y, runs[0].trace.y)


@pytest.mark.parametrize("which", ["python", "c"])
def test_the_same_seed_gives_the_same_bytes(which, request, tmp_path):
    from usvtool.trace import write_events, write_trace

    command = PY if which == "python" else [request.getfixturevalue("client_c")]
    scenario = read_scenario(SCENARIOS / "env1-crossing-port.yaml")
    written = []
    for i in range(2):
        result = run(scenario, command, seed=3)
        write_trace(tmp_path / f"t{i}.csv", result.trace)
        write_events(tmp_path / f"e{i}.json", result.events)
        written.append(((tmp_path / f"t{i}.csv").read_bytes(),
                        (tmp_path / f"e{i}.json").read_bytes()))  # fmt: skip
    assert written[0] == written[1]


# -- what the program is told --------------------------------------------------------------


RECORDER = """
import json, sys
out = open(sys.argv[1], "w")
hello = json.loads(sys.stdin.readline())
out.write(json.dumps(hello) + "\\n")
print(json.dumps({"protocol": 1}), flush=True)
for line in sys.stdin:
    out.write(line)
    own = json.loads(line)["own"]
    print(json.dumps({"v": own[3], "omega": own[4]}), flush=True)
"""


def script(tmp_path: Path, name: str, text: str) -> list[str]:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return [sys.executable, str(path)]


def test_the_hello_and_the_steps_hold_what_a_controller_sees(tmp_path):
    scenario = read_scenario(SCENARIOS / "env1-static.yaml")  # a map and a route
    scenario = parse({"name": "s", "map": str(scenario.map), "route": str(scenario.route),
                      "sim": {"dt": 0.1, "duration": 0.5},
                      "own": {"start": [10, 10], "goal": [490, 490], "heading": 70, "speed": 4},
                      "targets": [{"start": [60, 60], "heading": 250, "speed": 2, "length": 3}]},
                     SCENARIOS / "x.yaml")  # fmt: skip
    record = tmp_path / "record.jsonl"
    result = run(scenario, [*script(tmp_path, "rec.py", RECORDER), record], seed=7)
    hello, *steps = [json.loads(line) for line in record.read_text().splitlines()]
    vessel = vessel_model.preset("iwso-dwa-usv")
    assert hello["type"] == "hello" and hello["protocol"] == PROTOCOL == 1
    assert hello["seed"] == 7 and hello["dt"] == 0.1 and hello["goal"] == [490.0, 490.0]
    assert hello["vessel"]["max_yaw_rate"] == vessel.max_yaw_rate  # rad/s, exactly
    assert hello["vessel"]["max_speed"] == vessel.max_speed
    assert hello["route"][0] == [10.0, 10.0] and hello["route"][-1] == [490.0, 490.0]
    m = hello["map"]
    assert m["file"] == str((ROOT / "charts" / "env1.tif").resolve())
    assert (m["width"], m["height"], m["transform"]) == (500, 500, [1.0, 0.0, 0.0, 0.0, -1.0,
                                                                   500.0])  # fmt: skip
    assert m["crs_wkt"] is None and m["epsg"] is None  # env1 has no CRS
    assert len(steps) == 5 and [s["step"] for s in steps] == list(range(5))
    first = steps[0]
    assert first["t"] == 0.0 and first["own"] == [10.0, 10.0, math.radians(20.0), 4.0, 0.0]
    assert first["targets"] == [[60.0, 60.0, pytest.approx(2 * math.cos(math.radians(200))),
                                 pytest.approx(2 * math.sin(math.radians(200))), 3.0]]  # fmt: skip
    # the step's floats are the trace's, exactly (shortest round-trip decimals)
    for i, step in enumerate(steps):
        assert step["own"][:2] == [result.trace.x[i, 0], result.trace.y[i, 0]]
        assert step["targets"][0][:2] == [result.trace.x[i, 1], result.trace.y[i, 1]]


def test_a_map_with_a_crs_is_given_by_its_epsg_code_and_wkt(tmp_path):
    scenario = read_scenario(SCENARIOS / "rudee-inlet-channel.yaml")
    import dataclasses

    scenario = dataclasses.replace(scenario, sim=dataclasses.replace(scenario.sim, duration=0.2))
    record = tmp_path / "record.jsonl"
    run(scenario, [*script(tmp_path, "rec.py", RECORDER), record])
    m = json.loads(record.read_text().splitlines()[0])["map"]
    assert m["epsg"] == 32618 and "UTM zone 18N" in m["crs_wkt"]


def test_the_encounter_is_its_class_and_target(tmp_path):
    record = tmp_path / "record.jsonl"
    recorder = [*script(tmp_path, "rec.py", RECORDER), record]
    run(read_scenario(SCENARIOS / "env1-head-on.yaml"), recorder)
    steps = [json.loads(line) for line in record.read_text().splitlines()[1:]]
    assert steps[0]["encounter"] == {"class": "head-on", "target": 0}
    alone = parse({"name": "alone", "sim": {"duration": 0.3},
                   "own": {"start": [0, 0], "goal": [0, 100], "speed": 2}}, tmp_path / "a.yaml")
    run(alone, recorder)
    steps = [json.loads(line) for line in record.read_text().splitlines()[1:]]
    assert [s["targets"] for s in steps] == [[]] * 3
    assert [s["encounter"] for s in steps] == [None] * 3


# -- failures ------------------------------------------------------------------------------

#: A program that behaves at every step but the one it is told, where it does what it is told.
FAULTY = """
import json, os, signal, sys, time
mode, at, pidfile = sys.argv[1], int(sys.argv[2]), sys.argv[3]
open(pidfile, "w").write(str(os.getpid()))
if mode == "stubborn":
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
hello = json.loads(sys.stdin.readline())
if mode == "bad-hello":
    print(json.dumps({"protocol": 2}), flush=True)
else:
    print(json.dumps({"protocol": 1}), flush=True)
step = 0
for line in sys.stdin:
    own = json.loads(line)["own"]
    reply = json.dumps({"v": own[3], "omega": own[4]})
    if step == at:
        print("trouble ahead", file=sys.stderr, flush=True)
        if mode in ("late", "stubborn"):
            time.sleep(30)
        elif mode == "crash":
            sys.exit(3)
        elif mode == "garbage":
            reply = "hello there"
        elif mode == "nan":
            reply = '{"v": NaN, "omega": 0}'
        elif mode == "c-nan":
            reply = '{"v": nan, "omega": 0}'
        elif mode == "yaw":
            reply = json.dumps({"v": own[3], "omega": 10.0})
        elif mode == "jump":
            reply = json.dumps({"v": own[3] + 1.0, "omega": own[4]})
        elif mode == "missing":
            reply = json.dumps({"v": own[3]})
        elif mode == "both":
            reply = json.dumps({"v": own[3], "omega": 0, "course": 0, "speed": 2})
        elif mode == "string":
            reply = json.dumps({"v": "fast", "omega": 0})
        elif mode == "two-lines":
            reply = reply + "\\n" + reply
        elif mode == "slow-speed":
            reply = json.dumps({"course": 0.0, "speed": 0.5})
    print(reply, flush=True)
    step += 1
"""

#: mode, the step the program misbehaves at, the step that fails, what the one line says
FAILURES = [
    ("late", 4, 4, "no reply within its deadline of 0.5 s"),
    ("crash", 4, 4, "the program exited with status 3 before its reply"),
    ("garbage", 4, 4, "its reply is not JSON: 'hello there'"),
    ("nan", 4, 4, "its reply holds NaN, which is not JSON"),
    ("c-nan", 4, 4, "its reply is not JSON"),
    ("yaw", 4, 4, "omega 10.0 rad/s is outside the vessel's yaw rates, [-1.0472, 1.0472] rad/s"),
    ("jump", 4, 4, "v 5.0 m/s is outside what one period's acceleration reaches from 4.0"),
    ("missing", 4, 4, "its reply holds ['v']: give v and omega, or course and speed"),
    ("both", 4, 4, "give v and omega, or course and speed"),
    ("string", 4, 4, "v must be a number, not 'fast'"),
    ("two-lines", 4, 5, "it wrote more than one line for one message"),
    ("slow-speed", 4, 4, "speed 0.5 m/s is outside the vessel's speeds, [1, 5] m/s"),
    ("bad-hello", 0, 0, 'acknowledgement must be {"protocol": 1}, not {\'protocol\': 2}'),
    ("stubborn", 2, 2, "no reply within its deadline of 0.5 s"),
]


@pytest.mark.parametrize(("mode", "at", "step", "why"), FAILURES, ids=[f[0] for f in FAILURES])
def test_a_failing_program_ends_its_run_as_controller_failed(tmp_path, caplog, mode, at, step,
                                                             why):  # fmt: skip
    scenario = read_scenario(SCENARIOS / "env1-head-on.yaml")
    pidfile = tmp_path / "pid"
    command = [*script(tmp_path, "faulty.py", FAULTY), mode, at, pidfile]
    with caplog.at_level("WARNING", logger="usvtool"):
        result = run(scenario, command, deadline=0.5)
    s = result.summary()
    assert not s["arrived"] and s["collision"] is None
    assert s["controller_failed"].startswith(f"step {step} (t = {step / 10:g} s): exec: ")
    assert why in s["controller_failed"], s["controller_failed"]
    assert "\n" not in s["controller_failed"]
    run_object = result.events["run"]
    assert run_object["controller_failed"] == s["controller_failed"] and not run_object["arrived"]
    assert [e["kind"] for e in result.events["steps"]][-1] == "controller-failed"
    assert result.trace.t[-1] == pytest.approx(step / 10)  # the run stopped there
    warnings = [r.getMessage() for r in caplog.records if "controller failed" in r.getMessage()]
    assert len(warnings) == 1 and f"step {step} " in warnings[0]
    assert gone(int(pidfile.read_text()))  # ended and reaped, even the one ignoring SIGTERM
    if mode != "bad-hello":
        assert "trouble ahead" in result.controller_log


def test_a_program_that_cannot_start_is_an_error_before_the_run(tmp_path):
    scenario = read_scenario(SCENARIOS / "env1-head-on.yaml")
    with pytest.raises(UsvError, match="exec: command: program 'no-such-program' not found on"):
        run(scenario, ["no-such-program"])
    plain = tmp_path / "plain.txt"
    plain.write_text("not a program")
    with pytest.raises(UsvError, match="not found .or not executable."):
        run(scenario, [plain])


@pytest.mark.parametrize(("params", "why"), [
    ({"command": []}, "command must be a non-empty list of"),
    ({"command": "python3 client.py"}, "command must be a non-empty list"),
    ({"command": ["python3"], "deadline": 0}, "deadline must be > 0 for exec, not 0"),
    ({"command": ["python3", ""]}, "command must be a non-empty list of non-empty strings"),
    ({"command": ["python3"], "label": "udwa"}, "label 'udwa' is another controller's name"),
    ({"command": ["python3"], "label": "a b"}, "label must be a name"),
])  # fmt: skip
def test_bad_parameters_are_refused(params, why):
    with pytest.raises(UsvError, match=why):
        make_controller("exec", **params)


def test_a_label_names_the_run(tmp_path):
    result = run(read_scenario(SCENARIOS / "env1-head-on.yaml"), [*PY, "--trivial"],
                 label="my-client")  # fmt: skip
    assert result.summary()["controller"] == "my-client"
    assert result.events["controller"] == result.events["run"]["controller"] == "my-client"


def test_a_run_interrupted_in_a_step_leaves_no_process(tmp_path):
    """A KeyboardInterrupt (usvtool's SIGINT and SIGTERM handlers raise one) while the program
    thinks: the run's close ends it all the same."""
    scenario = read_scenario(SCENARIOS / "env1-head-on.yaml")
    pidfile = tmp_path / "pid"
    # a deadline no run reaches: only the interrupt ends this one, whatever the load
    controller = make_controller("exec", command=[*script(tmp_path, "faulty.py", FAULTY),
                                                  "late", "0", str(pidfile)],
                                 deadline=120.0)  # fmt: skip
    import signal
    import threading

    from usvtool.sim.run import _run, _Setup

    main = threading.get_ident()

    def interrupt():  # once the program runs (it writes its pid first), while it thinks
        while not (pidfile.exists() and pidfile.read_text()):
            time.sleep(0.05)
        time.sleep(0.2)
        signal.pthread_kill(main, signal.SIGINT)

    threading.Thread(target=interrupt, daemon=True).start()
    with pytest.raises(KeyboardInterrupt):
        _run(scenario, SimOptions(), controller, 100, _Setup(scenario))
    assert gone(int(pidfile.read_text()))


# -- the autopilot -------------------------------------------------------------------------


def test_the_autopilot_turns_onto_a_course_within_the_limits_without_overshoot():
    ship = vessel_model.preset("udwa-usv")  # 20 deg/s, 5 deg/s²: the turn must be braked
    own = Own(0.0, 0.0, 0.0, 5.0, 0.0)
    dt, target = 0.1, -math.pi / 2  # a turn of 90 degrees to starboard
    psi, omega, v, headings = 0.0, 0.0, 5.0, []
    for _ in range(600):
        v_new, omega_new = autopilot(Own(0.0, 0.0, psi, v, omega), target, 7.0, ship, dt, 0.5)
        assert abs(omega_new - omega) <= ship.max_yaw_accel * dt * (1 + 1e-12)
        assert abs(omega_new) <= ship.max_yaw_rate and 0 <= v_new - v <= ship.max_accel * dt + 1e-12
        v, omega = v_new, omega_new
        psi = math.remainder(psi + omega * dt, 2 * math.pi)
        headings.append(psi)
    assert v == ship.max_speed
    assert min(headings) >= target - math.radians(1.0)  # no more than a degree past the course
    assert headings[-1] == pytest.approx(target, abs=1e-6)
    assert own.psi == 0.0


# -- the command line ----------------------------------------------------------------------


def exec_word(command) -> str:
    import shlex

    return "exec:" + shlex.join(map(str, command))


def test_simulate_runs_a_program_and_writes_its_stderr_to_the_controller_log(usv, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    r = usv("simulate", SCENARIOS / "env1-head-on.yaml", "--controller", exec_word(PY), "-o",
            out / "trace.csv", "--events", out / "trace.events.json", "--controller-log",
            out / "controller.log", "--seed", 2)  # fmt: skip
    assert r.exit_code == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["controller"] == "exec" and summary["arrived"]
    assert summary["controller_log"] == str(out / "controller.log")
    assert summary["parameters"]["command"] == list(map(str, PY))
    log = (out / "controller.log").read_text().splitlines()
    assert log[0].startswith("client.py: protocol 1, seed 2, course replies")
    assert "client.py" not in r.stderr  # in the file, not relayed


def test_without_a_controller_log_its_lines_are_relayed_on_stderr(usv, tmp_path):
    r = usv("simulate", SCENARIOS / "env1-head-on.yaml", "--controller", exec_word(PY), "-o",
            tmp_path / "trace.csv")  # fmt: skip
    assert r.exit_code == 0, r.stderr
    relayed = [line for line in r.stderr.splitlines() if "client.py" in line]
    assert relayed[0].startswith("usvtool: exec: client.py: protocol 1, seed 0")
    assert relayed[-1].startswith("usvtool: exec: client.py: end of input after")


def test_a_failed_program_is_one_warning_line_and_a_result(usv, tmp_path):
    pidfile = tmp_path / "pid"
    command = [*script(tmp_path, "faulty.py", FAULTY), "crash", 7, pidfile]
    r = usv("simulate", SCENARIOS / "env1-head-on.yaml", "--controller", exec_word(command),
            "-o", tmp_path / "trace.csv", "--controller-log", tmp_path / "c.log")  # fmt: skip
    assert r.exit_code == 0, r.stderr
    assert r.stderr.count("\n") == 1
    assert r.stderr.startswith(f"usvtool: {SCENARIOS / 'env1-head-on.yaml'}: controller failed "
                               "at step 7 (t = 0.7 s): exec: the program exited with status 3 "
                               "before its reply")  # fmt: skip
    summary = json.loads(r.stdout)
    assert not summary["arrived"] and summary["controller_failed"].startswith("step 7 ")
    assert (tmp_path / "c.log").read_text() == "trouble ahead\n"
    assert gone(int(pidfile.read_text()))


def test_a_scenario_names_its_program(usv, tmp_path):
    scenario = tmp_path / "s.yaml"
    scenario.write_text((SCENARIOS / "env1-head-on.yaml").read_text().replace(
        "controller: {name: gdwa}",
        f"controller: {{name: exec, command: {json.dumps(list(map(str, PY)))}, deadline: 2, "
        "label: py-client}"))  # fmt: skip
    r = usv("simulate", scenario, "-o", tmp_path / "trace.csv")
    assert r.exit_code == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["controller"] == "py-client" and summary["arrived"]
    assert summary["parameters"]["deadline"] == 2


@pytest.mark.parametrize(("args", "why"), [
    (["--controller", "exec:"], "exec: names no program"),
    (["--controller", "exec:'client.py"], "No closing quotation"),
])  # fmt: skip
def test_a_bad_exec_word_is_a_usage_error(usv, tmp_path, args, why):
    r = usv("simulate", SCENARIOS / "env1-head-on.yaml", *args, "-o", tmp_path / "t.csv")
    assert r.exit_code == 2 and why in r.stderr
    assert not (tmp_path / "t.csv").exists()


def test_a_missing_program_is_one_error_line_and_no_output(usv, tmp_path):
    r = usv("simulate", SCENARIOS / "env1-head-on.yaml", "--controller", "exec:no-such-client",
            "-o", tmp_path / "t.csv")  # fmt: skip
    assert r.exit_code == 1
    assert r.stderr == ("Error: --controller: exec: command: program 'no-such-client' not found "
                        "on PATH\n")  # fmt: skip
    assert not (tmp_path / "t.csv").exists()


IMAZU = ["05", "13", "22"]  # a head-on and a crossing; three ships; an overtaking and two more
#: The Imazu family's compressed scale (15 m ships at 7 m/s, docs/families.md), as options.
COMPRESSED = [a for k, v in imazu.COMPRESSED.items() for a in ("--family-option", f"{k}={v:g}")]


@pytest.mark.parametrize("which", ["python", "c"])
def test_a_client_runs_imazu_cases(usv, tmp_path, which, request):
    command = PY if which == "python" else [request.getfixturevalue("client_c")]
    for kind in IMAZU:
        out = tmp_path / kind
        out.mkdir()
        r = usv("simulate", "--family", "imazu", "--kind", kind, *COMPRESSED, "--controller",
                exec_word(command), "--seed", 1, "-o", out / "trace.csv", "--events",
                out / "trace.events.json", "--scenario-out", out / "scene.yaml")  # fmt: skip
        assert r.exit_code == 0, r.stderr
        summary = json.loads(r.stdout)
        assert summary["arrived"] and summary["collision"] is None, (kind, summary)
        assert summary["closest_distance_m"] > 30  # 15 m ships: 15 m between centres is contact


def test_a_failed_run_is_a_failure_in_the_metrics_table(usv, tmp_path):
    """usvtool metrics: controller_failed True, not arrived, no arrival time, its encounters not
    judged; a run whose program did its work has no controller_failed value."""
    import csv
    import io

    runs = {"failed": [*script(tmp_path, "faulty.py", FAULTY), "garbage", 30, tmp_path / "pid"],
            "fine": PY}  # fmt: skip
    for name, command in runs.items():
        r = usv("simulate", SCENARIOS / "env1-head-on.yaml", "--controller", exec_word(command),
                "-o", tmp_path / f"{name}.csv", "--events", tmp_path / f"{name}.events.json")
        assert r.exit_code == 0, r.stderr
    r = usv("metrics", tmp_path / "failed.csv", tmp_path / "fine.csv")
    assert r.exit_code == 0, r.stderr
    rows = {Path(row["run"]).stem: row for row in csv.DictReader(io.StringIO(r.stdout))}
    failed, fine = rows["failed"], rows["fine"]
    assert (failed["controller_failed"], failed["arrived"], failed["arrival_time_s"]) == (
        "True", "False", "")
    assert failed["judged"] == "0" and failed["not_judged"] == failed["encounters"] == "1"
    assert (fine["controller_failed"], fine["arrived"]) == ("", "True")
