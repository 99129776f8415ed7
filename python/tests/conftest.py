"""Where the tests find the command line and the shipped assets (set by ctest; the defaults suit a
checkout built into build/)."""

import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("HAPTICUT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("HAPTICUT_CLI", str(SOURCE_DIR / "build" / "apps" / "hapticut" / "hapticut"))


@pytest.fixture
def assets():
    return SOURCE_DIR / "assets"


@pytest.fixture
def cli():
    return CLI
