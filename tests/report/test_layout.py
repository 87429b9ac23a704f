"""The report stage's layout (usvtool/report/__init__.py): the comparison report's sections in
``usvtool.report.sections``, the regression report in ``usvtool.report.regression``, neither
importing the other, and the shared pieces at the top importing neither."""

from __future__ import annotations

import ast
from pathlib import Path

from usvtool.report import sections
from usvtool.report.regression.compare import compare

REPORT = Path(__file__).resolve().parents[2] / "usvtool" / "report"
#: The pieces at the top of the stage that the regression report may use.
SHARED_BY_BOTH = {"values", "output", "templating"}


def report_imports(path: Path) -> set[str]:
    """The ``usvtool.report.X`` packages and modules ``path`` imports (X only), in functions
    too."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = [f"{node.module}.{a.name}" for a in node.names]
        else:
            continue
        found |= {n.split(".")[2] for n in names if n.startswith("usvtool.report.")}
    return found


def modules(*parts: str) -> list[Path]:
    found = sorted(REPORT.joinpath(*parts).glob("*.py"))
    assert found, parts
    return found


def test_every_section_builder_is_a_module_of_the_sections_package():
    names = [b.__module__.rsplit(".", 1)[1] for b in sections.builders()]
    assert names[0] == "summary" and names[-1] == "methods"  # page 1; the methods last
    assert len(set(names)) == len(names)
    for builder in sections.builders():
        assert builder.__module__.startswith("usvtool.report.sections."), builder.__module__
    assert not [p.name for p in modules() if "def section(" in p.read_text(encoding="utf-8")]
    # every module of the package with a section builder is registered (and only those)
    built = {p.stem for p in modules("sections") if "def section(" in p.read_text(encoding="utf-8")}
    assert built == set(names)


def test_the_parallel_build_builds_every_section_once():
    """build.sections on several processes builds :data:`sections.TASKS`: each section in
    exactly one task, so none is left out nor built twice."""
    tasked = [m for task in sections.TASKS for m in task]
    assert sorted(m.__name__ for m in tasked) == sorted(m.__name__ for m in sections.SECTIONS)
    assert len(set(tasked)) == len(tasked)


def test_the_regression_report_is_a_package_using_only_the_shared_pieces():
    assert compare.__module__ == "usvtool.report.regression.compare"
    for path in modules("regression"):
        assert report_imports(path) <= SHARED_BY_BOTH | {"regression"}, path.name


def test_the_sections_do_not_import_the_regression_report():
    for path in modules("sections"):
        assert "regression" not in report_imports(path), path.name


def test_the_shared_pieces_import_neither_report():
    for path in [*modules(), *modules("figures"), *modules("papers")]:
        if path.name not in ("build.py", "__init__.py"):
            assert not report_imports(path) & {"sections", "regression", "build"}, path


def test_the_stage_gives_its_entry_points_only():
    # the two reports and the animation of a run (issue 35), each imported when first asked
    assert report_imports(REPORT / "__init__.py") == {"animation", "build", "regression"}
