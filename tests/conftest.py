"""Shared fixtures: paths to the bundled charts, a CLI runner."""

from pathlib import Path

import pytest
from click.testing import CliRunner

ROOT = Path(__file__).resolve().parent.parent
CHARTS = ROOT / "charts"
KAP = CHARTS / "noaa" / "11361_4.KAP"
ENC = CHARTS / "noaa" / "US5MA12M.000"


@pytest.fixture(scope="session")
def kap() -> Path:
    """The NOAA raster chart 11361_4 (Head of Passes)."""
    return KAP


@pytest.fixture(scope="session")
def enc() -> Path:
    """The NOAA ENC cell US5MA12M (Boston Harbor)."""
    return ENC


@pytest.fixture(scope="session")
def charts() -> Path:
    return CHARTS


@pytest.fixture
def runner() -> CliRunner:
    return CliRunner()


@pytest.fixture
def usv(runner):
    """``usv(*args)`` invokes ``usvtool ARGS``; the result keeps stdout and stderr apart."""
    from usvtool.cli import cli

    def invoke(*args):
        return runner.invoke(cli, [str(a) for a in args], catch_exceptions=False)

    return invoke
