"""A planned route and its file, the path GeoJSON: the contract between planning and later stages.

Path GeoJSON: a FeatureCollection holding one Feature whose geometry is a LineString (the
route's vertices, start first, goal last); :func:`read_path_geojson` also reads a bare Feature.

- With a CRS (a georeferenced grid) the coordinates are WGS84 lon/lat (RFC 7946), and the
  properties add ``crs`` (the grid's CRS, e.g. ``"EPSG:32619"``) and ``map_coordinates`` (the
  vertices in the grid's map metres, which readers use, so no reprojection round trip).
- Without one (a synthetic grid) the coordinates are the grid's local metres, x east and y north
  from its lower-left corner, and the property ``frame`` says so.
- Properties (:meth:`Route.figures`, in this order): ``algorithm``, ``parameters``, ``seed``
  (null for the exact planners), ``length_m`` (:func:`route_length`), ``turns``, ``mot``
  (:mod:`usvtool.measures`), ``fitness`` (the path problem's cost), ``planning_time_s`` (null
  when not recorded), ``collision_free`` (:func:`usvtool.collision.is_collision_free` on the
  written coordinates), ``convergence`` (best cost per iteration, metres; empty for the exact
  planners) and ``attempt`` (the optimizer run that gave the route; null for the exact
  planners); then ``frame``, or ``crs`` and ``map_coordinates``.

The file is JSON indented by one space with a trailing newline, written atomically.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field

import numpy as np

from usvtool import measures
from usvtool.errors import UsvError
from usvtool.grid import Grid

#: The ``frame`` property of a path GeoJSON in local metres.
LOCAL_FRAME = "local metres (no CRS): x east, y north from the grid's lower-left corner"


@dataclass
class Route:
    """A planned route: map coordinates ``points`` ``(m, 2)`` and its figures."""

    points: np.ndarray
    algorithm: str
    parameters: dict
    seed: int | None
    length_m: float
    turns: int
    mot: float
    fitness: float
    planning_time_s: float | None  # None: not recorded (--no-timing)
    collision_free: bool
    convergence: list[float] = field(default_factory=list)
    attempt: int | None = None  # the optimizer run that gave the route (None: exact planner)

    def figures(self) -> dict:
        """The route's figures (the GeoJSON properties and the plan summary share them)."""
        return {
            "algorithm": self.algorithm,
            "parameters": self.parameters,
            "seed": self.seed,
            "length_m": self.length_m,
            "turns": self.turns,
            "mot": self.mot,
            "fitness": self.fitness,
            "planning_time_s": self.planning_time_s,
            "collision_free": self.collision_free,
            "convergence": self.convergence,
            "attempt": self.attempt,
        }


def route_length(grid: Grid, points) -> float:
    """Length in metres of a route on ``grid``: :func:`length_in_metres` in its CRS."""
    return length_in_metres(points, grid.crs)


def length_in_metres(points, crs=None) -> float:
    """Length in metres of a polyline ``(m, 2)`` in map coordinates: geodesic (WGS84) in
    ``crs``, planar (:func:`usvtool.measures.path_length`) without one. The one route length:
    the plan's ``length_m`` and the metrics table's.

    >>> length_in_metres([(0, 0), (3, 4), (3, 10)])
    11.0
    """
    points = np.asarray(points, float)
    if crs is None:
        return float(measures.path_length(points))
    from usvtool.geodesy import geodesic_length, map_to_lonlat

    return geodesic_length(*map_to_lonlat(crs, points[:, 0], points[:, 1]))


def write_path_geojson(path: str | os.PathLike, route: Route, grid: Grid) -> None:
    """Write ``route`` as a GeoJSON FeatureCollection holding one LineString feature, atomically.

    With a CRS the coordinates are lon/lat (RFC 7946) and ``map_coordinates`` (with ``crs``)
    holds the grid's; without one they are the grid's local metres, and ``frame`` says so.
    """
    from usvtool.atomic import jsonable, write_text

    points = np.asarray(route.points, float)
    props = route.figures()
    if grid.crs is None:
        coords = points
        props["frame"] = LOCAL_FRAME
    else:
        from usvtool.geodesy import map_to_lonlat

        coords = np.column_stack(map_to_lonlat(grid.crs, points[:, 0], points[:, 1]))
        props["crs"] = grid.crs.to_string()
        props["map_coordinates"] = points.tolist()
    feature = {
        "type": "Feature",
        "geometry": {"type": "LineString", "coordinates": coords.tolist()},
        "properties": props,
    }
    text = json.dumps(
        {"type": "FeatureCollection", "features": [feature]}, indent=1, default=jsonable
    )
    write_text(path, text + "\n")


def read_path_geojson(path: str | os.PathLike) -> tuple[np.ndarray, dict]:
    """The map coordinates ``(m, 2)`` and the properties of a path GeoJSON."""
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
        feature = data["features"][0] if data.get("type") == "FeatureCollection" else data
        props = feature["properties"]
        coords = props.get("map_coordinates", feature["geometry"]["coordinates"])
        return np.asarray(coords, float), props
    except (OSError, ValueError, KeyError, IndexError, TypeError) as exc:
        raise UsvError(f"{path}: not a path GeoJSON ({exc})") from None
