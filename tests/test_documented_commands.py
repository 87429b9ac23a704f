"""Every command line of the shell code blocks of README.md and docs/*.md runs as written.

A ```sh (``bash``, ``shell``, ``console``) block is a session, as a reader types it: its command
lines (``\\`` continuations joined; in a ``console`` block the ``$ `` lines, the rest being
output) run in order through bash, ``&&`` chains and comments as written, in a temporary
directory of its own that looks like a fresh clone (links to the repository's tracked top-level
entries: charts/, pipelines/, ...; no build/), with ``usvtool`` on PATH. Each must exit 0 and
leave every file its ``usvtool ... -o`` names. A file a command needs comes from an earlier line
of its block (a grid ``make charts`` would make is shown as its ``usvtool preprocess`` line). A
synopsis goes in a ```text block, which nothing runs; a line starting ``usvtool`` in any other
block fails. EXCLUDED lists the few commands not run here, with the reason; each is shown as a
skip. About 35 s: 22 usvtool commands, each a process of its own (its imports take 1 s of most).
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ("README.md", *sorted(f"docs/{p.name}" for p in (ROOT / "docs").glob("*.md")))
SHELLS = {"sh", "bash", "shell", "console"}
CONTROL = {"&&", "||", ";", "|", "&"}

# (doc, command prefix): why the command, and the rest of its block, does not run here
EXCLUDED = {
    ("README.md", "make "): "make report is the 5-minute full comparison, make test the suite "
    "this test belongs to",
    ("docs/cluster.md", ""): "the commands of a Dask cluster's machines (HEAD, /shared); "
    "tests/test_batch.py runs usvtool batch --scheduler on a local cluster",
    ("docs/compare.md", "usvtool batch pipelines/ci.yaml"): "about a minute, and the block is "
    "make regression's recipe, which CI (.ci/run) runs after make test",
}


@dataclass(frozen=True)
class Command:
    """One command line of a block: its first line's number in the doc and its text, with the
    continuation lines joined."""

    line: int
    text: str


@dataclass(frozen=True)
class Block:
    """A fenced code block: the doc, the line of its opening fence, its info string (the
    language, "" untagged) and its lines with their numbers."""

    doc: str
    line: int
    lang: str
    lines: tuple[tuple[int, str], ...]

    def commands(self) -> list[Command]:
        """The command lines of a shell block: blank and comment lines skipped, a ``$ ``
        prompt removed; in a console block only the prompted lines."""
        found: list[Command] = []
        pending: tuple[int, str] | None = None
        for number, raw in self.lines:
            if pending is not None:
                start, text = pending
                text += " " + raw.strip()
            else:
                line = raw.strip()
                if line.startswith("$ "):
                    line = line[2:].lstrip()
                elif self.lang == "console" or not line or line.startswith("#"):
                    continue
                start, text = number, line
            if text.endswith("\\"):
                pending = start, text[:-1].rstrip()
            else:
                pending = None
                found.append(Command(start, text))
        return found


def blocks(doc: str, text: str) -> list[Block]:
    """The fenced code blocks of a Markdown text, in order."""
    found = []
    for m in re.finditer(r"^```([^\n`]*)\n(.*?)^```", text, re.S | re.M):
        first = text.count("\n", 0, m.start(2)) + 1
        lines = tuple(enumerate(m.group(2).splitlines(), first))
        found.append(Block(doc, first - 1, m.group(1).strip().split(" ")[0], lines))
    return found


def programs(command: str) -> list[list[str]]:
    """The argument vectors of the simple commands of a command line (split at ``&&``, ``||``,
    ``;``, ``|`` and ``&``; a comment dropped)."""
    lexer = shlex.shlex(command, posix=True, punctuation_chars=True)
    lexer.whitespace_split = True
    found, argv = [], []
    for token in [*lexer, ";"]:
        if token not in CONTROL:
            argv.append(token)
        elif argv:
            found.append(argv)
            argv = []
    return found


def usvtool_outputs(command: str) -> list[str]:
    """The files the ``usvtool`` commands of a command line name with ``-o``/``--output``."""
    return [
        b
        for argv in programs(command)
        if Path(argv[0]).name == "usvtool"
        for a, b in zip(argv, argv[1:], strict=False)
        if a in ("-o", "--output")
    ]


def exclusion(doc: str, command: str) -> str | None:
    """Why a documented command does not run here, or None."""
    for (where, prefix), reason in EXCLUDED.items():
        if doc == where and command.startswith(prefix):
            return reason
    return None


BLOCKS = [b for doc in DOCS for b in blocks(doc, (ROOT / doc).read_text(encoding="utf-8"))]
SESSIONS = [b for b in BLOCKS if b.lang in SHELLS and b.commands()]


def test_the_commands_are_found():
    text = (
        "```sh\nmkdir -p out  # a comment\n\nusvtool plan a.tif --start 1 2 \\\n"
        "    --goal 3 4 -o p.geojson\n# a comment line\n$ usvtool scene --list\n```\n"
        '```console\n$ usvtool simulate s.yaml \\\n  -o t.csv\n{"output": "t.csv"}\n```\n'
        "```text\nusvtool plan GRID.tif [-o FILE]\n```\n```python\nusvtool = 1\n```\n"
    )
    sh, console, synopsis, python = blocks("x.md", text)
    assert (sh.line, sh.lang, console.lang, synopsis.lang, python.lang) == (
        1, "sh", "console", "text", "python")  # fmt: skip
    assert sh.commands() == [
        Command(2, "mkdir -p out  # a comment"),
        Command(4, "usvtool plan a.tif --start 1 2 --goal 3 4 -o p.geojson"),
        Command(7, "usvtool scene --list"),
    ]
    assert console.commands() == [Command(10, "usvtool simulate s.yaml -o t.csv")]
    line = "mkdir -p out&&usvtool simulate 'a b.yaml' -o out/t.csv --events e.json # -o no.csv"
    assert usvtool_outputs(line) == ["out/t.csv"]
    assert usvtool_outputs("cd x; .venv/bin/usvtool batch p.yaml --output o | tee -o l") == ["o"]
    assert usvtool_outputs("cp a -o b") == []
    assert programs("a 'b c'&&d|e # f") == [["a", "b c"], ["d"], ["e"]]


def test_the_documented_sessions_are_found():
    run = Counter(
        b.doc
        for b in SESSIONS
        for c in b.commands()
        if exclusion(b.doc, c.text) is None
        and any(argv[0] == "usvtool" for argv in programs(c.text))
    )
    assert run["README.md"] >= 10 and run["docs/planning.md"] >= 6  # usvtool lines run here
    assert run["docs/families.md"] >= 4 and run["docs/simulate.md"] >= 2


def test_a_usvtool_line_is_in_a_shell_block_or_a_text_block():
    """An example runs here (```sh); a synopsis with placeholders is marked ```text."""
    stray = [
        f"{b.doc}:{n}: {line}"
        for b in BLOCKS
        if b.lang not in SHELLS | {"text"}
        for n, line in b.lines
        if line.startswith("usvtool ")
    ]
    assert stray == [], "tag the block ```sh (it runs as written) or ```text (a synopsis)"


def test_every_exclusion_names_a_documented_command():
    used = {
        key
        for b in SESSIONS
        for c in b.commands()
        for key in EXCLUDED
        if key[0] == b.doc and c.text.startswith(key[1])
    }
    assert set(EXCLUDED) - used == set()


def fresh_clone(root: Path) -> None:
    """Links in ``root`` to the repository's tracked top-level entries (what a clone holds)."""
    tracked = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], check=True,
                             capture_output=True, text=True).stdout  # fmt: skip
    for name in sorted({p.split("/")[0] for p in tracked.split("\0") if p}):
        (root / name).symlink_to(ROOT / name)


@pytest.mark.slow
@pytest.mark.parametrize("block", SESSIONS, ids=[f"{b.doc}:{b.line}" for b in SESSIONS])
def test_a_documented_session_runs_as_written(block: Block, tmp_path: Path):
    bin_dir = Path(sys.executable).parent
    assert (bin_dir / "usvtool").is_file(), f"no usvtool beside {sys.executable}"
    fresh_clone(tmp_path)
    env = {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}"}
    ran = 0
    for command in block.commands():
        where = f"{block.doc}:{command.line}: {command.text}"
        reason = exclusion(block.doc, command.text)
        if reason is not None:
            if ran == 0:
                pytest.skip(f"{where}: {reason}")
            break
        shell = ["bash", "-e", "-o", "pipefail", "-c", command.text]
        p = subprocess.run(shell, cwd=tmp_path, env=env, stdin=subprocess.DEVNULL,
                           capture_output=True, text=True)  # fmt: skip
        if p.returncode != 0:
            pytest.fail(f"{where}\nexit status {p.returncode}\n{p.stderr}", pytrace=False)
        missing = [o for o in usvtool_outputs(command.text) if not (tmp_path / o).exists()]
        if missing:
            pytest.fail(f"{where}\nexit status 0, but no {', '.join(missing)}", pytrace=False)
        ran += 1
