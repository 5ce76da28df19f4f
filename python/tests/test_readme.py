"""The README's quick start works as written: every `build/release/bin/voroclip ...` line of
its shell blocks and its Python block under "From Python" run (in a temporary folder, with
the tool under test and examples/data of this repository) and write what they say."""

import os
import pathlib
import re
import shlex
import subprocess
import sys

import pytest

from conftest import REPO

README = (REPO / "README.md").read_text()
QUICK = README[README.index("## Quick start"):README.index("## What it is")]


def shell_commands(text):
    blocks = re.findall(r"```sh\n(.*?)```", text, re.S)
    return [line for b in blocks for line in b.splitlines()
            if line.startswith("build/release/bin/voroclip ")]


def test_the_readme_points_nowhere_outside_the_repository():
    assert "../" not in README and "/work/" not in README
    for link in re.findall(r"\]\(([^)#]+)\)", README):
        assert (REPO / link).exists(), link


def test_quick_start_commands(cli, tmp_path):
    commands = shell_commands(QUICK)
    assert len(commands) == 7
    for line in commands:
        args = shlex.split(line)[1:]
        args = [str(REPO / a) if a.startswith("examples/") else a for a in args]
        r = subprocess.run([os.path.abspath(cli), "-q", *args], cwd=tmp_path, capture_output=True,
                           text=True)
        assert r.returncode == 0, (line, r.stderr)
        if "-o" in args:
            assert (tmp_path / args[args.index("-o") + 1]).stat().st_size > 0, line
    assert (tmp_path / "cells.csv").read_text().startswith("site,x,y,z,volume,")
    assert (tmp_path / "pairs.csv").read_text().startswith("site_a,site_b,area")
    assert (tmp_path / "torus.msh").read_text().startswith("$MeshFormat\n4.1 0 8\n")


def test_quick_start_python(tmp_path):
    code = re.search(r"### From Python\n\n```python\n(.*?)```", QUICK, re.S).group(1)
    code = code.replace('"examples/', '"' + str(REPO / "examples") + "/")
    import voroclip

    # The package under test, wherever it is (PYTHONPATH may be relative to the repository).
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(voroclip.__file__).resolve().parents[1]))
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
                       env=env)
    assert r.returncode == 0, r.stderr
    volume = float(r.stdout.split()[0])
    # The torus's volume, 2 pi^2 R r^2 = 3.158 for the smooth torus, a little less for the
    # 32 x 16 polyhedron.
    assert 3.0 < volume < 3.16
    assert (tmp_path / "torus.msh").read_text().startswith("$MeshFormat\n4.1 0 8\n")
