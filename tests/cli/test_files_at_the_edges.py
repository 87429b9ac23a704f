"""Every command's files at their edges (usvtool/cli/guard.py, usvtool.atomic.in_place): an
output that is one of the inputs is refused in one line, an output that is a device, a FIFO or
a link to one is written in place (never replaced by a regular file), and an OSError that names
no file is one line naming the command's files."""

from __future__ import annotations

import errno
import os
import stat
import subprocess
import sys
import threading
from pathlib import Path

import click
import pytest
from click.testing import CliRunner

from usvtool.cli import SUBCOMMANDS, cli
from usvtool.cli.guard import guarded
from usvtool.cli.options import OutputDir, OutputPath
from usvtool.errors import UsvError

ROOT = Path(__file__).resolve().parents[2]
TRACKS = ROOT / "charts" / "ais" / "nyharbor-tracks.parquet"
SCENARIO = ROOT / "charts" / "scenarios" / "emergency-head-on.yaml"
#: The options through which a command writes a file or a folder.
WRITES = {"--output", "--summary", "--events", "--tracks", "--table", "--preview",
          "--scenario-out", "--make-fragment"}  # fmt: skip
READS = {("metrics", "--events"), ("animate", "--events")}  # the events JSON of the runs read


def usvtool(*args, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "usvtool.cli", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True)  # fmt: skip


def _commands():
    for name in SUBCOMMANDS:
        command = cli.get_command(None, name)
        if isinstance(command, click.Group):
            yield from ((f"{name} {n}", c) for n, c in command.commands.items())
        else:
            yield name, command


@pytest.mark.parametrize("name, command", list(_commands()), ids=[n for n, _ in _commands()])
def test_every_option_that_writes_is_typed_as_an_output(name, command):
    """The guard knows outputs from inputs by their types: an option that writes must say so
    (metrics -o, simulate --events and --tracks, functions --table, batch --summary were plain
    paths, so an output there could replace an input unnoticed)."""
    for param in command.params:
        if isinstance(param, click.Option) and WRITES & set(param.opts) - {
                o for n, o in READS if n == name}:
            assert isinstance(param.type, OutputPath | OutputDir), (name, param.opts)


def test_ais_read_and_encounters_refuse_their_input_as_output(tmp_path):
    tracks = tmp_path / "t.csv"
    tracks.write_text("mmsi,time,lat,lon\n")
    link = tmp_path / "link.csv"
    link.symlink_to(tracks)
    cases = [("ais", "read", tracks, "-o", tracks), ("ais", "encounters", tracks, "-o", tracks),
             ("ais", "read", link, "-o", tracks), ("ais", "encounters", tracks, "-o", link),
             ("metrics", tracks, "-o", tracks)]  # fmt: skip
    for args in cases:
        r = usvtool(*args)
        assert r.returncode == 1 and r.stderr.count("\n") == 1, (args, r.stderr)
        assert "the same file as the input" in r.stderr and str(args[-1]) in r.stderr
        assert tracks.read_text() == "mmsi,time,lat,lon\n" and link.is_symlink()


def test_an_output_that_is_a_device_or_a_link_to_one_is_written_in_place(tmp_path):
    """As root, renaming onto ``-o /dev/null`` would remove the system's /dev/null: links to
    it stand for it here, so that the old code replaces only a link of the test's."""
    links = {name: tmp_path / name for name in ("trace.csv", "events.json", "tracks.geojson")}
    for link in links.values():
        link.symlink_to(os.devnull)
    r = usvtool("simulate", SCENARIO, "-o", links["trace.csv"], "--events", links["events.json"],
                "--tracks", links["tracks.geojson"], "--summary", "/dev/stdout")  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert r.stdout.count('"scenario_file"') == 2  # --summary /dev/stdout, then stdout itself
    assert all(link.is_symlink() for link in links.values())
    assert stat.S_ISCHR(os.stat(os.devnull).st_mode)


def test_an_output_that_is_a_fifo_gets_the_bytes_a_file_would(tmp_path):
    expected = tmp_path / "encounters.csv"
    assert usvtool("ais", "encounters", TRACKS, "-o", expected).returncode == 0
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
    reader.start()
    r = usvtool("ais", "encounters", TRACKS, "-o", fifo)
    reader.join(timeout=60)
    assert r.returncode == 0, r.stderr
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode) and got == [expected.read_bytes()]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["encounters.csv", "fifo.csv"]


def test_an_os_error_naming_no_file_is_one_line_naming_the_commands_files():
    @click.command()
    @click.argument("source", type=click.Path())
    @click.option("-o", type=OutputPath())
    def read(source, o):
        raise OSError(errno.EIO, "Input/output error")  # as a damaged archive's reader does

    result = CliRunner().invoke(guarded(read), ["in.gz", "-o", "out.csv"])
    assert isinstance(result.exception, UsvError)
    assert str(result.exception) == "in.gz: Input/output error"
