"""A registered controller with parameters under a name of its own in a pipeline (``{name:
NAME, controller: REGISTERED, params: {...}}``, docs/pipelines.md): its jobs' command lines
(``--controller REGISTERED --param k=v --label NAME``), keys that hold the controller, its
parameters and its plugin origin while a built-in job's key stays as it was, and a tiny batch
that pairs ``udwa`` with ``udwa`` without weather on the same scenes of a family."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

from usvtool.batch import jobs as batch_jobs
from usvtool.batch.jobs import expand
from usvtool.cli.batch import stage_names
from usvtool.pipeline import Variant, load
from usvtool.results import read_results

NAMES = stage_names()
CALM = "{name: udwa-calm, controller: udwa, params: {weather: false}}"
CASES = {"wind/halves/s001", "wind/halves/s002"}


def pipeline(root: Path, controllers: str = f"[udwa, {CALM}]") -> Path:
    """Two scenes of the wind family (cut to 3 s) with ``controllers``."""
    path = root / "p.yaml"
    path.write_text(f"""root: .
families:
  - family: wind
    kinds: [halves]
    scenes: [1, 2]
    controllers: {controllers}
    seeds: [1]
    options: {{duration: 3}}
""")
    return path


def test_a_variant_s_jobs_run_its_controller_with_its_parameters_under_its_name(tmp_path):
    p = load(pipeline(tmp_path), NAMES)
    assert p.families[0].programs == (Variant("udwa-calm", "udwa", (("weather", False),)),)
    jobs = {(j.case, j.method): j for j in expand(p, NAMES)}
    assert set(jobs) == {(c, m) for c in CASES for m in ("udwa", "udwa-calm")}
    calm = jobs["wind/halves/s001", "udwa-calm"]
    i = calm.args.index("--controller")
    assert calm.args[i:i + 6] == ("--controller", "udwa", "--param", "weather=false",
                                  "--label", "udwa-calm")  # fmt: skip
    assert calm.info["variant"] == {"controller": "udwa", "params": {"weather": False}}
    plain = jobs["wind/halves/s001", "udwa"]
    assert "--label" not in plain.args and "variant" not in plain.info


def test_a_variant_s_key_holds_its_controller_parameters_and_origin(tmp_path):
    path = pipeline(tmp_path)

    def keys(names=NAMES):
        return {j.label: j.key for j in expand(load(path, names), names)}

    before = keys()
    (tmp_path / "alone").mkdir()
    alone = pipeline(tmp_path / "alone", "[udwa]")  # the same runs without the variant
    assert {k: v for k, v in before.items() if "calm" not in k} == {
        j.label: j.key for j in expand(load(alone, NAMES), NAMES)}  # fmt: skip
    plugged = keys(replace(NAMES, plugins={"udwa": "usvplug 1.2"}))  # udwa from a plugin
    assert all(plugged[k] != before[k] for k in before)
    path.write_text(path.read_text().replace("weather: false", "weather: false, horizon: 4"))
    after = keys()
    changed = {label for label in before if before[label] != after[label]}
    assert changed == {label for label in before if "udwa-calm" in label} and len(changed) == 2


def test_a_built_in_job_s_key_is_as_before_variants(tmp_path, monkeypatch):
    """The key of an Imazu run of udwa, its code's hash fixed, as the code before variants
    gave it (computed by hand then)."""
    monkeypatch.setattr(batch_jobs, "code_hash", lambda kind: "code")
    path = tmp_path / "p.yaml"
    path.write_text("""root: .
families:
  - family: imazu
    kinds: ['01']
    controllers: [udwa]
    seeds: [1]
    options: {duration: 20}
""")
    [job] = expand(load(path, NAMES), NAMES)
    assert job.key == "4940c4b4f88475f5"
    assert job.args == ("simulate", "--family", "imazu", "--kind", "01", "--scene", "0",
                        "--family-option", "duration=20", "--controller", "udwa", "--seed",
                        "1", "-o", "trace.csv", "--events", "trace.events.json",
                        "--scenario-out", "scenario.yaml")  # fmt: skip


@pytest.mark.slow  # four short runs, in this process
def test_a_batch_pairs_a_controller_with_its_variant_on_the_same_scenes(tmp_path, inline_batch):
    path = pipeline(tmp_path)
    out = tmp_path / "out"
    ran = inline_batch(path, out)
    assert ran.exit_code == 0, ran.stderr
    assert ran.counts() == (4, 0, 0)
    rows = read_results(out / "metrics.csv")
    by_method: dict[str, set] = {}
    for r in rows:
        by_method.setdefault(r.method, set()).add((r.case, r.seed))
    assert by_method == {"udwa": {(c, 1) for c in CASES}, "udwa-calm": {(c, 1) for c in CASES}}
    weather = {}
    for folder in (out / "runs").iterdir():
        record = json.loads((folder / "job.json").read_text())
        events = json.loads((folder / "trace.events.json").read_text())
        summary = json.loads((folder / "summary.json").read_text())
        assert events["run"]["controller"] == summary["controller"] == record["method"]
        weather[record["case"], record["method"]] = events["run"]["parameters"]["weather"]
    assert weather == {**{(c, "udwa"): True for c in CASES},
                       **{(c, "udwa-calm"): False for c in CASES}}  # fmt: skip
    again = inline_batch(path, out)
    assert again.counts() == (0, 4, 0)  # nothing runs again
