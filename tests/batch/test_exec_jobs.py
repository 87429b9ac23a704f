"""A controller that is a program in a pipeline (``{name: NAME, exec: [PROGRAM, ARGS...]}``,
docs/pipelines.md): read with its files relative to the root, its jobs' command lines, keys
that hold the program's bytes (a rebuilt client runs again, the other jobs do not), and a real
``usvtool batch -j 2`` on Imazu cases with the Python reference client, its stderr in each
job's folder."""

from __future__ import annotations

import csv
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from usvtool.batch.commands import CONTROLLER_LOG
from usvtool.batch.jobs import expand
from usvtool.cli.batch import stage_names
from usvtool.errors import UsvError
from usvtool.pipeline import Program, load

ROOT = Path(__file__).resolve().parents[2]
NAMES = stage_names()


def pipeline(root: Path, controllers: str, kinds: str = "['01', '05']") -> Path:
    """A pipeline in ``root`` (its root) with the client copied there: two Imazu cases (cut to
    20 s) and one bundled scenario, with ``controllers``."""
    root.mkdir(exist_ok=True)
    shutil.copy(ROOT / "examples" / "exec" / "client.py", root / "client.py")
    (root / "scenarios").mkdir(exist_ok=True)
    shutil.copy(ROOT / "charts" / "scenarios" / "env1-head-on.yaml", root / "scenarios")
    path = root / "p.yaml"
    path.write_text(f"""root: .
simulation:
  scenarios: [scenarios/env1-head-on.yaml]
  controllers: {controllers}
  seeds: [1]
families:
  - family: imazu
    kinds: {kinds}
    controllers: {controllers}
    seeds: [1]
    options: {{duration: 20}}
""")
    return path


PY_CLIENT = f"{{name: py-client, exec: [{sys.executable}, client.py], params: {{deadline: 5}}}}"


def test_a_program_is_read_with_its_files_from_the_root(tmp_path):
    p = load(pipeline(tmp_path, f"[dwa, {PY_CLIENT}]"), NAMES)
    program = Program("py-client", (Path(sys.executable), tmp_path / "client.py"),
                      (("deadline", 5),))  # fmt: skip
    assert p.simulation.controllers == ("dwa", "py-client")
    assert p.simulation.programs == (program,) and p.families[0].programs == (program,)
    assert p.program("py-client") == program and p.program("dwa") is None
    jobs = {(j.case, j.method): j for j in expand(p, NAMES)}
    assert len(jobs) == 6
    run = jobs["env1-head-on", "py-client"]
    assert run.args[2:8] == ("--controller", f"exec:{sys.executable} {tmp_path / 'client.py'}",
                             "--param", "label=py-client", "--param", "deadline=5")  # fmt: skip
    assert run.args[8:10] == ("--controller-log", CONTROLLER_LOG)
    assert run.info["program"] == {"command": [sys.executable, str(tmp_path / "client.py")],
                                   "params": {"deadline": 5}}  # fmt: skip
    family = jobs["imazu/05/s000", "py-client"]
    assert f"exec:{sys.executable} {tmp_path / 'client.py'}" in family.args
    assert "--controller-log" in family.args
    plain = jobs["env1-head-on", "dwa"]
    assert "--controller-log" not in plain.args and "program" not in plain.info


def test_the_program_s_bytes_key_its_jobs(tmp_path):
    path = pipeline(tmp_path, f"[dwa, {PY_CLIENT}]")

    def keys():
        return {j.label: j.key for j in expand(load(path, NAMES), NAMES)}

    before = keys()
    alone = pipeline(tmp_path / "alone", "[dwa]")  # the same runs without the program
    assert {k: v for k, v in before.items() if "dwa" in k} == {
        j.label: j.key for j in expand(load(alone, NAMES), NAMES)}  # fmt: skip
    client = tmp_path / "client.py"
    client.write_text(client.read_text() + "\n# rebuilt\n")
    after = keys()
    changed = {label for label in before if before[label] != after[label]}
    assert changed == {label for label in before if "py-client" in label} and len(changed) == 3
    path.write_text(path.read_text().replace("deadline: 5", "deadline: 4"))
    assert keys().keys() == after.keys() and keys() != after


@pytest.mark.parametrize(("entry", "words"), [
    ("{name: c, exec: [missing/client]}", "controllers[1].exec[0]: missing/client: no such file"),
    ("{name: c, exec: [no-such-program-here]}",
     "controllers[1].exec[0]: no-such-program-here: not found on PATH"),
    ("{name: udwa, exec: [client.py]}", "controllers[1].name: 'udwa' is a controller's name"),
    ("{name: c, exec: []}", "controllers[1].exec: expected the program and its arguments"),
    ("{name: c, exec: python3 client.py}", "controllers[1].exec: expected the program"),
    ("{name: c, exec: [python3], params: {command: [x]}}",
     "controllers[1].params.command: given by the entry's exec"),
    ("{name: c, exec: [python3], speed: 2}", "controllers[1].speed: unknown field"),
    ("exec", "controllers[1]: exec runs a program: give it as {name: NAME, exec: [PROGRAM"),
])  # fmt: skip
def test_a_bad_program_entry_is_refused_naming_its_field(tmp_path, entry, words):
    path = pipeline(tmp_path, f"[dwa, {entry}]")
    with pytest.raises(UsvError) as e:
        load(path, NAMES)
    assert str(e.value).startswith(f"{path}: simulation.{words}"), str(e.value)


def test_two_entries_of_one_name_are_refused(tmp_path):
    path = pipeline(tmp_path, f"[{PY_CLIENT}, {PY_CLIENT}]")
    with pytest.raises(UsvError, match="simulation.controllers: named twice: py-client"):
        load(path, NAMES)


@pytest.mark.slow  # a real batch: two worker processes, each running the client
def test_a_batch_runs_the_python_client_on_imazu_cases_with_two_workers(tmp_path):
    path = pipeline(tmp_path / "p", f"[{PY_CLIENT}]", "['01', '05', '13']")
    out = tmp_path / "out"
    command = [sys.executable, "-m", "usvtool.cli", "batch", str(path), "-j", "2", "-o", str(out)]
    r = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert (summary["jobs"], summary["done"], summary["failed"]) == (4, 4, 0)
    for folder in (out / "runs").iterdir():
        record = json.loads((folder / "job.json").read_text())
        assert record["method"] == "py-client" and CONTROLLER_LOG in record["files"]
        log = (folder / CONTROLLER_LOG).read_text().splitlines()
        assert log[0].startswith("client.py: protocol 1, seed 1, course replies")
        assert log[-1].startswith("client.py: end of input after")
        assert json.loads((folder / "summary.json").read_text())["controller"] == "py-client"
    with (out / "metrics.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert {r["method"] for r in rows} == {"py-client"}
    assert {r["case"] for r in rows} == {"env1-head-on", "imazu/01/s000", "imazu/05/s000",
                                         "imazu/13/s000"}  # fmt: skip
    assert not [r for r in rows if r["metric"] in ("collision", "controller_failed")]
    again = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path)
    assert json.loads(again.stdout)["skipped"] == 4  # the same program: nothing runs again


def test_one_name_is_one_program_through_the_pipeline(tmp_path):
    path = pipeline(tmp_path, f"[{PY_CLIENT}]")
    path.write_text(path.read_text().replace("controllers: [", "controllers: [", 1).replace(
        "    controllers: [{name: py-client, exec: [",
        "    controllers: [{name: py-client, exec: [python3, ", 1))  # fmt: skip
    with pytest.raises(UsvError, match=r"families\[0\].controllers: 'py-client' names another "
                                       "program elsewhere in the pipeline"):  # fmt: skip
        load(path, NAMES)
