"""Rows of metrics from route files and run files (docs/metrics.md).

Inputs, by extension:

- ``*.geojson``: a route (path GeoJSON of ``usvtool plan``). Its chart is the name of the file's
  directory (the pipeline writes ``build/paths/CHART/ALGO.geojson``). Length, turns and mot are
  computed again from its map coordinates (:func:`usvtool.route.length_in_metres`: geodesic
  when it has a CRS, as ``plan``); fitness, planning time, collision-free and attempt are the
  file's properties. ``length_ratio``: the length over that of the chart's reference route:
  a ``--reference`` file in the same directory, else the input route of that directory whose
  algorithm is ``anyangle``; empty when there is none.
- ``*.csv``: a run (trace CSV of ``usvtool simulate``) with its events JSON: given with
  ``events`` (paired with the traces in order), else ``<stem>.json`` beside the trace, else
  ``<stem>.events.json``. The events JSON must hold the ``run`` object (docs/simulate.md).

Rows: sorted by input path (as given), so the same inputs in any order give the same bytes.
The table's columns: :data:`ROUTE_COLUMNS` when every input is a route, :data:`RUN_COLUMNS`
when every input is a run, else both (routes' first, the shared ``length_m``, ``turns``,
``mot`` once), blank where a column does not apply.
"""

from __future__ import annotations

import csv
import io
import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from usvtool import measures
from usvtool.errors import UsvError, check_input_file
from usvtool.route import length_in_metres, read_path_geojson
from usvtool.trace import OWN, read_events, read_trace

ROUTE_COLUMNS = ("chart", "algorithm", "length_m", "length_ratio", "turns", "mot", "fitness",
                 "planning_time_s", "collision_free", "attempt")  # fmt: skip
RUN_COLUMNS = ("run", "scenario", "controller", "seed", "arrived", "collision",
               "controller_failed", "length_m",
               "turns", "mot", "arrival_time_s", "closest_distance_m", "average_distance_m",
               "domain_intrusion_s", "encounters", "judged", "compliant", "compliant_excused",
               "noncompliant", "not_judged", "failed_rules", "excused_rules",
               "reference_controller", "closest_distance_rate",
               "average_distance_rate")  # fmt: skip
#: The COLREGs counts of a run (:func:`colregs_counts`): every encounter in exactly one.
VERDICTS = ("compliant", "compliant_excused", "noncompliant", "not_judged")
#: Decimals of each real-valued column (written as Python writes the rounded number).
DECIMALS = {"length_m": 2, "length_ratio": 4, "mot": 4, "fitness": 2, "planning_time_s": 3,
            "arrival_time_s": 3, "closest_distance_m": 3, "average_distance_m": 3,
            "domain_intrusion_s": 3, "closest_distance_rate": 4,
            "average_distance_rate": 4}  # fmt: skip
ANY_ANGLE = "anyangle"


@dataclass(frozen=True)
class MetricsOptions:
    """``references``: route files, each the optimum of the routes in its directory;
    ``events``: events JSON files paired in order with the trace inputs (empty: found beside
    them); ``reference_controller``: the controller whose runs (same scenario and seed) the
    optimisation rates compare with."""

    references: tuple[str, ...] = ()
    events: tuple[str, ...] = ()
    reference_controller: str | None = None


@dataclass
class MetricsResult:
    """The rows (values unrounded; None = blank) and the table's columns."""

    columns: tuple[str, ...]
    rows: list[dict] = field(default_factory=list)

    def formatted(self) -> list[dict]:
        """The rows as written: reals rounded (:data:`DECIMALS`), every column present."""
        return [{c: _rounded(c, r.get(c)) for c in self.columns} for r in self.rows]

    def to_csv(self) -> str:
        out = io.StringIO()
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(self.columns)
        for row in self.formatted():
            writer.writerow([_cell(row[c]) for c in self.columns])
        return out.getvalue()

    def to_json(self) -> str:
        data = {"columns": list(self.columns), "rows": self.formatted()}
        return json.dumps(data, indent=1, allow_nan=False) + "\n"

    def summary(self) -> dict:
        kinds = [r["_kind"] for r in self.rows]
        return {"rows": len(self.rows), "routes": kinds.count("route"),
                "runs": kinds.count("run"), "columns": list(self.columns)}  # fmt: skip


def measure(paths, options: MetricsOptions | None = None) -> MetricsResult:
    """One row per input file (module docstring); :class:`UsvError` names the file at fault."""
    opts = options or MetricsOptions()
    paths = [os.fspath(p) for p in paths]
    if not paths:
        raise UsvError("no input: give route (.geojson) or trace (.csv) files")
    seen: dict[str, str] = {}
    for p in [*paths, *opts.references]:
        kind_of(p)
        check_input_file(p)
    for p in paths:
        key = os.path.realpath(p)
        if key in seen:
            raise UsvError(f"{p}: given twice (as {seen[key]})")
        seen[key] = p
    traces = sorted(p for p in paths if kind_of(p) == "run")
    if opts.events and len(opts.events) != len(traces):
        raise UsvError(f"--events: {len(opts.events)} file(s) for {len(traces)} trace(s); give "
                       "one per trace, in the order of the traces, or none")  # fmt: skip
    given = [p for p in paths if kind_of(p) == "run"]
    events_of = dict(zip(given, opts.events, strict=False)) if opts.events else {}
    rows = []
    for p in sorted(paths):
        if kind_of(p) == "route":
            rows.append(_route_row(p))
        else:
            rows.append(_run_row(p, events_of.get(p) or _events_beside(p)))
    _route_ratios(rows, opts.references)
    _run_rates(rows, opts.reference_controller)
    kinds = {r["_kind"] for r in rows}
    if kinds == {"route"}:
        columns = ROUTE_COLUMNS
    elif kinds == {"run"}:
        columns = RUN_COLUMNS
    else:
        columns = ROUTE_COLUMNS + tuple(c for c in RUN_COLUMNS if c not in ROUTE_COLUMNS)
    return MetricsResult(columns, rows)


def kind_of(path: str) -> str:
    suffix = Path(path).suffix.lower()
    if suffix == ".geojson":
        return "route"
    if suffix == ".csv":
        return "run"
    raise UsvError(f"{path}: not a route (.geojson) nor a trace (.csv)")


# --- routes ---------------------------------------------------------------------------------


def _route_figures(path: str) -> tuple[np.ndarray, dict, float]:
    points, props = read_path_geojson(path)
    if points.ndim != 2 or points.shape[1:] != (2,) or len(points) < 2:
        raise UsvError(f"{path}: a route needs two or more [x, y] points")
    if not np.isfinite(points).all():
        raise UsvError(f"{path}: a route's coordinates must be finite")
    return points, props, length_in_metres(points, props.get("crs") or None)


def _route_row(path: str) -> dict:
    points, props, length = _route_figures(path)
    return {
        "_kind": "route",
        "_path": path,
        "_dir": os.path.realpath(Path(path).parent),
        "chart": Path(path).resolve().parent.name,
        "algorithm": props.get("algorithm"),
        "length_m": length,
        "turns": int(measures.turns(points)),
        "mot": float(measures.mot(points)),
        "fitness": props.get("fitness"),
        "planning_time_s": props.get("planning_time_s"),
        "collision_free": props.get("collision_free"),
        "attempt": props.get("attempt"),
    }


def _route_ratios(rows: list[dict], references) -> None:
    optimum: dict[str, tuple[str, float]] = {}
    for ref in references:
        key = os.path.realpath(Path(ref).parent)
        if key in optimum and os.path.realpath(optimum[key][0]) != os.path.realpath(ref):
            raise UsvError(f"--reference {ref}: a second reference for the routes of "
                           f"{Path(ref).parent} (after {optimum[key][0]})")  # fmt: skip
        optimum[key] = (ref, _route_figures(ref)[2])
    for r in rows:
        if r["_kind"] == "route" and r["algorithm"] == ANY_ANGLE and r["_dir"] not in optimum:
            optimum[r["_dir"]] = (r["_path"], r["length_m"])
    for r in rows:
        if r["_kind"] == "route" and r["_dir"] in optimum:
            r["length_ratio"] = measures.length_ratio(r["length_m"], optimum[r["_dir"]][1])


# --- runs -----------------------------------------------------------------------------------


def _events_beside(trace: str) -> str:
    p = Path(trace)
    for candidate in (p.with_suffix(".json"), p.with_name(p.stem + ".events.json")):
        if candidate.is_file():
            return str(candidate)
    raise UsvError(f"{trace}: no events JSON beside it ({p.with_suffix('.json').name} or "
                   f"{p.stem}.events.json); give it with --events")  # fmt: skip


def _run_row(path: str, events_path: str) -> dict:
    trace = read_trace(path)
    events = read_events(events_path)
    run = events.get("run")
    if not isinstance(run, dict):
        raise UsvError(f"{events_path}: no run object (written by an older usvtool simulate? "
                       "run the simulation again)")  # fmt: skip
    encounters = events.get("encounters")
    if not isinstance(encounters, list) or not all(isinstance(e, dict) for e in encounters):
        raise UsvError(f"{events_path}: encounters must be a list of objects")
    if trace.ships[0] != OWN:
        raise UsvError(f"{path}: the first ship is {trace.ships[0]!r}, not {OWN!r}")
    try:
        intervals = [(float(e["onset_s"]), None if e["released_s"] is None
                      else float(e["released_s"]))
                     for e in encounters if e.get("class", "none") != "none"]  # fmt: skip
        dt = float(run.get("dt") or (np.median(np.diff(trace.t)) if trace.n_steps > 1 else 1.0))
    except (KeyError, TypeError, ValueError) as exc:
        raise UsvError(f"{events_path}: bad encounter or run entry ({exc})") from None
    own_x, own_y = trace.x[:, 0], trace.y[:, 0]
    tx, ty = trace.x[:, 1:], trace.y[:, 1:]
    track = np.column_stack([own_x, own_y])
    sampled = measures.track_samples(track, dt)
    arrived = run.get("arrived")
    completed = bool(arrived) and not run.get("collision") and not run.get("controller_failed")
    return {
        "_kind": "run",
        "_path": path,
        "run": path,
        "scenario": run.get("scenario", events.get("scenario")),
        "controller": run.get("controller", events.get("controller")),
        "_parameters": run.get("parameters"),
        "seed": run.get("seed"),
        "arrived": arrived,
        "collision": run.get("collision"),
        "controller_failed": True if run.get("controller_failed") else None,
        "length_m": float(measures.path_length(track)),
        "turns": int(measures.turns(sampled)),
        "mot": float(measures.mot(sampled)),
        "arrival_time_s": float(trace.t[-1]) if arrived else None,
        **measures.run_distances(
            own_x, own_y, tx, ty, measures.encounter_steps(trace.t, intervals)
        ),
        "domain_intrusion_s": run.get("domain_intrusion_s"),
        "encounters": len(intervals),
        **colregs_counts(encounters, completed),
    }


def verdict(encounter: dict, completed: bool) -> str:
    """The count of :data:`VERDICTS` an encounter of a run falls in: ``not_judged`` when the
    run did not arrive or collided (``completed`` false) or the encounter has no verdict
    (``compliant`` null); else ``noncompliant`` when a rule failed, ``compliant_excused`` when
    it is compliant only because a Rule 2 departure record excused failed rules
    (``excused_rules`` not empty), else ``compliant`` (docs/colregs.md, "Counting")."""
    if not completed or encounter.get("compliant") is None:
        return "not_judged"
    if not encounter["compliant"]:
        return "noncompliant"
    return "compliant_excused" if encounter.get("excused_rules") else "compliant"


def colregs_counts(encounters: list[dict], completed: bool) -> dict:
    """A run's COLREGs columns from its events' encounters (those of class ``none`` are
    targets without one, not counted): the :data:`VERDICTS` counts, ``judged`` (the first
    three), and the rules failed and excused in its judged encounters (sorted, unique)."""
    counts = dict.fromkeys(VERDICTS, 0)
    failed, excused = set(), set()
    for e in encounters:
        if e.get("class", "none") == "none":
            continue
        judged = verdict(e, completed)
        counts[judged] += 1
        if judged != "not_judged":
            failed.update(e.get("failed_rules") or [])
            excused.update(e.get("excused_rules") or [])
    return {"judged": sum(counts.values()) - counts["not_judged"], **counts,
            "failed_rules": sorted(failed), "excused_rules": sorted(excused)}  # fmt: skip


def _run_rates(rows: list[dict], controller: str | None) -> None:
    if controller is None:
        return
    refs: dict[tuple, dict] = {}
    for r in rows:
        if r["_kind"] == "run" and r["controller"] == controller:
            key = (r["scenario"], r["seed"])
            if key in refs:
                raise UsvError(f"{r['run']}: a second run of {controller} on scenario "
                               f"{key[0]} with seed {key[1]} (after {refs[key]['run']}): "
                               "the reference is ambiguous")  # fmt: skip
            refs[key] = r
    for r in rows:
        if r["_kind"] != "run":
            continue
        r["reference_controller"] = controller
        ref = refs.get((r["scenario"], r["seed"]))
        if ref is None:
            continue
        for name in ("closest_distance", "average_distance"):
            r[f"{name}_rate"] = measures.optimisation_rate(r[f"{name}_m"], ref[f"{name}_m"])


# --- formatting -----------------------------------------------------------------------------


def _rounded(column: str, value):
    if value is None:
        return None
    if column in DECIMALS and not isinstance(value, bool):
        return round(float(value), DECIMALS[column]) + 0.0  # no -0.0
    return value


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, list):
        return ";".join(str(v) for v in value)
    return str(value)
