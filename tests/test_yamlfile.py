"""The bounded YAML reader: the limits hold (deep nesting, alias bombs, size, duplicate keys), are
named in one short line, and every file the tool reads goes through it."""

from __future__ import annotations

import time

import pytest

from usvtool import yamlfile
from usvtool.errors import UsvError
from usvtool.pipeline import load
from usvtool.sim.scenario import read_scenario
from usvtool.yamlfile import read_yaml


def alias_bomb(levels: int, width: int = 9, key: str = "a") -> str:
    """``levels`` anchors, each a list of ``width`` aliases of the one before: width^levels
    values once expanded, in a few hundred bytes."""
    lines = [f"l0: &l0 [{', '.join(['x'] * width)}]"]
    for i in range(1, levels):
        lines.append(f"l{i}: &l{i} [{', '.join([f'*l{i - 1}'] * width)}]")
    return "\n".join(lines) + f"\n{key}: *l{levels - 1}\n"


def refused(path, *words) -> str:
    started = time.perf_counter()
    with pytest.raises(UsvError) as info:
        read_yaml(path)
    message = str(info.value)
    assert time.perf_counter() - started < 5
    assert message.startswith(f"{path}: ") and "\n" not in message and len(message) <= 200
    for w in words:
        assert w in message
    return message


def test_deep_nesting_is_refused_with_its_limit_and_line(tmp_path):
    path = tmp_path / "deep.yaml"
    path.write_text("name: x\nsides: " + "[" * 20_000 + "]" * 20_000 + "\n")
    refused(path, "line 2", f"nested deeper than {yamlfile.MAX_DEPTH} levels")
    # the limit itself is allowed: MAX_DEPTH collections nested
    path.write_text("a: " + "[" * (yamlfile.MAX_DEPTH - 1) + "1" + "]" * (yamlfile.MAX_DEPTH - 1))
    value = read_yaml(path)["a"]
    for _ in range(yamlfile.MAX_DEPTH - 2):
        (value,) = value
    assert value == [1]


@pytest.mark.parametrize("levels", [6, 9])
def test_alias_bombs_are_refused_quickly(tmp_path, levels):
    path = tmp_path / "bomb.yaml"
    path.write_text(alias_bomb(levels))
    refused(path, f"more than {yamlfile.MAX_VALUES} values with its aliases expanded")


def test_aliases_within_the_limit_expand(tmp_path):
    path = tmp_path / "ok.yaml"
    path.write_text(alias_bomb(3, width=4))  # 4 + 16 + 64 leaves
    data = read_yaml(path)
    assert data["a"] == [[["x"] * 4] * 4] * 4


def test_a_key_given_twice_is_refused_at_its_line(tmp_path):
    path = tmp_path / "twice.yaml"
    path.write_text("name: a\nown: {start: [0, 0], goal: [0, 1]}\nname: b\n")
    assert refused(path) == f"{path}: line 3: 'name' named twice"
    path.write_text("a: {b: 1, c: 2, b: 3}\n")  # nested too
    assert refused(path) == f"{path}: line 1: 'b' named twice"


def test_a_large_file_is_refused_before_it_is_read(tmp_path, monkeypatch):
    path = tmp_path / "big.yaml"
    path.write_text("a: " + "1" * 100 + "\n")
    monkeypatch.setattr(yamlfile, "MAX_BYTES", 50)
    refused(path, "104 bytes")


@pytest.mark.parametrize("text, value", [
    ("1e3", 1000.0), ("1.0e3", 1000.0), ("-2.5E-1", -0.25), (".5e1", 5.0), ("1.0e+3", 1000.0),
    ("1_000", 1000), ("e3", "e3"), ("'1e3'", "1e3"), ("1e", "1e"), ("0x10", 16),
])  # fmt: skip
def test_numbers_with_an_exponent_are_numbers(tmp_path, text, value):
    path = tmp_path / "n.yaml"
    path.write_text(f"v: {text}\n")
    got = read_yaml(path)["v"]
    assert got == value and type(got) is type(value)


def test_an_empty_document_and_bad_yaml(tmp_path):
    path = tmp_path / "e.yaml"
    path.write_text("# nothing\n")
    assert read_yaml(path) is None
    path.write_text("a: [1, 2\n")
    refused(path, "not valid YAML (line 2")
    path.write_bytes(b"a: \xff\xfe\n")
    refused(path, "not a UTF-8 text file")


def test_scenarios_and_pipelines_read_through_it(tmp_path):
    scenario = tmp_path / "s.yaml"
    scenario.write_text("name: s\nown: {start: [0, 0], goal: [0, 100], speed: 2}\n"
                        "sim: {duration: 1.0e3, dt: 2e-1}\n")  # fmt: skip
    s = read_scenario(scenario)
    assert (s.sim.duration, s.sim.dt) == (1000.0, 0.2)
    scenario.write_text(alias_bomb(9, key="controller"))
    with pytest.raises(UsvError, match="aliases expanded"):
        read_scenario(scenario)
    pipeline = tmp_path / "p.yaml"
    pipeline.write_text("routes: " + "{a: " * 100 + "1" + "}" * 100 + "\n")
    with pytest.raises(UsvError, match="nested deeper"):
        load(pipeline)


def test_a_time_step_above_the_duration_is_refused(tmp_path):
    scenario = tmp_path / "s.yaml"
    scenario.write_text("name: s\nown: {start: [0, 0], goal: [0, 100], speed: 2}\n"
                        "sim: {dt: 1000, duration: 20}\n")  # fmt: skip
    with pytest.raises(UsvError, match=r"sim.dt must be at most sim.duration \(20 s\), not 1000"):
        read_scenario(scenario)
    scenario.write_text(scenario.read_text().replace("1000", "20"))  # one step: allowed
    assert read_scenario(scenario).sim.dt == 20
