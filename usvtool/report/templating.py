"""The reports' jinja2 templates: ``templates/`` at the project root, CSS inlined.

Every page is self-contained: :func:`render` passes ``templates/style.css`` as ``style`` (safe
markup, for a ``<style>`` element), so a template refers to no file. Autoescaping is on and an
undefined name is an error (``StrictUndefined``), so a misspelt variable fails the render.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import jinja2
from markupsafe import Markup

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"
STYLE = "style.css"


@lru_cache(maxsize=1)
def environment() -> jinja2.Environment:
    """The templates' environment (one per process)."""
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(TEMPLATES),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
    )


def render(name: str, **context) -> str:
    """The template ``name`` rendered with ``context`` and the stylesheet as ``style``."""
    style = Markup((TEMPLATES / STYLE).read_text(encoding="utf-8"))
    return environment().get_template(name).render(style=style, **context)
