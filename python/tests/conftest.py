"""Where the tests find the command line and the shipped assets (set by ctest; the defaults suit a
checkout built into build/)."""

import os
import pathlib
import threading

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("HAPTICUT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("HAPTICUT_CLI", str(SOURCE_DIR / "build" / "apps" / "hapticut" / "hapticut"))


@pytest.fixture(scope="session")
def assets():
    return SOURCE_DIR / "assets"


@pytest.fixture(scope="session")
def cli():
    return CLI


def ticks_while(work):
    """How many turns of an empty loop this thread gets while another thread does `work`: millions when
    the work releases the interpreter's lock, a switch interval's worth (some 60,000) when it holds it."""
    started, done = threading.Event(), threading.Event()

    def run():
        started.set()
        work()
        done.set()

    thread = threading.Thread(target=run)
    thread.start()
    started.wait()
    ticks = 0
    while not done.is_set():
        ticks += 1
    thread.join()
    return ticks
