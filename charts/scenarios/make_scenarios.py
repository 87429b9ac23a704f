"""Write the generated files of the bundled scenarios (deterministic; README.md says what each is).

* ``routes/env1-iwso.geojson``, ``routes/env2-iwso.geojson``: the IWSO routes of the static runs
  (IWSO-DWA paper, Figs. 7h and 9h), planned on ``charts/env1.tif`` / ``env2.tif`` with the
  route matrix of ``pipelines/report.yaml`` (its seed, attempts and env ends: ``--algo iwso+s
  --seed 1 --attempts 5``, ``--start 10 10 --goal 490 490``) and ``--no-timing``
  (byte-identical per seed).
* ``grids/rudee_inlet.tif``: the navigation grid of NOAA chart 12205 inset 2 (Rudee Inlet), made
  by ``usvtool preprocess`` with the options of ``pipelines/report.yaml`` (none: the paper's rule,
  cells of 1.5 x 2.5 m = 3.75 m). It is 490 x 369 cells, under 10 kB compressed: no crop needed
  (``--bounds`` only applies to GeoJSON obstacle maps anyway).
* ``routes/rudee-inlet.geojson``: a route planned on that grid up Lake Rudee's channel, from
  :data:`RUDEE_START` to the goal of ``rudee_inlet`` in ``pipelines/report.yaml`` (its start
  lies 1.2 km away, in the south-west lake: a run from there would take four minutes of
  simulated time, too long for the test suite).
* ``wind/southeast-strong.tif``, ``wind/northwest-strong.tif``: the wind fields of the two wind
  runs (UDWA paper section 4.2, Fig. 18 a and b) over a :data:`WIND_SIZE` m square in the local
  frame (no CRS): bands ``wind_speed`` (m/s) and ``wind_from`` (compass degrees) in
  :data:`WIND_CELL` m cells, :data:`WIND_STRONG` m/s on one side of the diagonal y = x (the runs'
  start-goal line) and :data:`WIND_WEAK` m/s on the other, a linear ramp :data:`WIND_TRANSITION`
  m wide across the diagonal, everywhere from :data:`WIND_FROM`.

The scenario YAML files are written by hand (they carry their own comments).

Run: ``.venv/bin/python charts/scenarios/make_scenarios.py`` from the repository root (it calls
``.venv/bin/usvtool``, or ``usvtool`` on the PATH when there is no virtualenv).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

from usvtool.batch.commands import ends_args, option_args
from usvtool.pipeline import load

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
CHARTS = ROOT / "charts"

#: The route matrix of pipelines/report.yaml (`make report`'s seed, attempts and ends).
ROUTES = load().routes["report"]
#: Its options for an IWSO route (seed 1, 5 attempts) and the ends of env1 and env2 (the same).
PLAN_OPTIONS = ["--algo", "iwso+s", "--seed", str(ROUTES.seed), "--attempts", str(ROUTES.attempts)]
PLAN_OPTIONS += ["--no-timing"]
ENV_ENDS = ends_args(ROUTES.ends["env1"])

#: Rudee Inlet: the route's start, in Lake Rudee's channel (lon, lat), and the goal of
#: rudee_inlet's route (report.yaml), at the channel's east end below the fixed bridges.
RUDEE_START = (-75.978958, 36.828728)
RUDEE_GOAL = ROUTES.ends["rudee_inlet"].goal

#: Wind fields: a square of WIND_SIZE m in cells of WIND_CELL m (local frame, origin lower-left).
WIND_SIZE = 700.0
WIND_CELL = 10.0
#: Force 4 (Table 2: 5.5-7.0 m/s, the paper's maximum) and force 1 (0.3-1.5 m/s).
WIND_STRONG = 7.0
WIND_WEAK = 1.0
#: The width (m) of the linear ramp from WIND_WEAK to WIND_STRONG across the diagonal y = x, on
#: which the speed is their mean (4 m/s, force 3). Bilinear sampling between the cell centres
#: reproduces the ramp (it is linear in x - y) but for rounding its ends within a cell.
WIND_TRANSITION = 20.0
#: From the south-west (compass degrees): a following wind along the diagonal, so the two fields
#: are mirror images of each other about the start-goal line.
WIND_FROM = 225.0


def usvtool() -> str:
    local = ROOT / ".venv" / "bin" / "usvtool"
    if local.exists():
        return str(local)
    found = shutil.which("usvtool")
    if found is None:
        sys.exit("make_scenarios.py: no usvtool (.venv/bin/usvtool or on the PATH)")
    return found


def run(*args: str) -> None:
    """Run ``usvtool -q ARGS`` from the repository root (its JSON summary is discarded)."""
    subprocess.run([usvtool(), "-q", *args], cwd=ROOT, check=True, stdout=subprocess.DEVNULL)


def rel(path: Path) -> str:
    """The path relative to the repository root when it lies inside (as the grids record it)."""
    try:
        return str(path.relative_to(ROOT))
    except ValueError:
        return str(path)


def env_routes(out: Path) -> None:
    for env in ("env1", "env2"):
        target = out / "routes" / f"{env}-iwso.geojson"
        run("plan", rel(CHARTS / f"{env}.tif"), *ENV_ENDS, *PLAN_OPTIONS, "-o", rel(target))


def rudee(out: Path) -> None:
    grid = out / "grids" / "rudee_inlet.tif"
    options = option_args(load().charts["rudee_inlet"].options)
    run("preprocess", rel(CHARTS / "noaa" / "12205_2.KAP"), *options, "-o", rel(grid))
    start = [f"{v:.6f}" for v in RUDEE_START]
    goal = [f"{v:.6f}" for v in RUDEE_GOAL]
    route = out / "routes" / "rudee-inlet.geojson"
    run("plan", rel(grid), "--start-lonlat", *start, "--goal-lonlat", *goal, *PLAN_OPTIONS,
        "-o", rel(route))  # fmt: skip


def wind_field(strong_southeast: bool) -> tuple[np.ndarray, np.ndarray]:
    """(wind_speed, wind_from) rasters, row 0 the northern one: WIND_STRONG on one side of the
    diagonal y = x (south-east of it when ``strong_southeast``, else north-west), WIND_WEAK on the
    other, a linear ramp WIND_TRANSITION m wide between."""
    n = int(round(WIND_SIZE / WIND_CELL))
    centres = (np.arange(n) + 0.5) * WIND_CELL
    x, y = centres[None, :], (WIND_SIZE - centres)[:, None]
    southeast = (x - y) / np.sqrt(2.0)  # signed distance from the diagonal, > 0 south-east
    side = southeast if strong_southeast else -southeast
    strong = np.clip(0.5 + side / WIND_TRANSITION, 0.0, 1.0)
    speed = WIND_WEAK + (WIND_STRONG - WIND_WEAK) * strong
    return speed.astype(np.float32), np.full((n, n), WIND_FROM, np.float32)


def write_wind(path: Path, speed: np.ndarray, wind_from: np.ndarray) -> None:
    import rasterio
    from rasterio.transform import from_origin

    path.parent.mkdir(parents=True, exist_ok=True)
    profile = dict(
        driver="GTiff",
        height=speed.shape[0],
        width=speed.shape[1],
        count=2,
        dtype="float32",
        transform=from_origin(0.0, WIND_SIZE, WIND_CELL, WIND_CELL),
        compress="deflate",
    )
    tmp = path.with_suffix(".tmp.tif")
    with rasterio.open(tmp, "w", **profile) as ds:
        ds.write(speed, 1)
        ds.write(wind_from, 2)
        ds.set_band_description(1, "wind_speed")
        ds.set_band_description(2, "wind_from")
        ds.update_tags(1, units="m/s")
        ds.update_tags(2, units="degrees (compass, direction the wind comes from)")
        ds.update_tags(
            frame="local metres (no CRS): x east, y north from the lower-left corner",
            source="charts/scenarios/make_scenarios.py",
        )
    tmp.replace(path)


def winds(out: Path) -> None:
    for name, southeast in (("southeast-strong", True), ("northwest-strong", False)):
        write_wind(out / "wind" / f"{name}.tif", *wind_field(southeast))


def main(argv: list[str]) -> None:
    out = Path(argv[1]).resolve() if len(argv) > 1 else HERE
    for sub in ("routes", "grids", "wind"):
        (out / sub).mkdir(parents=True, exist_ok=True)
    env_routes(out)
    rudee(out)
    winds(out)


if __name__ == "__main__":
    main(sys.argv)
