"""usvtool.pipeline: the bundled pipelines read, their matrices expand into plain data, and bad
files give one line naming the file and the field. (Their command lines and the Make fragment
are the batch's: tests/batch/test_commands.py, tests/batch/test_make_fragment.py.)"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from usvtool.cli.batch import stage_names
from usvtool.errors import UsvError
from usvtool.pipeline import (
    BUNDLED,
    CLAIM_METRICS,
    ClaimSpec,
    Ends,
    Names,
    Variant,
    claims_text,
    load,
    read_claims,
)

ROOT = Path(__file__).resolve().parent.parent
NAMES = stage_names()


@pytest.fixture(scope="module")
def bundled():
    return load(BUNDLED, NAMES)


def test_the_bundled_pipeline_reads(bundled):
    assert BUNDLED == ROOT / "pipelines" / "report.yaml"
    assert bundled.root == ROOT
    assert all((ROOT / c.source).is_file() for c in bundled.charts.values())
    assert list(bundled.routes) == ["report"]
    matrix = bundled.routes["report"]
    assert set(matrix.charts) == set(bundled.charts) - {"us4md81m"}
    assert matrix.seed == 1 and matrix.attempts == 5
    assert dict(bundled.charts["env1"].options) == {"cell-size": 1, "margin": 3}
    assert bundled.charts["grid20"].options == (("cell-size", 1), ("no-swell", True),
                                                ("occupancy", 0.5))  # fmt: skip
    assert bundled.charts["us4md81m"].ends is None


def test_a_route_matrix_expands_into_charts_x_algorithms_x_seeds(bundled):
    jobs = bundled.route_jobs()
    m = bundled.routes["report"]
    assert len(jobs) == len(m.charts) * len(m.algorithms) == 8 * 13
    assert len({(j.chart, j.algorithm) for j in jobs}) == len(jobs)
    job = next(j for j in jobs if j.chart == "us5ma12m" and j.algorithm == "iwso")
    assert job.ends == m.ends["us5ma12m"] == Ends((-70.93391, 42.32119), (-70.79426, 42.31806),
                                                  "lonlat")  # fmt: skip
    assert (job.seed, job.attempts, job.options) == (1, 5, ())
    # with the stages' names, an exact planner is one job without a seed
    exact = [j for j in bundled.route_jobs(NAMES) if j.algorithm in ("anyangle", "astar")]
    assert len(exact) == 2 * 8 and {j.seed for j in exact} == {None}


def test_the_simulation_matrix_is_scenarios_x_controllers_x_seeds(bundled):
    sim = bundled.simulation
    assert sim.controllers == ("dwa", "gdwa", "ccdwa", "udwa") and sim.seeds == (1,)
    expected = sorted(p.relative_to(ROOT).as_posix()
                      for p in (ROOT / "charts/scenarios").glob("*.yaml"))  # fmt: skip
    assert list(sim.scenarios) == expected
    assert len(bundled.simulation_jobs()) == len(expected) * 4


def test_full_and_ci_read_with_the_stages_names():
    full = load(ROOT / "pipelines" / "full.yaml", NAMES)
    assert full.charts == load(BUNDLED).charts  # included, not repeated
    env = full.routes["env"]
    assert env.seeds == tuple(range(25)) and env.charts == ("env1", "env2")
    assert {"wso", "iwso", "ssa", "issa", "pso", "gwo", "woa", "mrfo", "boa"} <= set(
        full.functions.algorithms)
    assert full.functions.functions == tuple(f"F{i}" for i in range(1, 11))
    # env: 9 optimizers and iwso+g x 25 seeds + 2 exact planners, on 2 charts; grid20: 3 x 50
    # + anyangle
    routes = full.route_jobs(NAMES)
    assert sum(j.matrix == "env" for j in routes) == 2 * (10 * 25 + 2)
    assert sum(j.matrix == "grid20" for j in routes) == 3 * 50 + 1
    ci = load(ROOT / "pipelines" / "ci.yaml", NAMES)
    assert len(ci.route_jobs(NAMES)) + len(ci.simulation_jobs()) + len(ci.function_jobs()) < 120


def write(tmp_path: Path, data: dict) -> Path:
    """A pipeline in tmp_path with one chart file, from the bundled one edited by the test."""
    (tmp_path / "map.geojson").write_text("{}")
    path = tmp_path / "p.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def minimal() -> dict:
    return {
        "charts": {"m": {"source": "map.geojson", "options": {"cell-size": 1},
                         "start": [1, 1], "goal": [5, 5]}},  # fmt: skip
        "routes": {"a": {"charts": ["m"], "algorithms": ["iwso", "astar"], "seeds": [1]}},
    }


def test_a_minimal_pipeline_reads(tmp_path):
    p = load(write(tmp_path, minimal()), NAMES)
    assert [(j.chart, j.algorithm, j.seed) for j in p.route_jobs(NAMES)] == [("m", "iwso", 1),
                                                                              ("m", "astar", None)]
    assert p.simulation is None and p.functions is None and p.routes["a"].attempts == 1


def test_a_seed_range_counts_from_first(tmp_path):
    data = minimal()
    data["routes"]["a"]["seeds"] = {"first": 3, "count": 4}
    data["functions"] = {"functions": ["F1", "F2"], "algorithms": ["pso"], "seeds": [7, 9]}
    p = load(write(tmp_path, data), NAMES)
    assert p.routes["a"].seeds == (3, 4, 5, 6)
    assert [j.seed for j in p.route_jobs() if j.algorithm == "iwso"] == [3, 4, 5, 6]
    assert p.function_jobs() == [("F1", "pso", 7), ("F1", "pso", 9), ("F2", "pso", 7),
                                 ("F2", "pso", 9)]  # fmt: skip
    assert (p.functions.pop, p.functions.iters, p.functions.dim) == (50, 300, 30)


def test_a_labelled_matrix_names_its_routes_chart_label(tmp_path):
    data = minimal()
    data["routes"]["b"] = {"charts": ["m"], "algorithms": ["iwso"], "seeds": [1],
                           "options": {"waypoints": 11}, "label": "w11"}  # fmt: skip
    p = load(write(tmp_path, data), NAMES)
    assert [(j.matrix, j.case, j.chart) for j in p.route_jobs(NAMES)] == [
        ("a", "m", "m"), ("a", "m", "m"), ("b", "m-w11", "m")]
    # a label whose case would be a chart's name is refused
    data["charts"]["m-w11"] = dict(data["charts"]["m"])
    with pytest.raises(UsvError, match=r"routes\.b\.label: its case 'm-w11' is a chart's name"):
        load(write(tmp_path, data), NAMES)


def edit(data: dict, dotted: str, value) -> dict:
    *parents, last = dotted.split(".")
    node = data
    for key in parents:
        node = node[key]
    if value is KeyError:
        del node[last]
    else:
        node[last] = value
    return data


FUNCS = {"functions": ["F1"], "algorithms": ["pso"], "seeds": [1]}
SIM = {"scenarios": ["map.geojson"], "controllers": ["dwa"], "seeds": [1]}


@pytest.mark.parametrize(
    "dotted, value, field, words",
    [
        ("charts.m.source", KeyError, "charts.m.source", "missing"),
        ("routes.a.seeds", KeyError, "routes.a.seeds", "missing"),
        ("charts.m.source", "nowhere.geojson", "charts.m.source", "nowhere.geojson: no such file"),
        ("charts.m.start", [1], "charts.m.start", "two numbers"),
        ("charts.m.start", ["a", 2], "charts.m.start", "two numbers"),
        ("charts.m.goal", KeyError, "charts.m.goal", "missing"),
        ("charts.m.frame", "lonlat", "charts.m.start", "lon, lat"),  # start [200, 1]
        ("routes.a.charts", ["m", "x"], "routes.a.charts[1]", "unknown chart 'x'"),
        ("routes.a.algorithms", ["iwso", "zzz"], "routes.a.algorithms[1]",
         "unknown algorithm 'zzz'"),
        ("routes.a.algorithms", ["iwso", "iwso"], "routes.a.algorithms", "named twice"),
        ("routes.a.seeds", {"first": 1, "count": 0}, "routes.a.seeds.count", "integer >= 1"),
        ("routes.a.seeds", {"first": -1, "count": 3}, "routes.a.seeds.first", "integer >= 0"),
        ("routes.a.seeds", {"first": 1}, "routes.a.seeds.count", "missing"),
        ("routes.a.seeds", {"first": 1, "count": 2, "step": 2}, "routes.a.seeds.step",
         "unknown field"),
        ("routes.a.seeds", "1-5", "routes.a.seeds", "a list of seeds or {first: F, count: N}"),
        ("routes.a.seeds", [1, 2, 1], "routes.a.seeds", "named twice: 1"),
        ("routes.a.seeds", [1, 2.5], "routes.a.seeds[1]", "integer >= 0"),
        ("routes.a.attempts", 0, "routes.a.attempts", "integer >= 1"),
        ("routes.a.options", {"seed": 2}, "routes.a.options.seed", "set by the matrix"),
        ("routes.a.colour", "red", "routes.a.colour", "unknown field"),
        ("routes.a.label", "w/11", "routes.a.label", "not a valid label"),
        ("routes.a.label", 11, "routes.a.label", "not a valid label"),
        ("charts.m.options", {"cell-size": [1]}, "charts.m.options.cell-size", "expected a number"),
        ("functions", dict(FUNCS, functions=["F11"]), "functions.functions[0]",
         "unknown function 'F11'"),
        ("functions", dict(FUNCS, algorithms=["astar"]), "functions.algorithms[0]",
         "unknown optimizer 'astar'"),
        ("functions", dict(FUNCS, pop=1), "functions.pop", "integer >= 2"),
        ("simulation", dict(SIM, controllers=["dwa", "xdwa"]), "simulation.controllers[1]",
         "unknown controller 'xdwa'"),
        ("simulation", dict(SIM, reference_controller="udwa"),
         "simulation.reference_controller", "not one of the controllers"),
        ("simulation", dict(SIM, seeds={"first": 0, "count": -2}), "simulation.seeds.count",
         "integer >= 1"),
    ],
)  # fmt: skip
def test_errors_name_the_file_and_the_field(tmp_path, dotted, value, field, words):
    data = minimal()
    if dotted == "charts.m.frame":
        data["charts"]["m"]["start"] = [200, 1]
    path = write(tmp_path, edit(data, dotted, value))
    with pytest.raises(UsvError) as info:
        load(path, NAMES)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: {field}: ")
    assert words in message


@pytest.mark.parametrize(
    "where, option, value",
    [
        ("charts.m.options", "summary", "/abs/x.json"),
        ("charts.m.options", "summary", "../../../x.json"),
        ("charts.m.options", "preview", "p.png"),
        ("charts.m.options", "output", "g.tif"),
        ("routes.a.options", "summary", "/abs/x.json"),
        ("routes.a.options", "output", "r.geojson"),
    ],
)
def test_an_option_naming_an_output_file_is_refused(tmp_path, where, option, value):
    """usvtool batch names a job's outputs (in the job's directory): an option naming another
    would write outside -o DIR. Which options name outputs: the commands' declarations."""
    data = minimal()
    node = data
    for part in where.split("."):
        node = node.setdefault(part, {})
    node[option] = value
    path = write(tmp_path, data)
    with pytest.raises(UsvError) as info:
        load(path, NAMES)
    assert str(info.value) == (f"{path}: {where}.{option}: names an output file: usvtool batch "
                               "writes every output of a job in the job's directory under -o "
                               "DIR")  # fmt: skip


def test_an_option_naming_an_input_file_is_read_relative_to_the_root(tmp_path):
    data = minimal()
    data["charts"]["m"]["options"]["cutline"] = "cut.geojson"
    path = write(tmp_path, data)
    with pytest.raises(UsvError) as info:
        load(path, NAMES)
    assert str(info.value) == f"{path}: charts.m.options.cutline: cut.geojson: no such file"
    (tmp_path / "cut.geojson").write_text("{}")
    chart = load(path, NAMES).charts["m"]
    assert chart.options == (("cell-size", 1), ("cutline", tmp_path / "cut.geojson"))
    # without the stages' names: as written, relative to the root
    assert load(path).charts["m"].options == (("cell-size", 1), ("cutline", "cut.geojson"))


def test_without_names_any_algorithm_reads(tmp_path):
    data = edit(minimal(), "routes.a.algorithms", ["zzz"])
    assert load(write(tmp_path, data)).routes["a"].algorithms == ("zzz",)


def test_a_chart_without_ends_cannot_be_routed(tmp_path):
    data = minimal()
    del data["charts"]["m"]["start"], data["charts"]["m"]["goal"]
    with pytest.raises(UsvError, match=r"p\.yaml: routes\.a\.charts\[0\]: chart 'm' has no start"):
        load(write(tmp_path, data))


def test_a_name_given_twice_is_refused_with_its_line(tmp_path):
    (tmp_path / "map.geojson").write_text("{}")
    path = tmp_path / "p.yaml"
    path.write_text("charts:\n  m: {source: map.geojson, start: [1, 1], goal: [2, 2]}\n"
                    "routes:\n  a: {charts: [m], algorithms: [iwso], seeds: [1]}\n"
                    "  a: {charts: [m], algorithms: [pso], seeds: [1]}\n")  # fmt: skip
    with pytest.raises(UsvError) as info:
        load(path)
    assert str(info.value) == f"{path}: line 5: 'a' named twice"


def test_include_takes_the_charts_of_another_pipeline(tmp_path):
    base = write(tmp_path, minimal())
    (tmp_path / "q.yaml").write_text(
        "include: p.yaml\nroutes:\n  b: {charts: [m], algorithms: [pso], seeds: [2]}\n")
    q = load(tmp_path / "q.yaml", NAMES)
    assert q.charts == load(base).charts and list(q.routes) == ["b"]
    (tmp_path / "r.yaml").write_text(
        "include: p.yaml\ncharts:\n  m: {source: map.geojson}\nfunctions: "
        "{functions: [F1], algorithms: [pso], seeds: [1]}\n")
    with pytest.raises(UsvError, match=r"r\.yaml: charts\.m: named twice \(also in p\.yaml\)$"):
        load(tmp_path / "r.yaml")
    (tmp_path / "s.yaml").write_text("include: s.yaml\nfunctions: {functions: [F1], "
                                     "algorithms: [pso], seeds: [1]}\n")  # fmt: skip
    with pytest.raises(UsvError, match=r"s\.yaml: include: s\.yaml: includes itself"):
        load(tmp_path / "s.yaml")


def test_a_scenario_glob_matching_nothing_is_refused(tmp_path):
    data = minimal()
    data["simulation"] = {"scenarios": ["none/*.yaml"], "controllers": ["dwa"], "seeds": [1]}
    with pytest.raises(
        UsvError, match=r"p\.yaml: simulation\.scenarios\[0\]: none/\*\.yaml: matches no file$"
    ):
        load(write(tmp_path, data))


def test_bad_yaml_and_a_missing_file_are_one_line(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("charts: [\n")
    with pytest.raises(UsvError) as info:
        load(path)
    assert str(info.value).startswith(f"{path}: not valid YAML") and "\n" not in str(info.value)
    with pytest.raises(UsvError, match="no such file"):
        load(tmp_path / "absent.yaml")


def test_names_know_exact_planners_with_shortening():
    names = Names(optimizers=("pso",), exact=("astar",), controllers=(), functions=())
    assert names.is_exact("astar+s") and not names.is_exact("pso")


# --- claims -----------------------------------------------------------------------------------


def with_claims(*claims: dict) -> dict:
    """The minimal pipeline with pso too, functions F1 x pso, gwo, the emergency family's runs
    of ccdwa and udwa, and ``claims``."""
    data = minimal()
    data["routes"]["a"]["algorithms"] = ["iwso", "astar", "pso"]
    data["functions"] = dict(FUNCS, algorithms=["pso", "gwo"])
    data["families"] = [{"family": "emergency", "scenes": {"first": 0, "count": 2},
                         "controllers": ["ccdwa", "udwa"], "seeds": [1]}]  # fmt: skip
    data["claims"] = list(claims)
    return data


SHORTER = {"id": "pso-shorter", "method": "pso", "rivals": ["iwso", "astar"],
           "metric": "length_m", "better": "lower", "cases": ["m"]}  # fmt: skip
SAFE = {"id": "udwa-safe", "method": "udwa", "metric": "collision", "better": "lower",
        "target": 0, "cases": ["emergency/head-on", "emergency"]}  # fmt: skip


def test_claims_read_with_their_kind_inferred_from_their_cases(tmp_path):
    cost = {"id": "pso-cheaper", "method": "pso", "rivals": ["gwo"], "metric": "final_cost",
            "better": "lower", "statistic": "std", "cases": ["F1"]}  # fmt: skip
    p = load(write(tmp_path, with_claims(SHORTER, SAFE, cost)), NAMES)
    shorter, safe, cheaper = p.claims
    assert shorter == ClaimSpec("pso-shorter", "routes", "pso", ("iwso", "astar"), "length_m",
                                "lower", "median", ("m",))  # fmt: skip
    assert (safe.kind, safe.statistic, safe.target, safe.share) == ("runs", "every", 0.0, 1.0)
    assert (cheaper.kind, cheaper.statistic) == ("functions", "std")
    # claims.json: what the batch writes, read back the same
    (tmp_path / "claims.json").write_text(claims_text(p.claims))
    assert read_claims(tmp_path / "claims.json") == p.claims
    assert json.loads(claims_text(p.claims))["claims"][0] == {
        "id": "pso-shorter", "kind": "routes", "method": "pso", "rivals": ["iwso", "astar"],
        "metric": "length_m", "better": "lower", "statistic": "median", "cases": ["m"]}
    assert load(write(tmp_path, minimal())).claims == ()


@pytest.mark.parametrize(
    "claim, field, words",
    [
        (dict(SHORTER, better="less"), "better", "must be lower or higher, not 'less'"),
        (dict(SHORTER, metric="length"), "metric", "'length' is not a metric of routes"),
        (dict(SHORTER, metric="closest_distance_m"), "metric",
         "'closest_distance_m' is not a metric of routes"),
        (dict(SAFE, metric="length_ratio"), "metric", "'length_ratio' is not a metric of runs"),
        (dict(SHORTER, method="gwo"), "method", "'gwo' is not run in case 'm' (the pipeline "
                                                "runs astar, iwso, pso there)"),
        (dict(SHORTER, rivals=["iwso", "woa"]), "rivals[1]", "'woa' is not run in case 'm'"),
        (dict(SHORTER, rivals=["iwso", "pso"]), "rivals[1]", "'pso' is the claim's method"),
        (dict(SHORTER, rivals=["iwso", "iwso"]), "rivals", "named twice: iwso"),
        (dict(SHORTER, rivals="iwso"), "rivals", "expected a list of methods"),
        (dict(SHORTER, cases=["m", "nowhere"]), "cases[1]", "'nowhere' is no case of the "
                                                            "pipeline"),
        (dict(SHORTER, cases=[]), "cases", "expected a non-empty list of cases"),
        (dict(SHORTER, cases=["m", "m"]), "cases", "named twice: m"),
        (dict(SHORTER, cases=["m", "F1"]), "cases", "cases of different kinds of job (m: "
                                                    "routes; F1: functions)"),
        (dict(SHORTER, cases=["m", "x/../y"]), "cases[1]", "not a case"),
        (dict(SHORTER, kind="functions"), "cases[0]", "'m' is no case of functions (it is of "
                                                      "routes)"),
        (dict(SHORTER, kind="boats"), "kind", "must be routes, runs, functions, not 'boats'"),
        (dict(SHORTER, statistic="every"), "statistic", "a relative claim's (with rivals): "
                                                        "median, mean, min, max, variance, std"),
        (dict(SHORTER, statistic="of-best"), "statistic", "not 'of-best'"),
        (dict(SHORTER, target=5), "target", "a claim with rivals has none"),
        (dict(SHORTER, share=0.5), "share", "a claim with rivals has none"),
        (dict(SHORTER, colour="red"), "colour", "unknown field"),
        (dict(SHORTER, id="a b"), "id", "not a valid name"),
        ({k: v for k, v in SHORTER.items() if k != "metric"}, "metric", "missing"),
        ({k: v for k, v in SAFE.items() if k != "target"}, "target", "missing (an absolute "
                                                                     "claim"),
        (dict(SAFE, statistic="median"), "statistic", "an absolute claim's (no rivals): every"),
        (dict(SAFE, target="nonsense"), "target", "'nonsense' is not a metric of runs"),
        (dict(SAFE, target=True), "target", "expected a number or a metric, got True"),
        (dict(SAFE, target=float("nan")), "target", "expected a number or a metric"),
        (dict(SAFE, share=1.5), "share", "expected a number in (0, 1], got 1.5"),
        (dict(SAFE, share=0), "share", "expected a number in (0, 1], got 0"),
        (dict(SAFE, cases=["emergency/sideways"]), "cases[0]", "no case of the pipeline"),
        (dict(SAFE, method="dwa"), "method", "'dwa' is not run in case 'emergency/head-on'"),
    ],
)  # fmt: skip
def test_each_bad_claim_is_one_line_naming_its_field(tmp_path, claim, field, words):
    path = write(tmp_path, with_claims(SAFE, claim))  # the second claim: claims[1]
    with pytest.raises(UsvError) as info:
        load(path, NAMES)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: claims[1].{field}: "), message
    assert words in message, message


def test_claims_given_twice_or_not_as_a_list_are_refused(tmp_path):
    path = write(tmp_path, with_claims(SHORTER, dict(SAFE, id="pso-shorter")))
    with pytest.raises(UsvError) as info:
        load(path, NAMES)
    assert str(info.value) == f"{path}: claims[1].id: 'pso-shorter' names two claims"
    data = with_claims()
    data["claims"] = {"a": SHORTER}
    with pytest.raises(UsvError, match=r"p\.yaml: claims: expected a list of claims"):
        load(write(tmp_path, data), NAMES)


def test_a_case_of_two_kinds_needs_the_claims_kind(tmp_path):
    data = with_claims(dict(SHORTER, rivals=["gwo"], metric="wall_time_s", cases=["F1"]))
    data["charts"]["F1"] = dict(data["charts"]["m"])
    data["routes"]["a"]["charts"] = ["m", "F1"]
    path = write(tmp_path, data)
    with pytest.raises(UsvError) as info:
        load(path, NAMES)
    assert str(info.value) == (f"{path}: claims[0].kind: missing: the cases are of functions, "
                               "routes; give one")  # fmt: skip
    data["claims"][0]["kind"] = "functions"
    assert load(write(tmp_path, data), NAMES).claims[0].kind == "functions"


def test_without_the_stages_names_a_familys_kinds_are_any(tmp_path):
    path = write(tmp_path, with_claims(SAFE))
    assert load(path).claims[0].cases == ("emergency/head-on", "emergency")


def test_a_claims_file_is_checked_as_a_pipelines_claims(tmp_path):
    path = tmp_path / "claims.json"
    good = ClaimSpec("c", "runs", "udwa", (), "collision", "lower", "every", ("emergency",), 0.0)
    path.write_text(claims_text([good]))
    assert read_claims(path) == (good,)
    data = json.loads(claims_text([good]))
    data["claims"][0]["better"] = "less"
    path.write_text(json.dumps(data))
    with pytest.raises(UsvError) as info:
        read_claims(path)
    assert str(info.value) == f"{path}: claims[0].better: must be lower or higher, not 'less'"
    del data["claims"][0]["kind"]
    path.write_text(json.dumps(data))
    with pytest.raises(UsvError, match=r"claims\.json: claims\[0\]\.kind: missing"):
        read_claims(path)
    path.write_text("{")
    with pytest.raises(UsvError, match=r"claims\.json: not JSON"):
        read_claims(path)


def test_the_claims_metrics_are_the_results_tables():
    """Every metric a claim may judge is a column of usvtool metrics (but those naming the job
    or giving words) or a timing, and each of those columns is one."""
    from usvtool.metrics import ROUTE_COLUMNS, RUN_COLUMNS
    from usvtool.report.values import BOOLEANS, NUMBERS
    from usvtool.results import TIMING_METRICS

    named = {"chart", "algorithm", "run", "scenario", "controller", "seed",
             "reference_controller", "failed_rules", "excused_rules"}  # fmt: skip
    assert set(CLAIM_METRICS["routes"]) == set(ROUTE_COLUMNS) - named | set(TIMING_METRICS)
    assert set(CLAIM_METRICS["runs"]) == set(RUN_COLUMNS) - named | {"wall_time_s"}
    assert set(CLAIM_METRICS["functions"]) == {"final_cost", "wall_time_s"}
    for metrics in CLAIM_METRICS.values():
        assert set(metrics) <= NUMBERS | BOOLEANS | {"collision"}


def test_the_documented_claims_example_reads(tmp_path):
    """docs/pipelines.md's example of claims is a pipeline that reads, each claim as it says."""
    doc = (ROOT / "docs" / "pipelines.md").read_text(encoding="utf-8")
    block = doc.split("## Claims", 1)[1].split("```yaml\n", 1)[1].split("```", 1)[0]
    path = tmp_path / "claims.yaml"
    path.write_text(block.replace("root: ..", f"root: {ROOT}").replace(
        "include: report.yaml", f"include: {ROOT / 'pipelines' / 'report.yaml'}"))
    guided, berth, safe, compliant = load(path, NAMES).claims
    assert (guided.kind, guided.rivals, guided.statistic) == ("routes", ("iwso", "wso"), "median")
    assert (berth.kind, berth.cases) == ("runs", ("emergency/head-on", "emergency/crossing"))
    assert (safe.statistic, safe.target, safe.share) == ("every", 0.0, 1.0)
    assert (compliant.target, compliant.share) == ("judged", 0.9)


CALM = {"name": "udwa-calm", "controller": "udwa", "params": {"weather": False}}


def test_a_variant_names_a_registered_controller_with_parameters(tmp_path):
    data = minimal()
    data["simulation"] = dict(SIM, controllers=["udwa", CALM], reference_controller="udwa-calm")
    p = load(write(tmp_path, data), NAMES)
    variant = Variant("udwa-calm", "udwa", (("weather", False),))
    assert p.simulation.controllers == ("udwa", "udwa-calm")
    assert p.simulation.programs == (variant,)
    assert p.program("udwa-calm") == variant and p.program("udwa") is None
    assert [c for _, c, _ in p.simulation_jobs()] == ["udwa", "udwa-calm"]
    assert load(write(tmp_path, data)).simulation.programs == (variant,)  # without the names


@pytest.mark.parametrize(
    "entry, field, words",
    [
        (dict(CALM, controller="xdwa"), "controller", "unknown controller 'xdwa' (known: "),
        (dict(CALM, controller="exec"), "controller", "exec runs a program"),
        (dict(CALM, controller=3), "controller", "not a controller's name: 3"),
        (dict(CALM, params={"wether": False}), "params.wether",
         "is not a parameter of udwa (known: "),
        (dict(CALM, params={"horizon": "far"}), "params.horizon", "must be a finite number"),
        (dict(CALM, params={"horizon": 0}), "params.horizon", "must be > 0 for udwa"),
        (dict(CALM, params={"horizon": [1]}), "params.horizon", "expected a number, true"),
        (dict(CALM, params=[1]), "params", "expected a mapping of parameter: value"),
        (dict(CALM, name="dwa"), "name", "'dwa' is a controller's name"),
        (dict(CALM, name="udwa calm"), "name", "not a valid name"),
        (dict(CALM, speed=2), "speed", "unknown field"),
        ({"name": "c"}, "exec", "missing"),
    ],
)  # fmt: skip
def test_a_bad_variant_is_refused_in_one_line_naming_its_field(tmp_path, entry, field, words):
    data = minimal()
    data["simulation"] = dict(SIM, controllers=["dwa", entry])
    path = write(tmp_path, data)
    with pytest.raises(UsvError) as info:
        load(path, NAMES)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: simulation.controllers[1].{field}"), message
    assert words in message, message


def test_a_variant_s_name_is_its_own_through_the_pipeline(tmp_path):
    data = minimal()
    data["simulation"] = dict(SIM, controllers=["dwa", CALM, CALM])
    path = write(tmp_path, data)
    with pytest.raises(UsvError, match="simulation.controllers: named twice: udwa-calm"):
        load(path, NAMES)
    data["simulation"] = dict(SIM, controllers=[CALM])
    data["families"] = [{"family": "imazu", "kinds": ["01"], "seeds": [1], "controllers": [
        dict(CALM, params={"weather": True})]}]  # fmt: skip
    path = write(tmp_path, data)
    with pytest.raises(UsvError) as info:
        load(path, NAMES)
    assert str(info.value) == (f"{path}: families[0].controllers: 'udwa-calm' names another "
                               "variant elsewhere in the pipeline (give it a name of its own)")
