"""Scene families as pipeline entries (docs/pipelines.md, docs/families.md): the reader checks
``families:`` against the stages' names, expands them into runs (kinds x scenes x controllers
x seeds) whose case pairs by scene, the batch keys and command lines, and the commands
``usvtool simulate --family`` and ``usvtool scene``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from usvtool.batch.jobs import expand
from usvtool.cli import cli
from usvtool.cli.batch import stage_names
from usvtool.errors import UsvError
from usvtool.pipeline import family_case, load, split_family_case

ROOT = Path(__file__).resolve().parent.parent
NAMES = stage_names()
CONTROLLERS = ("dwa", "gdwa", "ccdwa", "udwa", "udwa+")


def write(tmp_path: Path, families) -> Path:
    path = tmp_path / "p.yaml"
    path.write_text(yaml.safe_dump({"families": families}))
    return path


def entry(**fields) -> dict:
    return {"family": "emergency", "scenes": [0, 1], "controllers": ["dwa", "udwa"],
            "seeds": [1], **fields}  # fmt: skip


def test_the_bundled_families_pipeline_is_every_family_at_full_size():
    p = load(ROOT / "pipelines" / "families.yaml", NAMES)
    assert [e.family for e in p.families] == ["emergency", "iwso", "imazu", "wind"]
    assert all(e.controllers == CONTROLLERS for e in p.families)
    sizes = {e.family: (len(e.kinds), len(e.scenes)) for e in p.families}
    assert sizes == {"emergency": (3, 30), "iwso": (5, 30), "imazu": (22, 1), "wind": (1, 30)}
    jobs = p.family_jobs()
    assert len(jobs) == 5 * (3 * 30 + 5 * 30 + 22 + 30) == 1460
    # each kind's runs pair by scene: every scene has one run of every controller
    head_on = [j for j in jobs if j.case.startswith("emergency/head-on/")]
    assert len({j.case for j in head_on}) == 30
    assert {j.controller for j in head_on if j.case == "emergency/head-on/s029"} == set(
        CONTROLLERS)  # fmt: skip


def test_an_entry_expands_into_kinds_x_scenes_x_controllers_x_seeds(tmp_path):
    p = load(write(tmp_path, [entry(kinds=["crossing", "head-on"], seeds=[1, 2],
                                    options={"own_speed": 5})]), NAMES)  # fmt: skip
    jobs = p.family_jobs()
    assert len(jobs) == 2 * 2 * 2 * 2
    assert [(j.kind, j.scene, j.controller, j.seed) for j in jobs[:3]] == [
        ("crossing", 0, "dwa", 1),
        ("crossing", 0, "dwa", 2),
        ("crossing", 0, "udwa", 1),
    ]
    assert jobs[0].case == "emergency/crossing/s000" and jobs[0].options == (("own_speed", 5),)


def test_defaults_every_kind_and_imazu_takes_no_scenes(tmp_path):
    p = load(write(tmp_path, [entry(), {"family": "imazu", "controllers": ["udwa"],
                                        "seeds": [1]}]), NAMES)  # fmt: skip
    assert p.families[0].kinds == ("head-on", "crossing", "overtaking")
    assert p.families[1].scenes == (0,) and len(p.families[1].kinds) == 22
    assert {j.case for j in p.family_jobs() if j.family == "imazu"} >= {"imazu/22/s000"}


def test_without_the_stages_names_the_kinds_must_be_given(tmp_path):
    p = load(write(tmp_path, [entry()]))
    with pytest.raises(UsvError, match="its kinds are not known"):
        p.family_jobs()
    assert len(load(write(tmp_path, [entry(kinds=["head-on"])])).family_jobs()) == 4


@pytest.mark.parametrize("families, field, words", [
    ([entry(family="emergencies")], "families[0].family", "unknown scene family 'emergencies'"),
    ([entry(kinds=["abeam"])], "families[0].kinds[0]", "unknown kind 'abeam'"),
    ([entry(scenes=None)], "families[0].scenes", "expected a list of seeds"),
    ([{"family": "emergency", "controllers": ["dwa"], "seeds": [1]}], "families[0].scenes",
     "missing"),
    ([{"family": "imazu", "scenes": [0], "controllers": ["dwa"], "seeds": [1]}],
     "families[0].scenes", "imazu is not seeded"),
    ([entry(controllers=["dwaa"])], "families[0].controllers[0]", "unknown controller 'dwaa'"),
    ([entry(options={"own_speed": -1})], "families[0].options.own_speed",
     "must be > 0 for family emergency, not -1"),
    ([entry(options={"speed": 3})], "families[0].options.speed",
     "is not a parameter of family emergency (known: own_speed, "),
    ([entry(options={"own-speed": 3})], "families[0].options.own-speed", "not a family option"),
    ([entry(options={"own_speed": [3]})], "families[0].options.own_speed", "a number or a word"),
    ([entry(), entry()], "families[1].name", "'emergency' names two entries"),
    ([entry(seeds=[1, 1])], "families[0].seeds", "named twice"),
    ([entry(depth=3)], "families[0].depth", "unknown field"),
    ({"family": "emergency"}, "families", "expected a list of family entries"),
])  # fmt: skip
def test_bad_entries_are_one_line_naming_the_field(tmp_path, families, field, words):
    path = write(tmp_path, families)
    with pytest.raises(UsvError) as err:
        load(path, NAMES)
    message = str(err.value)
    assert message.startswith(f"{path}: {field}") and words in message, message
    assert "\n" not in message


def test_two_entries_of_one_family_under_two_names(tmp_path):
    p = load(write(tmp_path, [entry(kinds=["head-on"]),
                              entry(kinds=["head-on"], name="slow", options={"own_speed": 4})]),
             NAMES)  # fmt: skip
    cases = {j.case for j in p.family_jobs()}
    assert cases == {"emergency/head-on/s000", "emergency/head-on/s001", "slow/head-on/s000",
                     "slow/head-on/s001"}  # fmt: skip


def test_the_case_splits_back_into_entry_kind_and_scene():
    assert family_case("iwso", "crossing-port", 12) == "iwso/crossing-port/s012"
    assert split_family_case("iwso/crossing-port/s012") == ("iwso", "crossing-port", 12)
    assert split_family_case("emergency/head-on/s1234") == ("emergency", "head-on", 1234)
    for other in ("env1-head-on", "a/b", "a/b/12", "a/b/s12", "a/b/c/s001"):
        assert split_family_case(other) is None


# ----------------------------------------------------------------------------- batch jobs


def test_the_batch_keys_a_run_by_its_scene_and_gives_its_command(tmp_path):
    base = [entry(kinds=["head-on"], scenes=[3], controllers=["udwa"])]
    job = expand(load(write(tmp_path, base), NAMES), NAMES)[0]
    assert job.kind == "runs" and job.case == "emergency/head-on/s003" and job.method == "udwa"
    assert job.args == ("simulate", "--family", "emergency", "--kind", "head-on", "--scene", "3",
                        "--controller", "udwa", "--seed", "1", "-o", "trace.csv", "--events",
                        "trace.events.json", "--scenario-out", "scenario.yaml")  # fmt: skip
    assert job.info == {"scene": {"family": "emergency", "kind": "head-on", "scene": 3,
                                  "options": {}}}  # fmt: skip
    same = expand(load(write(tmp_path, base), NAMES), NAMES)[0]
    assert same.key == job.key
    for change in ({"scenes": [4]}, {"options": {"own_speed": 6}}, {"seeds": [2]},
                   {"kinds": ["crossing"]}, {"controllers": ["ccdwa"]}):  # fmt: skip
        other = expand(load(write(tmp_path, [{**base[0], **change}]), NAMES), NAMES)[0]
        assert other.key != job.key, change
    renamed = expand(load(write(tmp_path, [{**base[0], "name": "x"}]), NAMES), NAMES)[0]
    assert renamed.key == job.key and renamed.case == "x/head-on/s003"  # the same run


def test_a_job_runs_the_scene_of_its_options(tmp_path, monkeypatch):
    p = load(write(tmp_path, [entry(kinds=["overtaking"], scenes=[2], controllers=["udwa"],
                                    options={"duration": 1.5, "own_speed": 6.5,
                                             "vessel": "udwa-usv"})]), NAMES)  # fmt: skip
    job = expand(p, NAMES)[0]
    assert "own_speed=6.5" in job.args and "vessel=udwa-usv" in job.args
    monkeypatch.chdir(tmp_path)
    r = CliRunner().invoke(cli, list(job.args))
    assert r.exit_code == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["scene"]["options"]["own_speed"] == 6.5 and summary["time_s"] == 1.5
    assert summary["scene"]["name"] == "emergency-overtaking-s002-duration=1.5-own_speed=6.5"


# ----------------------------------------------------------------------------- the commands


def test_simulate_family_writes_the_scene_it_runs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    args = ["simulate", "--family", "wind", "--kind", "halves", "--scene", "3",
            "--family-option", "duration=2", "--controller", "dwa", "-o", "a.csv",
            "--scenario-out", "scene.yaml"]  # fmt: skip
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["scene"]["draws"] == 1 and summary["scene"]["rejected"] == {}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "scene.wind.tif", "scene.yaml"]
    # the scene file alone runs the same run
    r = CliRunner().invoke(cli, ["simulate", "scene.yaml", "--controller", "dwa", "-o", "b.csv"])
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()


def test_scene_writes_a_scene_and_lists_the_families(tmp_path):
    out = tmp_path / "x.yaml"
    r = CliRunner().invoke(cli, ["scene", "--family", "iwso", "--kind", "static", "--scene", "1",
                                 "-o", str(out)])  # fmt: skip
    assert r.exit_code == 0, r.stderr
    assert json.loads(r.stdout)["files"] == [str(tmp_path / "x.map.tif")]
    assert "map: x.map.tif" in out.read_text()
    r = CliRunner().invoke(cli, ["scene", "--list"])
    listing = json.loads(r.stdout)
    assert set(listing) == {"emergency", "iwso", "imazu", "wind", "ais", "trafficgen"}
    assert listing["imazu"]["seeded"] is False and len(listing["imazu"]["kinds"]) == 22
    assert listing["emergency"]["options"]["own_speed"]["default"] == 7.0


@pytest.mark.parametrize("args, status, words", [
    (["simulate", "--family", "emergency", "--kind", "head-on", "-o", "t.csv"], 2,
     "--scenario-out: with --family"),
    (["simulate", "x.yaml", "--family", "emergency", "--kind", "head-on", "-o", "t.csv",
      "--scenario-out", "s.yaml"], 2, "give SCENARIO.yaml or --family"),
    (["simulate", "x.yaml", "--kind", "head-on", "-o", "t.csv"], 2, "--kind: only with --family"),
    (["simulate", "--family", "emergency", "-o", "t.csv", "--scenario-out", "s.yaml"], 2,
     "--family: needs --kind"),
    (["simulate", "--family", "emergency", "--kind", "head-on", "-o", "s.yaml",
      "--scenario-out", "s.yaml"], 1, "same file as"),
    (["simulate", "--family", "imazu", "--kind", "01", "--scene", "2", "-o", "t.csv",
      "--scenario-out", "s.yaml"], 1, "imazu is not seeded"),
    (["scene", "--family", "wind", "--kind", "halves", "--family-option", "ramp=300", "-o",
      "w.yaml"], 1, "no draw of 100 keeps its promise (100 forces [2, 3] off the line"),
    (["scene", "--family", "iwso", "--kind", "head-on", "--family-option", "own_speed=fast",
      "-o", "w.yaml"], 1, "--family-option own_speed must be a finite number, not 'fast'"),
    (["scene", "--list", "--family", "iwso"], 2, "--list: alone"),
])  # fmt: skip
def test_bad_family_commands_are_one_line_and_write_nothing(tmp_path, monkeypatch, args, status,
                                                             words):  # fmt: skip
    monkeypatch.chdir(tmp_path)
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == status, r.stderr
    assert words in r.stderr
    if status == 1:
        assert len(r.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
