"""The pure-Python layer (python/voroclip/*.py): docstrings that say what the core does, and
bad input that reaches it before the core raising voroclip.Error."""

import subprocess

import numpy as np
import pytest

import voroclip

SQUARE = [[(0, 0), (1, 0), (1, 1), (0, 1)]]
CUBE_V = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
CUBE_T = np.array([
    (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
    (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])


def test_regression_docstrings_say_what_the_core_does():
    # clip2d said a callable density had a "degree-4 rule" (clip/src/clip2d.cpp: Radon's
    # degree-5 rule, 7 points); Delaunay3 did not say its tets have det < 0; mesh3d did not
    # list max_topology_sites; mesh2d said "give one" of vertices and edge_length.
    assert "degree-5 rule, 7 points" in voroclip.clip2d.__doc__
    assert "degree-4" not in voroclip.clip2d.__doc__
    assert "det(p1 - p0, p2 - p0, p3 - p0) < 0" in voroclip.Delaunay3.__doc__
    assert "max_topology_sites" in voroclip.mesh3d.__doc__
    assert "topology_capped" in voroclip.mesh3d.__doc__
    assert "give exactly one" in voroclip.mesh2d.__doc__
    for f in (voroclip.clip2d, voroclip.clip3d):
        assert "a count above the cores runs on the cores" in " ".join(f.__doc__.split())


def test_regression_cells_index_is_checked():
    # Cells.polygons(-1) and faces(-1) returned [] (numpy's negative indexing of the
    # offsets), polygons(n) raised IndexError.
    s2 = np.random.default_rng(2).random((10, 2))
    c2 = voroclip.clip2d(SQUARE, s2, geometry=True)
    assert len(c2.polygons(np.int64(9))) == 1
    for i in (-1, 10, 2.0, True):
        with pytest.raises(voroclip.Error, match=rf"^polygons: no cell {i!r} \(cells 0 to 9\)$"):
            c2.polygons(i)
    c3 = voroclip.clip3d((CUBE_V, CUBE_T), np.random.default_rng(3).random((10, 3)),
                         geometry=True)
    assert len(c3.faces(0)) >= 4
    for i in (-1, 10):
        with pytest.raises(voroclip.Error, match=rf"^faces: no cell {i} \(cells 0 to 9\)$"):
            c3.faces(i)


def test_regression_python_conversions_raise_error():
    # The Python layer converted before the core could check: numpy's ValueError for sites
    # of strings, int()'s ValueError / TypeError for threads, iterations, n and seed.
    words = [["a", "b"], ["c", "d"], ["e", "f"]]
    cases = [
        (lambda: voroclip.clip2d(SQUARE, words), r"sites: expected an \(n, 2\) array of numbers"),
        (lambda: voroclip.cvt2d(SQUARE, words), r"sites: expected an \(n, 2\) array of numbers"),
        (lambda: voroclip.cvt2d(SQUARE, np.random.rand(5, 2), tolerance="tight"),
         "tolerance: expected a number, got 'tight'"),
        (lambda: voroclip.cvt2d(SQUARE, np.random.rand(5, 2), iterations=None),
         "iterations: expected an integer, got NoneType None"),
        (lambda: voroclip.clip2d(SQUARE, np.random.rand(5, 2), threads="two"),
         "threads: expected an integer, got str 'two'"),
        (lambda: voroclip.Delaunay2(np.random.rand(5, 2), threads=1.5),
         "threads: expected an integer, got float 1.5"),
        (lambda: voroclip.random_points((CUBE_V, CUBE_T), "3"),
         "n: expected an integer, got str '3'"),
        (lambda: voroclip.clip2d([words], np.random.rand(5, 2)),
         r"domain: ring 0: expected an \(n, 2\) array of numbers"),
        (lambda: voroclip.domain3((words, CUBE_T)),
         r"domain: expected \(vertices, triangles\) arrays"),
        (lambda: voroclip.quality(words, [[0, 1, 2]]), "quality: expected arrays"),
    ]
    for call, message in cases:
        with pytest.raises(voroclip.Error, match="^" + message):
            call()
    assert voroclip.Delaunay2(np.random.rand(5, 2), threads=None).check() == ""


def test_random_points_give_the_cli_cvt_start_with_rho_to_the_cvt_power(cli, tmp_path):
    # The README: cvt2d --random draws with rho^(1/2), so random_points with that density
    # gives the CLI's start sites, bit for bit (and with rho itself, other points).
    square = tmp_path / "square.json"
    square.write_text("[[[0, 0], [1, 0], [1, 1], [0, 1]]]")
    out = tmp_path / "sites.txt"
    subprocess.run([cli, "-q", "cvt2d", str(square), "--random", "200", "--seed", "3",
                    "--density", "1+3*x", "--iterations", "0", "-o", str(out)], check=True)
    theirs = np.loadtxt(out)
    mine = voroclip.random_points(str(square), 200, 3, lambda x, y: (1 + 3 * x) ** 0.5)
    assert np.array_equal(mine, theirs)
    assert not np.array_equal(voroclip.random_points(str(square), 200, 3, lambda x, y: 1 + 3 * x),
                              theirs)


def test_cvt_result_says_why_it_stopped():
    # CvtResult had converged and cancelled but not the CLI's "no progress" / "iteration
    # budget": stop names it.
    sites = voroclip.random_points(voroclip.domain2(SQUARE), 30, seed=2)
    assert voroclip.cvt2d(SQUARE, sites, iterations=2).stop == "iteration budget"
    done = voroclip.cvt2d(SQUARE, sites, tolerance=0.5)
    assert done.stop == "converged" and done.converged
    cancelled = voroclip.cvt3d((CUBE_V, CUBE_T), voroclip.random_points((CUBE_V, CUBE_T), 20),
                               callback=lambda info: info["iteration"] < 1)
    assert cancelled.stop == "cancelled" and cancelled.cancelled
