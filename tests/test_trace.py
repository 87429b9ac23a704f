"""The simulation's files (:mod:`usvtool.trace`): trace CSV, events JSON and tracks GeoJSON."""

from __future__ import annotations

import json

import numpy as np
import pytest
from pyproj import Transformer

from usvtool.atomic import staged
from usvtool.errors import UsvError
from usvtool.trace import (
    HEADER,
    Trace,
    format_trace,
    read_events,
    read_trace,
    tracks_geojson,
    write_events,
    write_trace,
    write_tracks,
)

HEAD = ",".join(HEADER)


def random_trace(n=40, ships=("own", "t1", "t2"), seed=0) -> Trace:
    rng = np.random.default_rng(seed)
    k = len(ships)
    states = np.stack(
        [
            rng.uniform(-500, 500000, (n, k)),
            rng.uniform(-500, 4000000, (n, k)),
            rng.uniform(0, 360, (n, k)),
            rng.uniform(-1, 8, (n, k)),
            rng.uniform(-20, 20, (n, k)),
        ],
        axis=2,
    )
    t = np.cumsum(np.full(n, 0.1)) - 0.1  # 0, 0.1, 0.2 ... with the usual rounding
    return Trace.from_states(t, ships, states)


def test_round_trip_gives_the_rounded_arrays_and_the_same_bytes(tmp_path):
    trace = random_trace()
    first, second = tmp_path / "a.csv", tmp_path / "b.csv"
    write_trace(first, trace)
    back = read_trace(first)
    assert back.ships == ("own", "t1", "t2") and back.n_steps == 40
    np.testing.assert_array_equal(back.t, np.round(trace.t, 3))
    for name, decimals in [("x", 3), ("y", 3), ("heading", 3), ("speed", 4), ("yaw_rate", 4)]:
        tol = 0.6 * 10**-decimals
        np.testing.assert_allclose(getattr(back, name), getattr(trace, name), atol=tol, rtol=0)
    write_trace(second, back)
    assert first.read_bytes() == second.read_bytes()
    write_trace(second, trace)  # the same run, the same bytes
    assert first.read_bytes() == second.read_bytes()
    np.testing.assert_array_equal(back.states(), read_trace(second).states())
    assert back.ship("t1").shape == (40, 5)


def test_the_text_is_fixed_point_without_negative_zero(tmp_path):
    trace = Trace.from_states(
        [0.0, 0.1], ["own", "b"],
        [[[-0.0001, 2e-7, 359.9996, -0.00001, -0.0], [1e6, -3.5, -10.0, 2.0, 1e-5]],
         [[12.3456, 0.5, 0.0004, 4.0, -0.25], [1e6 + 0.5, -3.25, 720.25, 2.0, 0.0]]],
    )  # fmt: skip
    assert format_trace(trace).splitlines() == [
        HEAD,
        "0.000,own,0.000,0.000,0.000,0.0000,0.0000",  # 359.9996 rounds to 360 = 0
        "0.000,b,1000000.000,-3.500,350.000,2.0000,0.0000",  # headings modulo 360
        "0.100,own,12.346,0.500,0.000,4.0000,-0.2500",
        "0.100,b,1000000.500,-3.250,0.250,2.0000,0.0000",
    ]
    write_trace(tmp_path / "t.csv", trace)
    assert (tmp_path / "t.csv").read_bytes() == format_trace(trace).encode()


def test_steps_closer_than_the_written_resolution_are_refused():
    trace = Trace.from_states([0.0, 0.0004], ["own"], np.zeros((2, 1, 5)))
    with pytest.raises(UsvError, match="steps 0 and 1 both write t 0.000"):
        format_trace(trace)


@pytest.mark.parametrize(
    ("ships", "t", "message"),
    [
        (("a", "own"), [0, 1], "the first ship must be 'own', not 'a'"),
        (("own", "own"), [0, 1], "unique"),
        (("own", "a,b"), [0, 1], "'a,b' is not a ship name"),
        (("own", "b"), [1, 1], "strictly increasing"),
    ],
)
def test_a_trace_is_checked_on_construction(ships, t, message):
    with pytest.raises(UsvError, match=message):
        Trace.from_states(t, ships, np.zeros((2, 2, 5)))


def test_a_trace_refuses_nan_and_wrong_shapes():
    states = np.zeros((2, 1, 5))
    states[1, 0, 3] = np.nan
    with pytest.raises(UsvError, match="speed holds NaN"):
        Trace.from_states([0, 1], ["own"], states)
    with pytest.raises(UsvError, match=r"shape \(n, k, 5\)"):
        Trace.from_states([0, 1], ["own"], np.zeros((2, 1, 4)))
    with pytest.raises(UsvError, match=r"x has shape \(3, 1\), expected \(2, 1\)"):
        Trace([0, 1], ("own",), *np.zeros((5, 3, 1)))


GOOD = [
    HEAD,
    "0.000,own,0.000,0.000,0.000,4.0000,0.0000",
    "0.000,b,50.000,100.000,180.000,3.0000,0.0000",
    "0.100,own,0.000,0.400,0.000,4.0000,0.0000",
    "0.100,b,50.000,99.700,180.000,3.0000,0.0000",
]


def csv_file(tmp_path, lines, name="trace.csv"):
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_a_hand_written_trace_is_read(tmp_path):
    trace = read_trace(csv_file(tmp_path, GOOD))
    assert trace.ships == ("own", "b") and trace.t.tolist() == [0.0, 0.1]
    assert trace.y.tolist() == [[0.0, 100.0], [0.4, 99.7]]
    # later steps may list the targets in another order; windows line ends are read too
    swapped = GOOD[:1] + GOOD[1:3] + ["0.100,own,0,0.4,0,4,0", "0.100,b,50,99.7,180,3,0"]
    path = tmp_path / "crlf.csv"
    path.write_bytes(("\r\n".join(swapped) + "\r\n").encode())
    np.testing.assert_array_equal(read_trace(path).states(), trace.states())


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda rows: ["t,ship,x,y,heading,speed"] + rows[1:],
         "line 1: the header must be 't,ship,x,y,heading,speed,yaw_rate', not "
         "'t,ship,x,y,heading,speed'"),
        (lambda rows: rows[:3] + ["0.100,own,0.000,north,0.000,4.0000,0.0000"] + rows[4:],
         "line 4, column y: 'north' is not a number"),
        (lambda rows: rows[:2] + ["0.000,b,50.000,100.000,180.000,nan,0.0000"] + rows[3:],
         "line 3, column speed: 'nan' is not a finite number"),
        (lambda rows: rows[:3] + [rows[4], rows[3]],
         "line 4, column ship: the step at t 0.100 starts with 'b'; the own ship ('own') must "
         "come first"),
        (lambda rows: rows[:4],
         "line 4: the step at t 0.100 lacks ship 'b' (the first step has own, b)"),
        (lambda rows: rows[:4] + ["0.200,own,0,0,0,4,0", "0.200,b,1,1,1,1,0"],
         "line 4: the step at t 0.100 lacks ship 'b' (the first step has own, b)"),
        (lambda rows: rows[:3] + [r.replace("0.100", "-0.100") for r in rows[3:]],
         "line 4, column t: -0.100 is before the previous step's t 0.000 (t must increase)"),
        (lambda rows: rows + ["0.050,own,0,0,0,4,0", "0.050,b,1,1,1,1,0"],
         "line 6, column t: 0.050 is before the previous step's t 0.100 (t must increase)"),
        (lambda rows: rows + ["0.200,own,0,0,0,4,0", "0.200,c,1,1,1,1,0"],
         "line 7, column ship: 'c' at t 0.200 is not in the first step (own, b)"),
        (lambda rows: rows[:3] + [rows[3], rows[3]],
         "line 5, column ship: 'own' twice at t 0.100"),
        (lambda rows: rows[:2] + ["0.000,b,50.000,100.000,360.000,3.0000,0.0000"] + rows[3:],
         "line 3, column heading: 360.000 is not in [0, 360)"),
        (lambda rows: rows[:2] + ["0.000,b,50.000,100.000"] + rows[3:],
         "line 3: 4 fields, expected 7 (t,ship,x,y,heading,speed,yaw_rate)"),
        (lambda rows: rows[:2] + ["0.000,,50.000,100.000,180.000,3.0000,0.0000"] + rows[3:],
         "line 3, column ship: '' is not a ship name"),
        (lambda rows: rows[:1], "no rows after the header"),
    ],
)  # fmt: skip
def test_each_kind_of_bad_trace_is_one_line_naming_the_file_and_line(tmp_path, edit, message):
    path = csv_file(tmp_path, edit(list(GOOD)))
    with pytest.raises(UsvError) as info:
        read_trace(path)
    assert str(info.value) == f"{path}: {message}"


def test_missing_empty_and_binary_traces(tmp_path):
    with pytest.raises(UsvError, match="no such file"):
        read_trace(tmp_path / "nothing.csv")
    (tmp_path / "empty.csv").write_bytes(b"")
    with pytest.raises(UsvError, match="empty file"):
        read_trace(tmp_path / "empty.csv")
    (tmp_path / "bin.csv").write_bytes(b"\xff\xfe\x00t")
    with pytest.raises(UsvError, match="not UTF-8 text"):
        read_trace(tmp_path / "bin.csv")


def test_events_are_deterministic_json_objects(tmp_path):
    path = tmp_path / "events.json"
    encounter = {"target": "b", "type": "head-on", "t_cpa": np.float64(12.5),
                 "dcpa_m": np.float32(40.25)}  # fmt: skip
    events = {"collisions": [], "arrived": True, "encounters": [encounter], "steps": np.int64(400)}
    write_events(path, events)
    text = path.read_text()
    assert text.endswith("}\n") and text.index('"arrived"') < text.index('"collisions"')
    assert '  "steps": 400' in text
    assert read_events(path) == {
        "arrived": True, "collisions": [], "steps": 400,
        "encounters": [{"dcpa_m": 40.25, "t_cpa": 12.5, "target": "b", "type": "head-on"}],
    }  # fmt: skip
    again = tmp_path / "again.json"
    write_events(again, read_events(path))
    assert again.read_bytes() == path.read_bytes()


@pytest.mark.parametrize(
    ("events", "message"),
    [
        ({"dcpa": float("nan")}, "NaN or an infinite number"),
        ({"x": np.array([1.0, np.inf])}, "NaN or an infinite number"),
        ({"when": object()}, "not JSON data"),
        ([1, 2], "events must be a dict, not list"),
    ],
)
def test_bad_events_are_refused_before_any_file(tmp_path, events, message):
    path = tmp_path / "events.json"
    with pytest.raises(UsvError, match=message):
        write_events(path, events)
    assert not path.exists() and list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('{"a": 1,\n "b": }\n', "line 2, column 7: not JSON (Expecting value)"),
        ('{"a": NaN}\n', "not an events JSON file (NaN is not JSON)"),
        ("[1, 2]\n", "events must be a JSON object, not an array"),
    ],
)
def test_bad_events_files(tmp_path, text, message):
    path = tmp_path / "events.json"
    path.write_text(text)
    with pytest.raises(UsvError) as info:
        read_events(path)
    assert str(info.value) == f"{path}: {message}"


def test_tracks_in_lon_lat_for_a_utm_crs_agree_with_pyproj(tmp_path):
    from rasterio.crs import CRS

    # five steps of three ships in Boston harbour (UTM 19N), 100 m apart, heading north
    states = np.zeros((5, 3, 5))
    states[..., 0] = 331000.0 + 100.0 * np.arange(3)
    states[..., 1] = 4687000.0 + 10.0 * np.arange(5)[:, None]
    trace = Trace.from_states(np.arange(5.0), ["own", "t1", "t2"], states)
    tracks = tracks_geojson(trace, CRS.from_epsg(32619))
    assert tracks["type"] == "FeatureCollection" and "frame" not in tracks
    assert [f["properties"] for f in tracks["features"]] == [{"ship": s} for s in trace.ships]
    to_lonlat = Transformer.from_crs(32619, 4326, always_xy=True)
    for j, feature in enumerate(tracks["features"]):
        assert feature["geometry"]["type"] == "LineString"
        coords = np.array(feature["geometry"]["coordinates"])
        lon, lat = to_lonlat.transform(trace.x[:, j], trace.y[:, j])
        np.testing.assert_allclose(coords, np.column_stack([lon, lat]), atol=5.1e-8, rtol=0)
        assert ((-71.1 < coords[:, 0]) & (coords[:, 0] < -70.9)).all()
        assert all(len(repr(v).split(".")[1]) <= 7 for v in coords.ravel().tolist())
    write_tracks(tmp_path / "tracks.geojson", trace, "EPSG:32619")
    text = (tmp_path / "tracks.geojson").read_text()
    assert json.loads(text) == tracks and text.endswith("\n") and text.count("\n") == 1


def test_tracks_in_a_local_frame(tmp_path):
    states = [[[1.23456, 2.0, 0, 1, 0], [5, -0.0001, 0, 1, 0]]]
    trace = Trace.from_states([0.0], ["own", "b"], states)
    tracks = tracks_geojson(trace)
    assert tracks["frame"] == "local"
    assert list(tracks) == ["type", "frame", "features"]
    assert tracks["features"][0]["geometry"]["coordinates"] == [[1.235, 2.0], [1.235, 2.0]]
    assert tracks["features"][1]["geometry"]["coordinates"] == [[5.0, 0.0], [5.0, 0.0]]


def test_the_outputs_of_a_run_are_staged_together(tmp_path):
    trace = random_trace(n=3)
    paths = [tmp_path / "trace.csv", tmp_path / "events.json", tmp_path / "tracks.geojson"]
    with staged(*paths) as (trace_tmp, events_tmp, tracks_tmp):
        write_trace(trace_tmp, trace)
        write_events(events_tmp, {"arrived": False})
        write_tracks(tracks_tmp, trace)
        assert not any(p.exists() for p in paths)  # nothing renamed before the end
    assert read_trace(paths[0]).n_steps == 3 and read_events(paths[1]) == {"arrived": False}
    for p in paths:
        p.unlink()
    with pytest.raises(UsvError, match="NaN"), staged(*paths) as (trace_tmp, events_tmp, _):
        write_trace(trace_tmp, trace)
        write_events(events_tmp, {"dcpa": float("nan")})
    assert list(tmp_path.iterdir()) == []  # all or nothing: no trace without its events


def test_the_whole_column_reader_gives_the_line_readers_trace_bit_for_bit(tmp_path,
                                                                         monkeypatch):  # fmt: skip
    from usvtool import trace as module

    rng = np.random.default_rng(5)
    states = rng.uniform(-500, 500, (60, 3, 5))
    states[..., 2] = rng.uniform(0, 359.999, (60, 3))  # headings in [0, 360)
    path = tmp_path / "t.csv"
    write_trace(path, Trace.from_states(np.arange(60) * 0.1, ["own", "a", "b"], states))
    text = path.read_text(encoding="utf-8")
    fast = module._well_formed(text)
    assert fast is not None  # the writer's format takes the whole-column path
    monkeypatch.setattr(module, "_well_formed", lambda text: None)
    slow = read_trace(path)
    assert fast.ships == slow.ships == ("own", "a", "b")
    for name in ("t", "x", "y", "heading", "speed", "yaw_rate"):
        assert np.array_equal(getattr(fast, name), getattr(slow, name)), name
    monkeypatch.undo()
    # a later step listing its ships in another order is still a trace: the line reader's
    lines = text.splitlines()
    lines[5], lines[6] = lines[6], lines[5]  # step 2: own, b, a
    (tmp_path / "o.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    assert module._well_formed((tmp_path / "o.csv").read_text(encoding="utf-8")) is None
    reordered = read_trace(tmp_path / "o.csv")
    assert np.array_equal(reordered.x, slow.x)
