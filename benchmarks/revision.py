"""Modules of an earlier git revision, loaded beside the current package: the benchmarks' "plain
way" when the plain way is the project's own previous implementation."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def source_at(base: str, path: str) -> str:
    """The text of ``path`` (relative to the repository) at git revision ``base``."""
    return subprocess.run(
        ["git", "show", f"{base}:{path}"], cwd=ROOT, check=True, capture_output=True, text=True
    ).stdout


def load_module(name: str, source: str, tmp: Path):
    """Import ``source`` as the module ``name`` (written into ``tmp``, registered in
    ``sys.modules`` so that other old modules can import it by that name)."""
    path = tmp / f"{name}.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module
