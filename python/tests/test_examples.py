"""The scripts of examples/python (and so the README's examples) run and do what they say."""

import pathlib
import subprocess
import sys

import meshio
import numpy as np

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python"


def test_clip2d_plot(tmp_path):
    out = tmp_path / "clip.png"
    r = subprocess.run([sys.executable, EXAMPLES / "clip2d_plot.py", out], check=True,
                       capture_output=True, text=True)
    assert out.stat().st_size > 10000
    assert r.stdout.startswith("300 cells, area 0.874")


def test_mesh_surface(data, tmp_path):
    out = tmp_path / "sphere.msh"
    subprocess.run([sys.executable, EXAMPLES / "mesh_surface.py",
                    data / "surfaces" / "sphere.obj", out, "300"], check=True)
    m = meshio.read(out)
    assert len(m.cells_dict["tetra"]) > 300
    p = m.points[m.cells_dict["tetra"]]
    assert (np.linalg.det(p[:, 1:] - p[:, :1]) > 0).all()
