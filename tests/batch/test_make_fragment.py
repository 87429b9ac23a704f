"""usvtool.batch.make and ``usvtool batch --make-fragment``: the Make variables of a pipeline,
built from the batch's own command lines and file lists (tests/test_make.py runs Make on them)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
from click.testing import CliRunner

from usvtool.batch.jobs import expand
from usvtool.batch.make import fragment
from usvtool.cli import cli
from usvtool.cli.batch import stage_names
from usvtool.errors import UsvError
from usvtool.pipeline import BUNDLED, load

ROOT = Path(__file__).resolve().parents[2]
NAMES = stage_names()


def variables(text: str) -> dict[str, str]:
    """The fragment's ``NAME := value`` (and ``?=``) lines, continuation lines joined."""
    text = text.replace(" \\\n\t", " ")
    return {m[1]: m[2] for m in re.finditer(r"^(\w+) [:?]= ?(.*)$", text, re.MULTILINE)}


@pytest.fixture(scope="module")
def bundled():
    return load(BUNDLED, NAMES)


def test_the_fragment_names_every_chart_and_route_target(bundled):
    v = variables(fragment(bundled))
    assert v["GRIDS"].split() == list(bundled.charts)
    for name, chart in bundled.charts.items():
        assert v[f"CHART_SOURCE_{name}"] == chart.source
    assert v["ROUTES"].split() == [f"build/paths/{j.chart}/{j.algorithm}.geojson"
                                   for j in bundled.route_jobs()]  # fmt: skip
    assert v["ENDS_grid20"] == "--start 0.5 0.5 --goal 19.5 19.5"
    assert (v["SEED"], v["ATTEMPTS"], v["PLAN_OPTIONS"]) == ("1", "5", "")
    # the S-57 approach cell: its three update files, as its grid's key hashes them
    assert v["CHART_INPUTS_us4md81m"].split() == [f"charts/noaa/US4MD81M/US4MD81M.00{i}"
                                                  for i in (1, 2, 3)]  # fmt: skip
    assert v["CHART_FOLDERS"].split() == ["charts", "charts/noaa", "charts/noaa/US4MD81M"]


def test_make_gives_the_batch_jobs_own_arguments(bundled):
    """routes.mk's recipe, ``plan GRID $(ENDS_c) --algo A --seed $(SEED) --attempts
    $(ATTEMPTS) $(PLAN_OPTIONS)``, and charts.mk's, ``preprocess SOURCE $(PREPROCESS_c)``,
    give the words of the batch's jobs."""
    v = variables(fragment(bundled))
    jobs = expand(bundled, NAMES)
    grids = [j for j in jobs if j.kind == "grids"]
    assert len(grids) == 8
    for j in grids:
        assert list(j.args[2:-4]) == shlex.split(v[f"PREPROCESS_{j.case}"])
    seeded = [j for j in jobs if j.kind == "routes" and j.seed is not None]
    assert len(seeded) == 8 * 11
    for j in seeded:
        make = [*shlex.split(v[f"ENDS_{j.case}"]), "--algo", j.method, "--seed", v["SEED"],
                "--attempts", v["ATTEMPTS"], *shlex.split(v["PLAN_OPTIONS"])]  # fmt: skip
        assert list(j.args[2:-3]) == make


def test_an_option_file_is_relative_to_the_root_and_a_dependency_with_its_companions(tmp_path):
    for name in ("maps/m.geojson", "cut/cut.geojson", "cut/cut.geojson.aux.xml", "cut/x.txt"):
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_text("{}")
    (tmp_path / "p.yaml").write_text(
        "charts:\n  m: {source: maps/m.geojson, options: {cutline: cut/cut.geojson},\n"
        "      start: [1, 1], goal: [2, 2]}\n"
        "routes:\n  a: {charts: [m], algorithms: [astar], seeds: [1], options: {pop: 9}}\n"
    )
    v = variables(fragment(load(tmp_path / "p.yaml", NAMES)))
    assert v["PREPROCESS_m"] == "--cutline cut/cut.geojson"
    assert v["CHART_INPUTS_m"] == "cut/cut.geojson cut/cut.geojson.aux.xml"
    assert v["CHART_FOLDERS"] == "cut maps" and v["PLAN_OPTIONS"] == "--pop 9"


def test_the_fragment_needs_one_matrix_of_one_seed(tmp_path):
    with pytest.raises(UsvError, match=r"full\.yaml: routes: the Make fragment needs exactly one"):
        fragment(load(ROOT / "pipelines" / "full.yaml"))
    path = tmp_path / "p.yaml"
    path.write_text(
        "charts:\n  m: {source: m.geojson, start: [1, 1], goal: [2, 2]}\n"
        "routes:\n  a: {charts: [m], algorithms: [astar], seeds: [1, 2]}\n"
    )
    (tmp_path / "m.geojson").write_text("{}")
    with pytest.raises(UsvError, match=r"p\.yaml: routes\.a: 2 seeds, not one \(the Make "):
        fragment(load(path))
    path.write_text(path.read_text().replace("seeds: [1, 2]", "seeds: [1], label: w2"))
    with pytest.raises(UsvError, match=r"p\.yaml: routes\.a\.label: the Make fragment writes "):
        fragment(load(path))


def test_usvtool_batch_writes_the_fragment_and_runs_nothing(tmp_path, bundled):
    out = tmp_path / "pipeline.mk"
    r = CliRunner().invoke(cli, ["batch", str(BUNDLED), "--make-fragment", str(out)])
    assert r.exit_code == 0 and r.output == ""
    assert out.read_text() == fragment(bundled) and list(tmp_path.iterdir()) == [out]


def test_a_bad_pipeline_or_option_is_one_line(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(
        "charts:\n  m: {source: m.geojson, start: [1, 1], goal: [2, 2]}\n"
        "routes:\n  a: {charts: [m], algorithms: [astar], seeds: one}\n"
    )
    (tmp_path / "m.geojson").write_text("{}")
    out = tmp_path / "pipeline.mk"
    r = CliRunner().invoke(cli, ["batch", str(path), "--make-fragment", str(out)])
    assert r.exit_code == 1 and not out.exists()
    assert r.output == (f"Error: {path}: routes.a.seeds: expected a list of seeds or {{first: F, "
                        "count: N}, got 'one'\n")  # fmt: skip
    r = CliRunner().invoke(cli, ["batch", str(BUNDLED), "--make-fragment", str(out), "-j", "2"])
    assert r.exit_code == 2 and not out.exists()
    assert r.output.splitlines()[-1] == "Error: -j: not with --make-fragment (it runs no job)"
    r = CliRunner().invoke(cli, ["batch", str(BUNDLED), "--make-fragment", str(tmp_path / "no/f")])
    assert r.exit_code == 1 and r.output == (f"Error: --make-fragment {tmp_path}/no/f: directory "
                                             f"{tmp_path}/no does not exist\n")  # fmt: skip
