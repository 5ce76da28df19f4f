"""Shared fixtures of the Python tests: the shared data folder and the CLI.

Run from a build tree (scripts/test.sh does):
    PYTHONPATH=build/rel/python VOROCLIP_CLI=build/rel/bin/voroclip /usr/bin/python3 -m pytest python/tests
or after `pip install .`. Tests needing the shared data or the CLI skip when absent."""

import os
import pathlib
import shutil

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def _data_dir():
    env = os.environ.get("VOROCLIP_SHARED_DATA")
    for p in ([pathlib.Path(env)] if env else []) + [REPO.parent / "shared" / "data",
                                                     pathlib.Path("/work/shared/data")]:
        if (p / "surfaces").is_dir():
            return p
    return None


DATA = _data_dir()


@pytest.fixture
def data():
    if DATA is None:
        pytest.skip("the shared data folder (../shared/data) is not there")
    return DATA


@pytest.fixture
def cli():
    env = os.environ.get("VOROCLIP_CLI")
    candidates = [env] if env else []
    candidates += [str(p) for p in sorted(REPO.glob("build/*/bin/voroclip"))]
    candidates.append(shutil.which("voroclip"))
    for c in candidates:
        if c and os.access(c, os.X_OK):
            return c
    pytest.skip("the voroclip command-line tool is not built (set VOROCLIP_CLI)")


@pytest.fixture
def sigint_interrupts():
    """SIGINT raises KeyboardInterrupt for the test's duration, as in an interactive Python.
    A process started in the background by a non-interactive shell (a CI runner, `cmd &`)
    inherits SIGINT ignored, and Python then installs no handler for it: a Ctrl-C test must
    not depend on how the suite was launched."""
    import signal

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)
