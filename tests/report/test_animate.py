"""``usvtool animate``: a GIF, an MP4 and an HTML player of a short bundled run (the same bytes
twice), the player self-contained and escaped, its decimation bound checked against the full
trace by an independent interpolation, its size for 35 ships over 10 minutes, and bad inputs in
one line with nothing written."""

from __future__ import annotations

import io
import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml
from affine import Affine

from usvtool.grid import Grid, write_grid
from usvtool.trace import Trace, read_trace, write_events, write_trace

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "charts" / "scenarios" / "rudee-inlet-channel.yaml"
SMALL = ("--size", "320x240", "--speed", "10", "--fps", "4")
EVIL = "</script><script>alert(1)</script>"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """rudee-inlet-channel (a chart map, a route, a head-on encounter) cut to 16 s:
    trace.csv and trace.events.json, as usvtool batch names them."""
    from click.testing import CliRunner

    from usvtool.cli import cli

    d = tmp_path_factory.mktemp("run")
    data = yaml.safe_load(SCENARIO.read_text())
    data["sim"]["duration"] = 16
    for key in ("map", "route"):
        data[key] = str(SCENARIO.parent / data[key])
    (d / "s.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    r = CliRunner().invoke(cli, ["simulate", str(d / "s.yaml"), "-o", str(d / "trace.csv"),
                                 "--events", str(d / "trace.events.json")])  # fmt: skip
    assert r.exit_code == 0, r.output
    return d


def listing(d: Path) -> list[str]:
    return sorted(p.name for p in d.iterdir())


@pytest.mark.parametrize("suffix", [".gif", ".mp4", ".html"])
def test_each_format_for_a_bundled_run_the_same_bytes_twice(run, usv, tmp_path, suffix):
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        pytest.skip("ffmpeg is not installed (make test installs it as root)")
    outs = []
    for n in (1, 2):
        out = tmp_path / f"a{n}{suffix}"
        r = usv("animate", run / "trace.csv", "-o", out, *SMALL)
        assert r.exit_code == 0, r.stderr
        summary = json.loads(r.stdout)
        assert summary["output"] == str(out) and summary["bytes"] == out.stat().st_size
        assert summary["ships"] == 2 and summary["events"].endswith("trace.events.json")
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
    content = outs[0]
    if suffix == ".gif":
        from PIL import Image

        image = Image.open(io.BytesIO(content))
        assert content[:6] == b"GIF89a" and image.size == (320, 240)
        duration = read_trace(run / "trace.csv").t[-1]
        frames = int(duration // 2.5) + 1 + (duration % 2.5 > 1e-9)  # 2.5 s apart, and the end
        assert summary["frames"] == frames
        assert 1 < image.n_frames <= summary["frames"]  # Pillow merges identical frames
    elif suffix == ".mp4":
        assert content[4:8] == b"ftyp" and summary["frames"] > 5
    else:
        text = content.decode("utf-8")
        assert text.startswith("<!DOCTYPE html>") and 'class="usv-player"' in text
        data = player_json(text)
        assert [s["n"] for s in data["ships"]] == ["own", "channel-boat"]
        assert data["map"]["src"].startswith("data:image/png;base64,")
        assert data["route"] and data["goal"]
        kinds = {data["kinds"][m[2]] for m in data["marks"]}
        assert {"onset", "manoeuvre"} <= kinds


def player_json(text: str) -> dict:
    m = re.search(r'<script type="application/json" class="usv-data">(.*?)</script>', text, re.S)
    return json.loads(m.group(1))


def synthetic(ships: int, seconds: float, dt: float = 0.1, name_of=None, seed: int = 1):
    """A trace of ``ships`` (own first) over ``seconds`` and its events (no encounter): each
    ship on a course that turns slowly (sines of a few minutes) with a little heading noise
    (0.3 degrees a step), at 2-8 m/s, spread over 3 km, 10-200 m long."""
    rng = np.random.default_rng(seed)
    t = np.round(np.arange(0.0, seconds + dt / 2, dt), 3)
    n = t.size
    h0 = rng.uniform(0, 360, ships)
    amp = rng.uniform(0, 40, ships)
    period = rng.uniform(120, 400, ships)
    heading = (h0 + amp * np.sin(2 * np.pi * t[:, None] / period)
               + rng.normal(0, 0.3, (n, ships))) % 360  # fmt: skip
    speed = np.repeat(rng.uniform(2, 8, ships)[None], n, 0)
    a = np.radians(heading)
    x = rng.uniform(0, 3000, ships) + np.cumsum(speed * np.sin(a) * dt, axis=0)
    y = rng.uniform(0, 3000, ships) + np.cumsum(speed * np.cos(a) * dt, axis=0)
    names = ["own"] + [name_of(j) if name_of else f"ship{j}" for j in range(1, ships)]
    trace = Trace(t, names, np.round(x, 3), np.round(y, 3), np.round(heading, 3) % 360, speed,
                  np.zeros((n, ships)))  # fmt: skip
    lengths = [15.0] + [float(v) for v in rng.uniform(10, 200, ships - 1)]
    events = {
        "scenario": "synthetic", "controller": "none", "steps": [], "encounters": [],
        "run": {"scenario": "synthetic", "controller": "none", "goal": [1500.0, 1500.0],
                "goal_tolerance": 5.0, "ships": [{"name": s, "length": v}
                                                  for s, v in zip(names, lengths, strict=True)],
                "map": None, "route": None},
    }  # fmt: skip
    return trace, events


def synthetic_run(d: Path, ships: int, seconds: float, scenario: str = "synthetic",
                  **kwargs) -> Path:
    """:func:`synthetic` written as ``trace.csv`` and ``trace.events.json`` in ``d``."""
    trace, events = synthetic(ships, seconds, **kwargs)
    events["run"]["scenario"] = scenario
    write_trace(d / "trace.csv", trace)
    write_events(d / "trace.events.json", events)
    return d / "trace.csv"


def decoded(ship: dict, q: float):
    """A ship's key samples from the player's JSON, decoded here (not by the player's code):
    seconds, quanta x and y, and headings unwrapped along the shorter arc."""
    k = np.cumsum(np.asarray(ship["k"], float).reshape(-1, 4), axis=0)
    return k[:, 0] / 1000, k[:, 1], k[:, 2], np.degrees(np.unwrap(np.radians(k[:, 3])))


def test_the_player_of_35_ships_over_10_minutes_is_within_its_bound_and_100_kB(tmp_path):
    """The trace in memory (its CSV would take 10 s to write and read): 35 ships, 600 s at
    0.1 s. At every sample of the trace, the player's interpolated position and heading are
    within the stated bound of the recorded ones, checked in map metres."""
    from usvtool.report.animation.frames import TIMELINE_PX, fit_view
    from usvtool.report.animation.player import bounds, player
    from usvtool.report.animation.scene import scene_of

    trace, events = synthetic(35, 600.0)
    scene = scene_of(trace, events, tmp_path / "trace.events.json")
    page = player(scene, (800, 600), 10.0, 60.0, 0.5)
    assert len(page.html.encode("utf-8")) < 100_000
    assert (page.bound_m, page.bound_deg) == bounds(0.5)
    assert page.bound_m == pytest.approx(0.5 + 0.2 * 0.5 / np.sqrt(2)) and page.bound_deg == 2
    data = player_json(page.html)
    left, bottom = fit_view(scene.view, 800, 600 - TIMELINE_PX)[:2]
    ox, oy = round(left, 3), round(bottom, 3)
    q = data["q"]
    at = trace.t - trace.t[0]
    for j, ship in enumerate(data["ships"]):
        tk, xk, yk, hk = decoded(ship, q)
        x, y = ox + q * np.interp(at, tk, xk), oy + q * np.interp(at, tk, yk)
        assert np.hypot(x - trace.x[:, j], y - trace.y[:, j]).max() <= page.bound_m
        h = np.interp(at, tk, hk)
        assert np.abs((h - trace.heading[:, j] + 180) % 360 - 180).max() <= page.bound_deg
    assert page.keys < 35 * trace.n_steps / 20  # decimated


def test_the_player_is_self_contained_and_escapes_names(usv, tmp_path):
    other = "b&c\u2028d>"
    trace_path = synthetic_run(tmp_path, 3, 30.0, scenario=EVIL,
                               name_of=lambda j: EVIL if j == 1 else other)  # fmt: skip
    out = tmp_path / "p.html"
    r = usv("animate", trace_path, "-o", out)
    assert r.exit_code == 0, r.stderr
    text = out.read_text(encoding="utf-8")
    assert EVIL not in text and other not in text and "alert(1)</script>" not in text
    assert "<title>&lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt; / none</title>" in text
    assert text.count("<script") == 2 and text.count("</script>") == 2
    data = player_json(text)
    assert [s["n"] for s in data["ships"]] == ["own", EVIL, other]
    assert data["title"] == f"{EVIL} / none"
    addresses = set(re.findall(r"https?://[^\s\"'<>)]*", text))
    assert addresses <= {"http://www.w3.org/2000/svg"}  # the SVG namespace, a name
    for external in ("<link", "<img", "<iframe", "@import", "url(", " src=", "src:", "fetch(",
                     "XMLHttpRequest", "@font-face", "<object", "<embed"):  # fmt: skip
        assert external not in text, external
    assert "\u2028" not in text and "\u2029" not in text


def test_script_json_escapes_what_would_close_or_break_a_script():
    from usvtool.report.animation.player import script_json

    text = script_json({"n": "</script><!-- & \u2028\u2029 >"})
    assert not set("<>&\u2028\u2029") & set(text)
    assert json.loads(text) == {"n": "</script><!-- & \u2028\u2029 >"}


@pytest.fixture
def outdir(tmp_path):
    d = tmp_path / "out"
    d.mkdir()
    (d / "old.gif").write_bytes(b"earlier")
    return d


def one_line_error(r, *words):
    lines = r.stderr.strip().splitlines()
    assert lines and lines[-1].startswith("Error:"), r.stderr
    assert "Traceback" not in r.stderr
    for w in words:
        assert w in lines[-1], (w, lines[-1])


def test_a_trace_without_its_events_is_one_line(run, usv, tmp_path, outdir):
    lone = tmp_path / "lone.csv"
    lone.write_bytes((run / "trace.csv").read_bytes())
    r = usv("animate", lone, "-o", outdir / "old.gif")
    assert r.exit_code == 1
    one_line_error(r, "lone.csv", "lone.events.json", "--events")
    assert listing(outdir) == ["old.gif"] and (outdir / "old.gif").read_bytes() == b"earlier"


def test_a_map_in_another_crs_or_place_is_one_line(run, usv, tmp_path, outdir):
    r = usv("animate", run / "trace.csv", "--map", ROOT / "charts" / "env1.tif", "-o",
            outdir / "a.html")  # fmt: skip
    assert r.exit_code == 1
    one_line_error(r, "--map", "env1.tif", "CRS", "EPSG:32618")
    from rasterio.crs import CRS

    far = tmp_path / "far.tif"  # the trace's CRS, another place
    write_grid(far, Grid(np.zeros((10, 10), np.uint8), Affine(10, 0, 0, 0, -10, 100),
                         CRS.from_epsg(32618)))  # fmt: skip
    r = usv("animate", run / "trace.csv", "--map", far, "-o", outdir / "a.html")
    assert r.exit_code == 1
    one_line_error(r, "--map", "far.tif", "outside the map")
    assert listing(outdir) == ["old.gif"]


@pytest.mark.parametrize("args, code, words", [
    (["-o", "{out}/a.avi"], 2, ["-o", ".gif"]),
    (["-o", "{out}/a.gif", "--size", "800"], 2, ["--size", "WIDTHxHEIGHT"]),
    (["-o", "{out}/a.gif", "--size", "20x20"], 2, ["--size", "160"]),
    (["-o", "{out}/a.mp4", "--size", "321x240"], 2, ["--size", "even"]),
    (["-o", "{out}/a.gif", "--speed", "0"], 2, ["--speed"]),
    (["-o", "{out}/a.gif", "--fps", "0"], 2, ["--fps"]),
    (["-o", "{out}/a.gif", "--events", "{out}/none.json"], 1, ["none.json", "no such file"]),
    (["-o", "{out}/a.gif", "--speed", "0.001", "--fps", "60"], 1, ["--speed", "frames"]),
    (["-o", "{out}/no/a.gif"], 1, ["-o", "does not exist"]),
])  # fmt: skip
def test_bad_options_are_one_line_and_write_nothing(run, usv, outdir, args, code, words):
    args = [a.format(out=outdir) for a in args]
    r = usv("animate", run / "trace.csv", *args)
    assert r.exit_code == code, r.stderr
    one_line_error(r, *words)
    assert listing(outdir) == ["old.gif"]


def test_bad_files_are_one_line_naming_them(run, usv, tmp_path, outdir):
    bad = tmp_path / "bad.csv"
    bad.write_text("t,ship\n1,own\n")
    r = usv("animate", bad, "--events", run / "trace.events.json", "-o", outdir / "a.gif")
    assert r.exit_code == 1
    one_line_error(r, "bad.csv", "header")
    other = synthetic_run(tmp_path, 3, 5.0)  # another run's events
    r = usv("animate", run / "trace.csv", "--events", other.with_name("trace.events.json"),
            "-o", outdir / "a.gif")  # fmt: skip
    assert r.exit_code == 1
    one_line_error(r, "trace.events.json", "not the trace's ships")
    no_run = tmp_path / "norun.json"
    no_run.write_text('{"encounters": []}\n')
    r = usv("animate", run / "trace.csv", "--events", no_run, "-o", outdir / "a.gif")
    assert r.exit_code == 1
    one_line_error(r, "norun.json", "'run'")
    assert listing(outdir) == ["old.gif"]


def test_an_mp4_without_ffmpeg_says_what_to_install(run, usv, outdir, monkeypatch):
    monkeypatch.setattr(shutil, "which", lambda name, *a, **k: None)
    r = usv("animate", run / "trace.csv", "-o", outdir / "a.mp4", *SMALL)
    assert r.exit_code == 1
    one_line_error(r, "ffmpeg", "apt-get install ffmpeg")
    assert listing(outdir) == ["old.gif"]


def test_the_facade_gives_the_player_fragment_and_a_summary(run):
    from usvtool.report import AnimateOptions, animate

    result = animate(AnimateOptions(str(run / "trace.csv"), "html", size=(400, 300)))
    assert result.fragment.startswith('<div class="usv-player"')
    assert result.fragment in result.content.decode("utf-8")
    s = result.summary()
    assert s["format"] == "html" and s["bytes"] == len(result.content) and s["frames"] is None


def test_animate_imports_neither_the_report_sections_nor_scipy():
    """usvtool.report's entry points are imported when asked for: an animation does not pay
    for the comparison report's sections and SciPy (3-5 s of imports on a loaded machine)."""
    import subprocess
    import sys

    code = ("import sys\nfrom usvtool.report import AnimateOptions, animate\n"
            "from usvtool.report.animation import encode, frames, player, scene\n"
            "import usvtool.cli.animate\n"
            "bad = [m for m in sys.modules if m.startswith(('scipy', 'usvtool.report.sections',"
            " 'usvtool.report.build', 'usvtool.report.figures'))]\n"
            "assert not bad, bad\n")  # fmt: skip
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_a_failure_while_writing_leaves_no_output_nor_temporary(run, usv, outdir, monkeypatch):
    """The animation and its --summary are renamed into place together, or neither."""
    import usvtool.cli.options
    from usvtool.errors import UsvError

    def fail(path, summary):
        raise UsvError(f"{path}: no space left on device")

    monkeypatch.setattr(usvtool.cli.options, "write_summary", fail)
    r = usv("animate", run / "trace.csv", "-o", outdir / "old.gif", "--summary",
            outdir / "s.json", *SMALL)  # fmt: skip
    assert r.exit_code == 1
    one_line_error(r, "no space left")
    assert listing(outdir) == ["old.gif"] and (outdir / "old.gif").read_bytes() == b"earlier"


def test_names_are_drawn_as_text_in_a_gif(usv, tmp_path):
    """A scenario or ship name with Matplotlib's mathtext signs is drawn as it is."""
    trace_path = synthetic_run(tmp_path, 2, 5.0, scenario="a$\\frac{x$_{b}$ $",
                               name_of=lambda j: "$x^2$")  # fmt: skip
    r = usv("animate", trace_path, "-o", tmp_path / "a.gif", "--size", "200x160", "--speed",
            "10", "--fps", "2")  # fmt: skip
    assert r.exit_code == 0, r.stderr
