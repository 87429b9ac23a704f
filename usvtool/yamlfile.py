"""Reading the YAML files the tool takes (pipelines, scenarios, tolerances), bounded.

PyYAML's safe loader alone lets one small file exhaust the machine or the interpreter: 20 000
nested brackets overflow the recursion of its composer, and an alias bomb (9 levels of 9
aliases, a few hundred bytes) expands into 387 million values for whoever walks the result.
:func:`read_yaml` refuses, with one line naming the file, the line and the limit:

- a file larger than :data:`MAX_BYTES`;
- nesting deeper than :data:`MAX_DEPTH` collections (counted while the document is composed,
  before the recursion could overflow);
- more than :data:`MAX_VALUES` values once aliases are expanded (counted on the composed
  node graph, each node once, so the count itself is linear in the file);
- a key given twice in one mapping (PyYAML keeps the last one silently).

Numbers follow YAML 1.2 as well as 1.1: ``1e3`` and ``1.0e3`` are floats (PyYAML's YAML 1.1
resolver reads them as strings and needs ``1.0e+3``).

>>> import tempfile
>>> from pathlib import Path
>>> p = Path(tempfile.mkdtemp()) / "a.yaml"
>>> _ = p.write_text("dt: 1e-1\\nduration: 1.0e3\\n")
>>> read_yaml(p)
{'dt': 0.1, 'duration': 1000.0}
>>> _ = p.write_text("a: 1\\nb: 2\\na: 3\\n")
>>> read_yaml(p)  # doctest: +ELLIPSIS
Traceback (most recent call last):
usvtool.errors.UsvError: ...a.yaml: line 3: 'a' named twice
"""

from __future__ import annotations

import os
import re
import unicodedata

import yaml

from usvtool.errors import UsvError, check_input_file

#: The largest file read (bytes): a scenario's long data (a replayed track) lives in files of
#: its own, and the bundled files are under 20 KB.
MAX_BYTES = 16 * 2**20
#: The deepest nesting of mappings and lists (the bundled files nest at most 5 deep).
MAX_DEPTH = 64
#: The most values (scalars, mappings, lists) a document may hold with its aliases expanded.
MAX_VALUES = 200_000
#: The longest excerpt of a value an error line shows.
SHOWN = 60

# YAML 1.2's floats with an exponent and no sign in it (1e3, 1.0e3, 2E-2 is already 1.1's)
_FLOAT_12 = re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9][0-9_]*)[eE][-+]?[0-9]+$")


def show(value) -> str:
    """``repr(value)`` cut to :data:`SHOWN` characters, for error lines."""
    text = repr(value)
    return text if len(text) <= SHOWN else text[: SHOWN - 3] + "..."


class _Refused(yaml.YAMLError):
    def __init__(self, problem: str, mark):
        super().__init__(problem)
        self.problem, self.problem_mark = problem, mark


class _Loader(yaml.SafeLoader):
    """The safe loader with the limits of this module."""

    def __init__(self, stream):
        super().__init__(stream)
        self._depth = 0

    def compose_node(self, parent, index):
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH and not self.check_event(yaml.ScalarEvent, yaml.AliasEvent):
                raise _Refused(f"nested deeper than {MAX_DEPTH} levels",
                               self.peek_event().start_mark)  # fmt: skip
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_mapping(self, node, deep=False):
        if isinstance(node, yaml.MappingNode):
            seen: set = set()
            for key_node, _ in node.value:
                key = self.construct_object(key_node, deep=True)
                if not isinstance(key, list | dict) and key in seen:
                    raise _Refused(f"{show(key)} named twice", key_node.start_mark)
                if not isinstance(key, list | dict):
                    seen.add(key)
        return super().construct_mapping(node, deep)


_Loader.add_implicit_resolver("tag:yaml.org,2002:float", _FLOAT_12, list("-+0123456789."))


def _expanded_size(root: yaml.Node) -> int:
    """The number of values under ``root`` with aliases expanded (each node counted once,
    memoised: linear in the number of distinct nodes)."""
    sizes: dict[int, int] = {}

    def size(node: yaml.Node) -> int:
        known = sizes.get(id(node))
        if known is not None:
            return known
        if isinstance(node, yaml.MappingNode):
            n = 1 + sum(size(k) + size(v) for k, v in node.value)
        elif isinstance(node, yaml.SequenceNode):
            n = 1 + sum(size(v) for v in node.value)
        else:
            n = 1
        sizes[id(node)] = n = min(n, MAX_VALUES + 1)
        return n

    return size(root)


def read_yaml(path: str | os.PathLike):
    """The one YAML document in ``path`` (None for an empty document), within this module's
    limits; any problem is a :class:`UsvError` of one line naming the file (and the line)."""
    check_input_file(path)
    size = os.path.getsize(path)
    if size > MAX_BYTES:
        raise UsvError(f"{path}: {size} bytes, larger than the {MAX_BYTES // 2**20} MiB a YAML "
                       "file may hold")  # fmt: skip
    try:
        with open(path, encoding="utf-8") as f:
            loader = _Loader(f)
            try:
                node = loader.get_single_node()
                if node is None:
                    return None
                if _expanded_size(node) > MAX_VALUES:
                    raise _Refused(f"more than {MAX_VALUES} values with its aliases expanded",
                                   node.start_mark)  # fmt: skip
                return loader.construct_document(node)
            finally:
                loader.dispose()
    except UnicodeDecodeError:
        raise UsvError(f"{path}: not a UTF-8 text file") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = f"line {mark.line + 1}: " if mark is not None else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        if isinstance(exc, _Refused):
            raise UsvError(f"{path}: {line}{problem}"[:200]) from None
        raise UsvError(f"{path}: not valid YAML ({line}{problem})"[:200]) from None


def comment(text: str) -> str:
    """``text`` as one YAML comment line (``# ...``, no line break): each control character and
    line or paragraph separator (YAML ends a comment at any line break) as its Python escape, so
    that text from an input (a path, a vessel's name, an option's value) cannot end the comment
    and become a key.

    >>> comment("a.csv\\nweather: {}\\u2028x")
    '# a.csv\\\\nweather: {}\\\\u2028x'
    """
    return "# " + "".join(repr(c)[1:-1] if unicodedata.category(c) in ("Cc", "Zl", "Zp") else c
                          for c in text)  # fmt: skip

