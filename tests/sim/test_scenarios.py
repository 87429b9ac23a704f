"""The bundled scenarios (charts/scenarios/, README.md there) run end to end.

Runs are cached for the module: each (scenario, controller) pair is simulated once.

* Every scenario reads and starts with every controller: a short run (``SMOKE_S`` seconds of
  simulated time) of each of the 16 x 5 pairs. Full runs cover every pair, and ccdwa on udwa+'s
  window in the emergencies (the like-for-like comparison for the variant): about 30 s on two
  shared cores with the compiled control step (three and a half minutes before it).
* The papers' claims: the eight IWSO-DWA encounters (gdwa) arrive without collision and turn to
  starboard first; in the three UDWA emergency encounters udwa does not collide and keeps a
  larger minimum distance than ccdwa (and so does the variant udwa+, against ccdwa on its own
  window and on udwa+'s); in both wind runs udwa arrives before dwa.
* Every run's trace is checked independently: the centre distances recomputed from it give the
  summary's minimum distances, and no run with touching hulls is reported arrived.
* The outcomes of all 80 pairs (seed 1, as pipelines/full.yaml runs them) are those committed in
  ``data/outcomes.csv`` (:func:`outcome`): arrival, collision, the closest distance and the
  path length to 1 mm, the controller's events and the COLREGs verdicts. A change of the
  controllers that keeps its decisions keeps the file; one that changes them shows here. After
  a deliberate change, ``USVTOOL_WRITE_OUTCOMES=1`` writes the file anew from the runs (and the
  test then fails, to be run again).
"""

from __future__ import annotations

import csv
import dataclasses
import importlib.util
import json
import os
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from usvtool import angles, geodesy
from usvtool.grid import NAVIGABLE, read_grid
from usvtool.sim import controllers as registry
from usvtool.sim.run import SimOptions, simulate
from usvtool.sim.scenario import read_scenario
from usvtool.sim.vessel import vessel_from

pytestmark = pytest.mark.slow  # every bundled scenario with every controller

SCENARIOS = Path(__file__).resolve().parents[2] / "charts" / "scenarios"
#: every registered controller but exec, a program run as a process, which needs its program
#: (tests/sim/test_exec.py runs the reference clients on bundled scenarios)
CONTROLLERS = tuple(n for n, cls in registry.CONTROLLERS.items()
                    if not issubclass(cls, registry.ProcessController))
PAPER = [
    f"{env}-{kind}"
    for env in ("env1", "env2")
    for kind in ("overtaking", "head-on", "crossing-port", "crossing-starboard")
]
STATIC = ["env1-static", "env2-static"]
EMERGENCY = ["emergency-head-on", "emergency-crossing", "emergency-overtaking"]
WIND = ["wind-southeast-strong", "wind-northwest-strong"]
CHANNEL = ["rudee-inlet-channel"]
NAMES = PAPER + STATIC + EMERGENCY + WIND + CHANNEL
#: Seconds of simulated time of the runs that only show a pair starts and steps.
SMOKE_S = 3.0


#: ccdwa on udwa+'s trajectory-rollout window: the like-for-like comparison for the variant
#: (the same rollouts, the side rule the only difference, as in the UDWA paper's comparison).
CCDWA_HORIZON = "ccdwa:window=horizon"


FULL = [(n, c) for n in NAMES for c in CONTROLLERS] + [(n, CCDWA_HORIZON) for n in EMERGENCY]


@pytest.fixture(scope="module")
def scenario():
    cache = {}

    def get(name):
        if name not in cache:
            cache[name] = read_scenario(SCENARIOS / f"{name}.yaml")
        return cache[name]

    return get


@pytest.fixture(scope="module")
def run(scenario):
    """``run(name, controller)``: the full run, simulated once per module; ``controller`` may
    carry parameters, ``"ccdwa:window=horizon"``."""
    cache = {}

    def get(name, controller):
        if (name, controller) not in cache:
            base, *settings = controller.split(":")
            params = dict(item.split("=") for item in settings)
            options = SimOptions(controller=base, params=params, seed=1)
            cache[name, controller] = simulate(scenario(name), options)
        return cache[name, controller]

    return get


#: The committed outcomes of every (scenario, controller) pair: :func:`outcome`'s columns.
OUTCOMES = Path(__file__).resolve().parent / "data" / "outcomes.csv"


def outcome(summary: dict, events: dict) -> dict[str, str]:
    """What a run decided, as text: arrival, collision, time, closest distance and path length
    (1 mm), the controller's step events by kind, and the COLREGs verdicts (encounters judged,
    how many compliant, the failed rules by name)."""
    judged = [e for e in events["encounters"] if e["compliant"] is not None]
    failed = Counter(rule for e in judged for rule in e["failed_rules"])
    kinds = Counter(e["kind"] for e in events["steps"])
    closest = summary["closest_distance_m"]

    def counts(counter: Counter) -> str:
        return " ".join(f"{k}:{n}" for k, n in sorted(counter.items()))

    return {
        "scenario": summary["scenario"],
        "controller": summary["controller"],
        "arrived": str(summary["arrived"]).lower(),
        "collision": summary["collision"] or "",
        "time_s": f"{summary['time_s']:.1f}",
        "closest_distance_m": "" if closest is None else f"{closest:.3f}",
        "path_length_m": f"{summary['path_length_m']:.3f}",
        "controller_events": counts(kinds),
        "judged": str(len(judged)),
        "compliant": str(sum(bool(e["compliant"]) for e in judged)),
        "failed_rules": counts(failed),
    }


@pytest.mark.parametrize("controller", CONTROLLERS)
def test_every_pair_keeps_its_committed_outcome(run, controller):
    """Every scenario with the controller decides as the committed table says (one test per
    controller, so that the suite's workers share the 80 runs)."""
    with OUTCOMES.open(newline="") as f:
        committed = list(csv.DictReader(f))
    assert {(r["scenario"], r["controller"]) for r in committed} == {
        (n, c) for n in NAMES for c in CONTROLLERS
    }
    mine = [r for r in committed if r["controller"] == controller]
    now = []
    for row in mine:
        result = run(row["scenario"], controller)
        now.append(outcome(result.summary(), result.events))
    if os.environ.get("USVTOOL_WRITE_OUTCOMES"):
        fresh = iter(now)
        rows = [next(fresh) if r["controller"] == controller else r for r in committed]
        with OUTCOMES.open("w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
            writer.writeheader()
            writer.writerows(rows)
        pytest.fail(f"{OUTCOMES} written anew for {controller}: run the test again")
    changed = [(c, n) for c, n in zip(mine, now, strict=True) if c != n]
    assert not changed, "\n".join(
        f"{c['scenario']}/{c['controller']}: "
        + ", ".join(f"{k} {c[k]!r} -> {n[k]!r}" for k in c if c[k] != n[k])
        for c, n in changed
    )


def test_every_yaml_is_listed():
    assert sorted(p.stem for p in SCENARIOS.glob("*.yaml")) == sorted(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_every_controller_starts(scenario, name):
    """Each scenario reads and steps with every controller (a short run of each pair)."""
    sc = scenario(name)
    assert sc.name == name
    short = dataclasses.replace(sc, sim=dataclasses.replace(sc.sim, duration=SMOKE_S))
    for controller in CONTROLLERS:
        result = simulate(short, SimOptions(controller=controller))
        s = result.summary()
        assert s["controller"] == controller
        assert s["collision"] is None, (controller, s["collision"])
        assert len(result.trace.t) == int(round(SMOKE_S / sc.sim.dt)) + 1 or s["arrived"]
        check_trace(sc, result)


def check_trace(sc, result) -> None:
    """The independent check of one run: distances recomputed from the trace."""
    s = result.summary()
    tr = result.trace
    assert tr.ships[0] == "own" and list(tr.ships[1:]) == [t.name for t in sc.targets]
    own_length = vessel_from(sc.own.vessel, sc.own.overrides).length
    d = np.hypot(tr.x[:, 1:] - tr.x[:, :1], tr.y[:, 1:] - tr.y[:, :1])  # (n, k)
    if not sc.targets:
        assert s["closest_distance_m"] is None and s["per_target"] == []
        return
    assert s["closest_distance_m"] == pytest.approx(d.min(), abs=1e-3)
    for j, target in enumerate(sc.targets):
        events = [p for p in s["per_target"] if p["target"] == target.name]
        assert events, f"no entry for {target.name}"
        reported = min(p["closest_distance_m"] for p in events)
        assert reported == pytest.approx(d[:, j].min(), abs=1e-3), (
            f"{sc.name}/{s['controller']}: {target.name} came within {d[:, j].min():.3f} m "
            f"(t = {tr.t[np.argmin(d[:, j])]:.1f} s), its encounters report {reported} m"
        )
    touching = (d < (own_length + np.array([t.length for t in sc.targets])) / 2).any()
    if touching:
        assert not s["arrived"] and s["collision"] is not None


@pytest.mark.parametrize(("name", "controller"), FULL, ids=[f"{n}/{c}" for n, c in FULL])
def test_trace_agrees_with_summary(scenario, run, name, controller):
    result = run(name, controller)
    check_trace(scenario(name), result)
    s = result.summary()
    assert s["scenario"] == name and s["controller"] == controller.split(":")[0]


#: The side of the first manoeuvre the paper reports: "veering toward the upper right" (env1
#: overtaking, 65 deg), "steering approximately 68 degrees to the upper right" (env2 overtaking),
#: head-on and both crossings "adjust(s) the starboard" / "turning ... to the starboard".
PAPER_SIDES = {name: "starboard" for name in PAPER}


@pytest.mark.parametrize("name", PAPER)
def test_paper_encounter_arrives_without_collision(run, name):
    s = run(name, "gdwa").summary()
    assert s["arrived"] and s["collision"] is None, (s["time_s"], s["collision"])


#: Claims the controllers miss today (strict expected failures: a fix shows as an unexpected
#: pass; docs/controllers.md, "Known misses", gives the figures and the causes).
KNOWN_MISSES = {
    "emergency-head-on": "udwa's window is one control period's (IWSO-DWA eq. 19): +-0.5 deg/s "
    "of yaw rate on this boat, so over the 10 s horizon every rollout runs within 5 deg of the "
    "present course and the sides look alike until the domain rule fires at 5 s; the starboard "
    "priority then decides, and from there the window holds no port rate: it runs as ccdwa "
    "does (35.5 m against 35.3 m)",
    "emergency-crossing": "every sample of the one-period window meets a contact at the start (a "
    "collision course 10 s ahead, a 10 s horizon): the fallback, then the side rule's override "
    "(no contact while a free sample exists), take ccdwa to port as they take udwa, and both "
    "run alike (46.3 m each)",
}

def _known(names):
    return [pytest.param(n, marks=pytest.mark.xfail(strict=True, reason=KNOWN_MISSES[n]))
            if n in KNOWN_MISSES else n for n in names]  # fmt: skip


@pytest.mark.parametrize("name", _known(PAPER))
def test_paper_encounter_turns_to_starboard(run, name):
    s = run(name, "gdwa").summary()
    first = s["per_target"][0]
    assert first["class"] != "none"
    assert first["first_manoeuvre_side"] == PAPER_SIDES[name], first


def test_env1_overtaking_passes_on_the_targets_starboard_side(run):
    """ "It expertly navigates past the red dynamic obstacle ship from its starboard side": the
    target ends on the own ship's port side (passing_side is where the target is)."""
    first = run("env1-overtaking", "gdwa").summary()["per_target"][0]
    assert first["class"] == "overtaking"
    assert first["passing_side"] == "port", first


@pytest.mark.parametrize("name", STATIC)
def test_static_route_run_arrives(run, name):
    s = run(name, "gdwa").summary()
    assert s["arrived"] and s["collision"] is None, (s["time_s"], s["collision"])


@pytest.mark.parametrize("name", _known(EMERGENCY))
def test_emergency_udwa_keeps_further_than_ccdwa(run, name):
    keeps_further(run(name, "udwa").summary(), run(name, "ccdwa").summary())


def keeps_further(udwa: dict, ccdwa: dict) -> None:
    """The UDWA paper's claim (section 4.1, Table 1): no collision, and a closest distance
    larger by a margin, not by noise (the paper's Table 1 has 1.8, 3.3 and 2.1 times)."""
    assert udwa["collision"] is None, (udwa["collision"], udwa["time_s"])
    assert udwa["closest_distance_m"] > 1.1 * ccdwa["closest_distance_m"], (
        udwa["closest_distance_m"],
        ccdwa["closest_distance_m"],
    )


#: udwa+ against ccdwa: the faithful ccdwa (one period's window) and ccdwa on udwa+'s window.
PLUS_MISSES = {
    ("emergency-crossing", "ccdwa"): "the one-period ccdwa is taken to port at the start (see "
    "KNOWN_MISSES) and so does what the UDWA paper has UDWA do; udwa+ slows and passes astern "
    "of the target (Rule 15): 45.0 m against 46.3 m",
}
PLUS_CASES = [
    pytest.param(n, c, marks=pytest.mark.xfail(strict=True, reason=PLUS_MISSES[n, c]))
    if (n, c) in PLUS_MISSES else (n, c)
    for n in EMERGENCY for c in ("ccdwa", CCDWA_HORIZON)
]  # fmt: skip


@pytest.mark.parametrize(("name", "versus"), PLUS_CASES)
def test_emergency_udwa_plus_keeps_further_than_ccdwa(run, name, versus):
    keeps_further(run(name, "udwa+").summary(), run(name, versus).summary())


@pytest.mark.parametrize("name", WIND)
def test_wind_udwa_arrives_before_dwa(run, name):
    udwa = run(name, "udwa").summary()
    dwa = run(name, "dwa").summary()
    assert udwa["arrived"] and dwa["arrived"]
    assert udwa["time_s"] < dwa["time_s"], (udwa["time_s"], dwa["time_s"])


def test_channel_encounter_arrives_turning_to_starboard(run):
    s = run("rudee-inlet-channel", "gdwa").summary()
    assert s["arrived"] and s["collision"] is None, (s["time_s"], s["collision"])
    first = s["per_target"][0]
    assert first["class"] == "head-on" and first["first_manoeuvre_side"] == "starboard", first


def test_channel_points_are_navigable(scenario):
    """The channel scenario's points, and its route's vertices, lie on navigable cells."""
    sc = scenario("rudee-inlet-channel")
    grid = read_grid(sc.map)
    points = [sc.own.start, sc.own.goal]
    for t in sc.targets:
        points += [t.start, *t.waypoints]
    for p in points:
        x, y = geodesy.lonlat_to_map(grid.crs, p["lon"], p["lat"])
        assert grid.contains(x, y) and grid.cells[grid.cell_of(x, y)] == NAVIGABLE, p
    route = json.loads(sc.route.read_text())["features"][0]["properties"]
    assert route["collision_free"]
    for x, y in route["map_coordinates"]:
        assert grid.cells[grid.cell_of(x, y)] == NAVIGABLE


def test_wind_fields_are_the_generators():
    """The bundled wind rasters hold what make_scenarios.py writes, and read as the field the
    README describes (strong south-east of the diagonal y = x, then north-west of it; the mean
    speed on it; from the south-west)."""
    from usvtool.sim.weather import read_weather

    spec = importlib.util.spec_from_file_location("make_scenarios", SCENARIOS / "make_scenarios.py")
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    import rasterio

    for name, southeast in (("southeast-strong", True), ("northwest-strong", False)):
        path = SCENARIOS / "wind" / f"{name}.tif"
        speed, frm = gen.wind_field(southeast)
        with rasterio.open(path) as ds:
            assert ds.crs is None
            assert list(ds.descriptions) == ["wind_speed", "wind_from"]
            np.testing.assert_array_equal(ds.read(1), speed)
            np.testing.assert_array_equal(ds.read(2), frm)
        w = read_weather(path)
        # 71 m south-east of the diagonal, 71 m north-west of it, on it
        c = w.at(np.array([400.0, 300.0, 350.0]), np.array([300.0, 400.0, 350.0]))
        strong, weak = (0, 1) if southeast else (1, 0)
        assert c.wind_speed[strong] == pytest.approx(7.0) and c.wind_speed[weak] == pytest.approx(1)
        assert c.wind_speed[2] == pytest.approx(4.0)
        np.testing.assert_allclose(angles.math_to_compass(c.wind_from), 225.0)
