"""Shared fixtures of the Python tests: the shared data folder, the CLI, sites outside.

Run from a build tree (scripts/test.sh does):
    PYTHONPATH=build/rel/python VOROCLIP_CLI=build/rel/bin/voroclip /usr/bin/python3 -m pytest python/tests
or after `pip install .`. Tests needing the shared data or the CLI skip when absent."""

import os
import pathlib
import re
import shutil

import numpy as np
import pytest

import voroclip

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


def _count_outside_2d(domain, points):
    """Points of `points` outside a Domain2 by the even-odd rule over all its rings, in
    floating point (random points are not on an edge): an independent count."""
    x, y = points[:, 0], points[:, 1]
    inside = np.zeros(len(points), dtype=bool)
    for k in range(domain.nb_rings):
        ring = domain.ring(k)
        for a, b in zip(ring, np.roll(ring, -1, axis=0)):
            crosses = (a[1] > y) != (b[1] > y)
            with np.errstate(divide="ignore", invalid="ignore"):
                at = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
            inside ^= crosses & (x < at)
    return int(np.count_nonzero(~inside))


@pytest.fixture
def outside():
    """outside(clip, *args, expected=None, **kwargs): a clip2d/clip3d call whose random
    sites partly fall outside the domain. The SiteWarning must be given once; its count is
    at least the number of empty cells (only a site outside has one; a site outside may
    still own part of the domain) and, when given, `expected` (outside.count2d(domain,
    points) counts it independently in 2D)."""
    def run(clip, *args, expected=None, **kwargs):
        with pytest.warns(voroclip.SiteWarning, match=r"sites? outside the domain") as caught:
            cells = clip(*args, **kwargs)
        counts = [int(m.group(1)) for w in caught
                  if (m := re.search(r": (\d+) sites? outside the domain", str(w.message)))]
        assert len(counts) == 1
        assert np.count_nonzero(cells.measures == 0) <= counts[0] <= len(cells.measures)
        if expected is not None:
            assert counts[0] == expected
        return cells
    run.count2d = _count_outside_2d
    return run
