"""Each stage package names its entry points in ``__all__`` (docs/api.md): every name is
defined, is a function or a class of the stage (or a constant), and shadows none of the
package's modules (were ``usvtool.chart.preprocess`` both a function and a module, ``import
usvtool.chart.preprocess as m`` would give the function)."""

from __future__ import annotations

import importlib
import inspect
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "usvtool"
STAGES = sorted(
    p.name for p in PACKAGE.iterdir() if (p / "__init__.py").is_file() and p.name != "cli"
)


@pytest.mark.parametrize("stage", STAGES)
def test_a_stage_names_its_entry_points(stage):
    if stage == "gym":  # the gym extra's (docs/gym.md)
        pytest.importorskip("gymnasium")
    package = importlib.import_module(f"usvtool.{stage}")
    names = package.__all__
    assert names and len(set(names)) == len(names)
    modules = {p.stem for p in (PACKAGE / stage).glob("*.py")}
    modules |= {p.parent.name for p in (PACKAGE / stage).glob("*/__init__.py")}
    for name in names:
        entry = getattr(package, name)
        assert name not in modules, f"usvtool.{stage}.{name} is an entry point and a module"
        if name.isupper():  # a constant (usvtool.metrics' columns)
            continue
        assert inspect.isfunction(entry) or inspect.isclass(entry), name
        assert entry.__module__.startswith(f"usvtool.{stage}."), name


def test_each_stage_gives_a_function_and_its_options_and_result():
    for stage, function, options, result in [
        ("chart", "preprocess", "PreprocessOptions", "PreprocessResult"),
        ("chart", "render", "RenderOptions", "RenderResult"),
        ("plan", "plan_route", "PlanOptions", "PlanResult"),
        ("sim", "simulate", "SimOptions", "SimResult"),
        ("metrics", "measure", "MetricsOptions", "MetricsResult"),
        ("batch", "run_batch", "BatchOptions", "BatchResult"),
        ("report", "make_report", "ReportOptions", "ReportResult"),
        ("report", "compare", "CompareOptions", "CompareResult"),
        ("report", "animate", "AnimateOptions", "AnimateResult"),
        ("ais", "read_ais", "ReadOptions", "ReadResult"),
        ("ais", "find_encounters", "EncounterOptions", "EncounterResult"),
        ("ais", "make_scenario", "ScenarioOptions", "ScenarioResult"),
    ]:
        names = importlib.import_module(f"usvtool.{stage}").__all__
        assert {function, options, result} <= set(names), stage


def test_docs_api_lists_every_stage_and_every_contract_module():
    """docs/api.md's tables name each stage package and each contract module (``usvtool/*.py``),
    and nothing else: a new one is documented there."""
    import re

    text = (PACKAGE.parent / "docs" / "api.md").read_text(encoding="utf-8")
    rows = set(re.findall(r"^\| `usvtool\.(\w+)` \|", text, re.M))
    contracts = {p.stem for p in PACKAGE.glob("*.py") if p.stem != "__init__"}
    assert {"tracks", "csvtable", "traffic"} <= contracts
    assert rows == set(STAGES) | contracts
