"""The field's scenario files in and out (``usvtool scene import`` / ``export``, docs/scenario.md):
DNV's ship-traffic-generator situations (trafficgen's JSON, its ``TrafficSituation`` as of
trafficgen 0.9, maritime-schema 0.2.0) and NTNU colav-simulator scenario YAML (its
``schemas/scenario.yaml``), read from their schemas, no code of theirs.

An imported scenario keeps every ship's position, course, speed, length and waypoints. A field
that is not in the format's schema is refused, in one line naming it; a field of the schema that
a usvtool scenario has no place for (an MMSI, a sensor, a turn radius) is named, in one line, in
the scenario's header comment and the summary's ``not_imported``: never silently dropped.

Positions: trafficgen's WGS84 lon/lat become map metres of a local azimuthal equidistant
projection (:mod:`usvtool.geodesy`) centred on ``origin`` (lat, lon; by default the own ship's
start, which is then (0, 0)); colav-simulator's UTM north/east metres become map metres east and
north of the own ship's start. The scenario has no map (no CRS): its points are ``[x, y]``.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

from usvtool.errors import UsvError
from usvtool.yamlfile import read_yaml, show

#: One knot in m/s (1852 m an hour).
KNOT = 1852.0 / 3600.0
#: The maritime-schema version trafficgen 0.9 writes.
SCHEMA_VERSION = "0.2.0"
#: The length colav-simulator's fixed ``telemetron`` model gives its ship (TelemetronParams).
TELEMETRON_LENGTH = 8.0


def local_crs(lat: float, lon: float) -> str:
    """The local projection (azimuthal equidistant, WGS84, metres) centred on (lat, lon)."""
    return f"+proj=aeqd +lat_0={lat!r} +lon_0={lon!r} +datum=WGS84 +units=m +no_defs"


def _camel(key: str) -> str:
    """trafficgen's JSON names (camelCase); its models accept snake_case too."""
    head, *rest = key.split("_")
    return head + "".join(w.capitalize() for w in rest)


class _Reader:
    """Checks a format's fields: unknown ones refused in one line, known but unused ones noted."""

    def __init__(self, path: Path, schema: str):
        self.path, self.schema, self.dropped = path, schema, []

    def fail(self, where: str, message: str):
        raise UsvError(f"{self.path}: {where}: {message}")

    def fields(self, value, where: str, known: dict, *, extra: bool = False,
               camel: bool = False) -> dict:  # fmt: skip
        """``value`` as a mapping: each key must be one of ``known`` (key -> True: used, False:
        no usvtool place, noted); ``extra``: the schema allows any other key (noted)."""
        if not isinstance(value, dict):
            self.fail(where or "the file", f"must be a mapping, not {show(value)}")
        out = {}
        unknown = []
        for key, item in value.items():
            name = _camel(key) if camel else key
            if name not in known and not extra:
                unknown.append(str(key))
                continue
            if not known.get(name, False):
                self.drop(f"{where}.{name}" if where else name)
            else:
                out[name] = item
        if unknown:
            at = f"{where}." if where else ""
            self.fail(
                ", ".join(at + k for k in unknown),
                f"not a field of {self.schema}'s schema (docs/scenario.md, import)",
            )
        return out

    def drop(self, field: str) -> None:
        field = re.sub(r"\[\d+\]", "[*]", field)
        if field not in self.dropped:
            self.dropped.append(field)

    def number(self, value, where: str) -> float:
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            self.fail(where, f"must be a number, not {show(value)}")
        return float(value)


# ------------------------------------------------------------------------------------ trafficgen

_TG_TOP = {
    "trafficgenVersion": False,
    "schemaVersion": False,
    "title": True,
    "description": True,
    "startTime": False,
    "ownShip": True,
    "targetShips": True,
}
_TG_SHIP = {"initial": True, "waypoints": True, "static": True}
_TG_INITIAL = {"position": True, "sog": True, "cog": True, "heading": True, "navStatus": False}
_TG_STATIC = {
    "id": True,
    "mmsi": False,
    "imo": False,
    "name": True,
    "dimensions": True,
    "shipType": False,
    "pathType": False,
    "sogMin": True,
    "sogMax": True,
}
_TG_DIMENSIONS = {
    "length": True,
    "width": True,
    "height": False,
    "draught": False,
    "a": True,
    "b": True,
    "c": False,
    "d": False,
}
_TG_POSITION = {"lon": True, "lat": True}
_TG_WAYPOINT = {"position": True, "turnRadius": False, "leg": True}
_TG_LEG = {"starboardXtd": False, "portsideXtd": False, "sog": True, "data": True}
_TG_DATA = {"sog": True}
_TG_DATAPOINT = {"value": True, "interpStart": False, "interpEnd": False, "interpMethod": False}


def _tg_ship(r: _Reader, value, where: str, project) -> dict:
    """A trafficgen ship: start (m), course, speed (m/s), length, beam, sog limits, waypoints."""
    ship = r.fields(value, where, _TG_SHIP, camel=True)
    static = r.fields(ship.get("static", {}), f"{where}.static", _TG_STATIC, extra=True,
                      camel=True)  # fmt: skip
    initial = r.fields(ship.get("initial") or {}, f"{where}.initial", _TG_INITIAL, camel=True)

    def point(value, at):
        p = r.fields(value, at, _TG_POSITION, extra=True, camel=True)
        if "lon" not in p or "lat" not in p:
            r.fail(at, "needs lon and lat")
        return project(r.number(p["lon"], f"{at}.lon"), r.number(p["lat"], f"{at}.lat"))

    waypoints, speeds = [], []
    for i, w in enumerate(ship.get("waypoints") or []):
        at = f"{where}.waypoints[{i}]"
        wp = r.fields(w, at, _TG_WAYPOINT, camel=True)
        if "position" not in wp:
            r.fail(at, "needs a position")
        waypoints.append(point(wp["position"], f"{at}.position"))
        leg = r.fields(wp.get("leg") or {}, f"{at}.leg", _TG_LEG, camel=True)
        sog = leg.get("sog")
        data = r.fields(leg.get("data") or {}, f"{at}.leg.data", _TG_DATA, camel=True)
        if sog is None and data.get("sog") is not None:
            sog = r.fields(data["sog"], f"{at}.leg.data.sog", _TG_DATAPOINT, camel=True).get(
                "value"
            )
        speeds.append(None if sog is None else r.number(sog, f"{at}.leg.sog") * KNOT)
    if "position" in initial:
        start = point(initial["position"], f"{where}.initial.position")
    elif waypoints:
        start = waypoints[0]
    else:
        r.fail(where, "has neither initial.position nor waypoints")
    if waypoints and math.dist(waypoints[0], start) < 1e-3:
        waypoints, speeds = waypoints[1:], speeds[1:]  # the start, repeated
    if "sog" in initial:
        speed = r.number(initial["sog"], f"{where}.initial.sog") * KNOT
    elif speeds and speeds[0] is not None:
        speed = speeds[0]
    else:
        r.fail(where, "has no speed (initial.sog or its first leg's sog)")
    if any(s is not None and abs(s - speed) > 1e-6 for s in speeds):
        r.drop(f"{where}.waypoints[*].leg.sog (a speed per leg; usvtool keeps the first)")
    if "cog" in initial:
        course = r.number(initial["cog"], f"{where}.initial.cog")
        if "heading" in initial:
            r.drop(f"{where}.initial.heading")
    elif waypoints:
        course = math.degrees(math.atan2(waypoints[0][0] - start[0], waypoints[0][1] - start[1]))
        if "heading" in initial:
            r.drop(f"{where}.initial.heading")
    elif "heading" in initial:
        course = r.number(initial["heading"], f"{where}.initial.heading")
    else:
        r.fail(where, "has no course (initial.cog, a leg or initial.heading)")
    dims = r.fields(static.get("dimensions") or {}, f"{where}.static.dimensions", _TG_DIMENSIONS,
                    camel=True)  # fmt: skip
    length = dims.get("length")
    if length is None and "a" in dims and "b" in dims:
        length = r.number(dims["a"], "a") + r.number(dims["b"], "b")
    return {"start": start, "course": course % 360.0, "speed": speed, "waypoints": waypoints,
            "length": None if length is None else r.number(length, f"{where}.static.dimensions"),
            "beam": dims.get("width"), "name": static.get("name"), "id": static.get("id"),
            "sog_min": static.get("sogMin"), "sog_max": static.get("sogMax")}  # fmt: skip


def read_trafficgen(path: Path, origin: tuple[float, float] | None, data=None):
    """(title, description, own ship, targets, notes, dropped) of a trafficgen situation: the
    file ``path``, or ``data``, its JSON already read (``path`` then names it)."""
    from usvtool.geodesy import lonlat_to_map

    if data is None:
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (json.JSONDecodeError, UnicodeDecodeError) as exc:
            raise UsvError(f"{path}: not JSON: {exc}") from None
    r = _Reader(path, "trafficgen")
    top = r.fields(data, "", _TG_TOP, camel=True)
    if "ownShip" not in top:
        r.fail("ownShip", "missing")
    if origin is None:
        own = top["ownShip"] if isinstance(top["ownShip"], dict) else {}
        pos = ((own.get("initial") or {}).get("position")
               or ((own.get("waypoints") or [{}])[0] or {}).get("position") or {})  # fmt: skip
        if not isinstance(pos, dict) or "lat" not in pos or "lon" not in pos:
            r.fail("ownShip", "has no start position (initial.position or waypoints[0])")
        origin = (float(pos["lat"]), float(pos["lon"]))
    crs = local_crs(*origin)

    def project(lon, lat):
        x, y = lonlat_to_map(crs, lon, lat)
        return [round(float(x), 6) + 0.0, round(float(y), 6) + 0.0]

    own = _tg_ship(r, top["ownShip"], "ownShip", project)
    targets = [_tg_ship(r, t, f"targetShips[{i}]", project)
               for i, t in enumerate(top.get("targetShips") or [])]  # fmt: skip
    notes = [f"positions: WGS84 lon/lat in a local azimuthal equidistant projection centred on "
             f"lat {origin[0]!r}, lon {origin[1]!r} (map metres east, north); speeds: knots "
             f"x 1852/3600"]  # fmt: skip
    return top.get("title"), top.get("description"), own, targets, notes, r.dropped


# ------------------------------------------------------------------------------- colav-simulator

_CS_TOP_USED = {"name", "t_start", "t_end", "dt_sim", "ship_list"}
_CS_TOP_UNUSED = {
    "save_scenario", "type", "utm_zone", "episode_generation", "n_episodes",
    "n_constant_os_state_episodes", "n_constant_os_plan_episodes", "n_constant_do_state_episodes",
    "n_plans_per_do_state", "n_constant_disturbance_episodes", "delta_uniform_position_sample",
    "map_data_files", "map_size", "map_origin_enu", "map_tolerance", "map_buffer",
    "new_load_of_map_data", "ais_data_file", "ship_data_file", "allowed_nav_statuses",
    "n_random_ships", "n_random_ships_range", "min_dist_between_ships", "max_dist_between_ships",
    "rl", "filename", "stochasticity",
}  # fmt: skip
_CS_SHIP = {"default": False, "mmsi": False, "id": True, "t_start": False, "t_end": False,
            "random_generated": False, "csog_state": True, "goal_csog_state": True,
            "waypoints": True, "speed_plan": True, "colav": False, "tracker": False,
            "sensors": False, "guidance": False, "controller": False, "model": True}  # fmt: skip
_CS_MODELS = {"csog", "telemetron", "cybership2", "rvgunnerus"}


def _cs_ship(r: _Reader, value, where: str) -> dict:
    """A colav-simulator ship in UTM (north, east): start, course, speed, waypoints, length."""
    ship = r.fields(value, where, _CS_SHIP)

    def vector(key, n=None):
        v = ship[key]
        if not isinstance(v, list) or (n is not None and len(v) != n):
            r.fail(f"{where}.{key}", f"must be a list of {n} numbers, not {show(v)}")
        return [r.number(x, f"{where}.{key}") for x in v]

    waypoints = []
    if "waypoints" in ship:
        rows = ship["waypoints"]
        if not (isinstance(rows, list) and len(rows) == 2 and all(isinstance(x, list) for x in rows)
                and len(rows[0]) == len(rows[1])):  # fmt: skip
            r.fail(f"{where}.waypoints", "must be two lists (north, east) of equal length")
        waypoints = [(r.number(e, f"{where}.waypoints"), r.number(n, f"{where}.waypoints"))
                     for n, e in zip(rows[0], rows[1], strict=True)]  # fmt: skip
    plan = vector("speed_plan") if "speed_plan" in ship else []
    if "csog_state" in ship:
        north, east, speed, course = vector("csog_state", 4)
        start = (east, north)
    elif waypoints and plan:
        start, speed = waypoints[0], plan[0]
        if len(waypoints) < 2:
            r.fail(where, "has no csog_state and one waypoint only")
        course = math.degrees(math.atan2(waypoints[1][0] - start[0], waypoints[1][1] - start[1]))
    else:
        r.fail(where, "has no csog_state (nor waypoints and a speed_plan): a ship drawn at random "
                      "or from AIS data has no state to import")  # fmt: skip
    if waypoints and math.dist(waypoints[0], start) < 1e-3:
        waypoints, plan = waypoints[1:], plan[1:]
    if any(abs(s - speed) > 1e-6 for s in plan):
        r.drop(f"{where}.speed_plan (a speed per waypoint; usvtool keeps the start's)")
    goal = None
    if "goal_csog_state" in ship:
        g = vector("goal_csog_state")
        if len(g) < 2:
            r.fail(f"{where}.goal_csog_state", "needs north and east")
        goal = (g[1], g[0])
    length = None
    model = ship.get("model")
    if model is not None:
        if not isinstance(model, dict) or len(model) != 1 or next(iter(model)) not in _CS_MODELS:
            r.fail(f"{where}.model", f"must be one of {', '.join(sorted(_CS_MODELS))}, not "
                                     f"{show(model)}")  # fmt: skip
        name, params = next(iter(model.items()))
        if name == "csog":
            params = r.fields(params, f"{where}.model.csog", dict.fromkeys(
                ("draft", "width", "ship_vertices", "T_chi", "T_U", "r_max", "U_min", "U_max",
                 "name"), False) | {"length": True})  # fmt: skip
            if "length" in params:
                length = r.number(params["length"], f"{where}.model.csog.length")
        elif name == "telemetron":
            length = TELEMETRON_LENGTH
        else:
            r.drop(f"{where}.model.{name} (its length: --length)")
    return {"start": start, "course": course % 360.0, "speed": speed, "waypoints": waypoints,
            "goal": goal, "length": length, "id": ship.get("id"), "name": None, "beam": None,
            "sog_min": None, "sog_max": None}  # fmt: skip


def read_colav(path: Path, data: dict):
    """(name, description, own ship, targets, notes, dropped) of a colav-simulator scenario,
    in metres east and north of the own ship's start."""
    r = _Reader(path, "colav-simulator")
    known = dict.fromkeys(_CS_TOP_USED, True) | dict.fromkeys(_CS_TOP_UNUSED, False)
    top = r.fields(data, "", known)
    ships = top.get("ship_list")
    if not isinstance(ships, list) or not ships:
        r.fail("ship_list", "must list the ships, the own ship first")
    parsed = [_cs_ship(r, s, f"ship_list[{i}]") for i, s in enumerate(ships)]
    x0, y0 = parsed[0]["start"]

    def shift(p):
        return [round(p[0] - x0, 6) + 0.0, round(p[1] - y0, 6) + 0.0]

    for s in parsed:
        s["start"] = shift(s["start"])
        s["waypoints"] = [shift(p) for p in s["waypoints"]]
        if s["goal"] is not None:
            s["goal"] = shift(s["goal"])
    zone = data.get("utm_zone")
    notes = [f"positions: UTM (zone {zone}) north/east minus the own ship's start (east "
             f"{x0!r}, north {y0!r}); the own ship is ship_list[0]"]  # fmt: skip
    sim = {}
    if "dt_sim" in top:
        sim["dt"] = r.number(top["dt_sim"], "dt_sim")
    if "t_end" in top:
        sim["duration"] = r.number(top["t_end"], "t_end") - r.number(top.get("t_start", 0.0),
                                                                     "t_start")  # fmt: skip
    return top.get("name"), None, parsed[0], parsed[1:], notes, r.dropped, sim


# ---------------------------------------------------------------------------------- the scenario


def import_scene(path, *, vessel: str = "udwa-usv", controller: str = "udwa",
                 origin: tuple[float, float] | None = None, length: float | None = None,
                 duration: float | None = None,
                 data: dict | None = None) -> tuple[dict, list[str], list[str]]:  # fmt: skip
    """The usvtool scenario (a mapping, docs/scenario.md) of the trafficgen JSON or
    colav-simulator YAML ``path``, with its header notes and the fields not imported.
    ``origin`` (lat, lon): trafficgen's projection centre; ``length``: a ship's length where the
    file has none; ``duration``: sim.duration where the file has none (by default 1.5 times the
    own ship's straight run to its goal, rounded up to 10 s). ``data``: a trafficgen situation
    already read (``path`` then only names it)."""
    path = Path(path)
    sim: dict = {}
    if data is not None or path.suffix.lower() == ".json":
        fmt = "trafficgen"
        name, description, own, targets, notes, dropped = read_trafficgen(path, origin, data)
    elif path.suffix.lower() in (".yaml", ".yml"):
        fmt = "colav-simulator"
        name, description, own, targets, notes, dropped, sim = read_colav(path, read_yaml(path))
    else:
        raise UsvError(f"{path}: not a scenario file usvtool imports (a trafficgen .json or a "
                       "colav-simulator .yaml)")  # fmt: skip
    where = "ownShip" if fmt == "trafficgen" else "ship_list[0]"
    goal = own.get("goal") or (own["waypoints"][-1] if own["waypoints"] else None)
    if goal is None:
        raise UsvError(f"{path}: {where}: has no goal (waypoints or a goal state)")
    if len(own["waypoints"]) > 1:
        dropped.append(f"{where} waypoints before the last (the own ship heads for its last; a "
                       "route is a GeoJSON file, usvtool plan)")  # fmt: skip
    own_out = {"start": own["start"], "goal": [float(goal[0]), float(goal[1])],
               "heading": own["course"], "speed": own["speed"], "vessel": vessel}  # fmt: skip
    for key, value in (("length", own["length"]), ("beam", own["beam"])):
        if value is not None:
            own_out[key] = float(value)
    if own["sog_min"] is not None:
        own_out["min_speed"] = float(own["sog_min"]) * KNOT
    if own["sog_max"] is not None:
        own_out["max_speed"] = float(own["sog_max"]) * KNOT
    out_targets, names = [], {"own"}
    for i, t in enumerate(targets):
        label = f"targetShips[{i}]" if fmt == "trafficgen" else f"ship_list[{i + 1}]"
        tname = t["name"] if isinstance(t["name"], str) else None
        if not tname or tname in names or any(c in tname for c in ',"\n\r'):
            tname = f"ts{t['id'] if isinstance(t['id'], int) else i + 1}"
        if tname in names:
            tname = f"ts{i + 1}-{len(names)}"
        names.add(tname)
        tlen = t["length"] if t["length"] is not None else length
        if tlen is None:
            raise UsvError(f"{path}: {label}: has no length (give --length)")
        entry = {"name": tname, "start": t["start"], "heading": t["course"], "speed": t["speed"],
                 "length": float(tlen)}  # fmt: skip
        if t["waypoints"]:
            entry["waypoints"] = [[float(p[0]), float(p[1])] for p in t["waypoints"]]
        if t.get("goal") is not None:
            dropped.append(f"{label}.goal_csog_state (a target has no goal)")
        if t["beam"] is not None:
            dropped.append(re.sub(r"\[\d+\]", "[*]", f"{label}.static.dimensions.width"))
        out_targets.append(entry)
    if duration is None:
        duration = sim.get("duration")
    if duration is None:
        run = math.dist(own_out["start"], own_out["goal"]) / max(own_out["speed"], 0.1)
        duration = 10.0 * math.ceil(1.5 * run / 10.0)
    settings = {"dt": sim.get("dt", 0.1), "duration": float(duration), "goal_tolerance": 5.0}
    scenario = {"name": str(name or path.stem), "sim": settings, "own": own_out,
                "targets": out_targets, "controller": {"name": controller}}  # fmt: skip
    header = [f"Imported by usvtool scene import from {path.name} ({fmt}, docs/scenario.md).",
              *notes]  # fmt: skip
    if description:
        header.append(f"description: {description}")
    dropped = list(dict.fromkeys(dropped))
    header.append("Not imported (no usvtool field): " + (", ".join(dropped) or "none") + ".")
    return scenario, header, dropped


def scenario_text(scenario: dict, header: list[str]) -> str:
    import yaml

    from usvtool.yamlfile import comment

    body = yaml.safe_dump(scenario, sort_keys=False, default_flow_style=None, width=100)
    return "\n".join(comment(line) for line in header) + "\n" + body


# ------------------------------------------------------------------------------------ the export


def export_trafficgen(path, origin: tuple[float, float] = (0.0, 0.0)) -> dict:
    """The trafficgen situation (a JSON mapping, maritime-schema 0.2.0) of the usvtool scenario
    ``path``: map metres -> lon/lat of the local projection centred on ``origin`` (lat, lon), the
    own ship's waypoints its start and goal, a target's its start and its waypoints."""
    from usvtool.geodesy import map_to_lonlat
    from usvtool.sim.scenario import read_scenario
    from usvtool.sim.vessel import PRESETS

    s = read_scenario(path)
    crs = local_crs(*origin)

    def where(p, what):
        if isinstance(p, dict) or p is None:
            raise UsvError(f"{path}: {what}: trafficgen export takes map-metre points, not "
                           f"{show(p)}")  # fmt: skip
        lon, lat = map_to_lonlat(crs, float(p[0]), float(p[1]))
        return {"lat": float(lat), "lon": float(lon)}

    def leg(speed):
        return {"sog": speed / KNOT}

    preset = {**PRESETS[s.own.vessel], **s.own.overrides}
    own_static = {"id": 0, "name": "own", "dimensions": {"length": float(preset["length"]),
                                                         "width": float(preset["beam"])},
                  "sogMax": float(preset["max_speed"]) / KNOT}  # fmt: skip
    if preset.get("min_speed"):
        own_static["sogMin"] = float(preset["min_speed"]) / KNOT
    own = {"initial": {"position": where(s.own.start, "own.start"), "sog": s.own.speed / KNOT,
                       "cog": s.own.heading, "heading": s.own.heading},
           "waypoints": [{"position": where(s.own.start, "own.start"), "leg": leg(s.own.speed)},
                         {"position": where(s.own.goal, "own.goal"), "leg": leg(s.own.speed)}],
           "static": own_static}  # fmt: skip
    targets = []
    for i, t in enumerate(s.targets):
        if t.track is not None or t.start is None:
            raise UsvError(f"{path}: targets[{i}]: a replayed track has no trafficgen form")
        if t.heading_sd or t.speed_sd:
            raise UsvError(f"{path}: targets[{i}]: a noisy course or speed (heading_sd, speed_sd) "
                           "has no trafficgen form")  # fmt: skip
        ship = {"initial": {"position": where(t.start, f"targets[{i}].start"),
                            "sog": t.speed / KNOT, "cog": t.heading, "heading": t.heading},
                "static": {"id": i + 1, "name": t.name,
                           "dimensions": {"length": t.length}}}  # fmt: skip
        if t.waypoints:
            ship["waypoints"] = [{"position": where(p, f"targets[{i}].waypoints"),
                                  "leg": leg(t.speed)}
                                 for p in [t.start, *t.waypoints]]  # fmt: skip
        targets.append(ship)
    return {"trafficgenVersion": _trafficgen_version(), "schemaVersion": SCHEMA_VERSION,
            "title": s.name, "description": f"usvtool scene export of {Path(path).name}",
            "ownShip": own, "targetShips": targets}  # fmt: skip


def _trafficgen_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("trafficgen")
    except PackageNotFoundError:
        return "0.9"
