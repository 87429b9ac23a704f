"""The layering rule: a stage never imports another stage; the contracts below them import none.

Stages are the subpackages (``usvtool/chart``, ``usvtool/plan``, ``usvtool/sim``, ...); the
contracts are the top-level modules (``usvtool/grid.py``, ``route.py``, ``trace.py``, ...). The
command line (``usvtool/cli``) may import anything. Imports inside functions count too.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "usvtool"
#: The layers on top of the stages, which may import any of them: the command line, and the
#: Gymnasium environment (the gym extra), which no module of usvtool imports.
TOP = ("cli", "gym")
STAGES = sorted(
    p.name for p in PACKAGE.iterdir() if (p / "__init__.py").is_file() and p.name not in TOP
)


def usvtool_imports(path: Path) -> set[str]:
    """The ``usvtool.X`` subpackages and modules ``path`` imports (X only)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        else:
            continue
        found |= {n.split(".")[1] for n in names if n.startswith("usvtool.")}
    return found


def test_the_stages_are_found():
    assert set(STAGES) == {"ais", "batch", "chart", "metrics", "plan", "report", "sim"}


@pytest.mark.parametrize("stage", STAGES)
def test_a_stage_imports_no_other_stage_nor_the_cli(stage):
    bad = {
        f"{p.relative_to(PACKAGE.parent)} imports usvtool.{name}"
        for p in (PACKAGE / stage).rglob("*.py")
        for name in usvtool_imports(p)
        if name != stage and (name in STAGES or name in TOP)
    }
    assert not bad


def test_nothing_imports_the_gymnasium_environment():
    """usvtool.gym needs gymnasium (an optional extra): no other module imports it, so that
    usvtool works without gymnasium (tests/gym/test_policy.py runs a policy without it)."""
    bad = {
        str(p.relative_to(PACKAGE.parent))
        for p in PACKAGE.rglob("*.py")
        if p.relative_to(PACKAGE).parts[0] != "gym" and "gym" in usvtool_imports(p)
    }
    assert not bad
    used = {name for p in (PACKAGE / "gym").rglob("*.py") for name in usvtool_imports(p)}
    assert used & {*STAGES, "cli"} == {"sim"}  # the scenes and the run, nothing else


def test_the_contracts_import_no_stage():
    bad = {
        f"{p.name} imports usvtool.{name}"
        for p in PACKAGE.glob("*.py")
        for name in usvtool_imports(p)
        if name in STAGES or name in TOP
    }
    assert not bad
