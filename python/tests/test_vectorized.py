"""Vectorized density and sizing callables (``vectorized=True``): called with arrays of
points, giving the bits of the same formula called point by point, and of the CLI's."""

import subprocess

import numpy as np
import pytest

import voroclip


class Recorder:
    """A vectorized callable that records the shapes it is called with."""

    def __init__(self, f):
        self.f = f
        self.sizes = []

    def __call__(self, *xs):
        for x in xs:
            assert isinstance(x, np.ndarray) and x.dtype == np.float64 and x.ndim == 1
            assert x.shape == xs[0].shape
        self.sizes.append(len(xs[0]))
        return self.f(*xs)


def rho3(x, y, z):
    return 1 + x * x + 0.5 * y - 0.25 * z


def test_clip3d_vectorized_matches_point_by_point(data):
    bunny = voroclip.domain3(str(data / "surfaces" / "sphere.obj"))
    sites = voroclip.random_points(bunny, 300, seed=3)
    pointwise = voroclip.clip3d(bunny, sites, density=lambda x, y, z: rho3(x, y, z) + 2,
                                threads=1)
    f = Recorder(lambda x, y, z: rho3(x, y, z) + 2)
    for threads in (1, 2):
        vec = voroclip.clip3d(bunny, sites, density=f, vectorized=True, threads=threads)
        # The same values at the same points: the same bits, for any thread count.
        assert np.array_equal(vec.masses, pointwise.masses)
        assert np.array_equal(vec.centroids, pointwise.centroids)
        assert np.array_equal(vec.energies, pointwise.energies)
    # Called with many points at once: a chunk of inner cells' quadrature points.
    assert max(f.sizes) > 1000
    # One number for all points: the density 2, twice the volumes.
    two = voroclip.clip3d(bunny, sites, density=lambda x, y, z: 2.0, vectorized=True)
    assert np.allclose(two.masses, 2 * two.volumes, rtol=1e-12, atol=0)


def test_cvt3d_and_random_points_vectorized(data):
    sphere = voroclip.domain3(str(data / "surfaces" / "sphere.obj"))
    sites = voroclip.random_points(sphere, 60, seed=2)
    a = voroclip.cvt3d(sphere, sites, iterations=5, density=rho3_plus, threads=1)
    b = voroclip.cvt3d(sphere, sites, iterations=5, density=rho3_plus, vectorized=True)
    assert np.array_equal(a.sites, b.sites) and a.energy == b.energy
    p = voroclip.random_points(sphere, 200, seed=5, density=rho3_plus)
    q = voroclip.random_points(sphere, 200, seed=5, density=rho3_plus, vectorized=True)
    assert np.array_equal(p, q)


def rho3_plus(x, y, z):
    return rho3(x, y, z) + 2


def test_2d_vectorized_called_one_point_at_a_time():
    square = voroclip.domain2([[(0, 0), (1, 0), (1, 1), (0, 1)],
                               [(0.4, 0.4), (0.6, 0.4), (0.6, 0.6), (0.4, 0.6)]])
    sites = voroclip.random_points(square, 40, seed=1)
    f = Recorder(lambda x, y: 1 + x * x + y)
    a = voroclip.clip2d(square, sites, density=lambda x, y: 1 + x * x + y)
    b = voroclip.clip2d(square, sites, density=f, vectorized=True)
    assert np.array_equal(a.masses, b.masses) and np.array_equal(a.energies, b.energies)
    assert set(f.sizes) == {1}
    c = voroclip.cvt2d(square, sites, iterations=3, density=lambda x, y: 1 + x * x + y)
    d = voroclip.cvt2d(square, sites, iterations=3, density=lambda x, y: 1 + x * x + y,
                       vectorized=True)
    assert np.array_equal(c.sites, d.sites)


def test_mesh3d_vectorized_as_the_cli(data, cli, tmp_path):
    # The CLI's --density / --sizing formulas and vectorized callables of the same
    # arithmetic give the same mesh, byte for byte.
    sphere = str(data / "surfaces" / "sphere.obj")
    for flags, kwargs in ((["--vertices", "80", "--density", "1+x*x"],
                           dict(vertices=80, density=lambda x, y, z: 1 + x * x)),
                          (["--vertices", "120", "--sizing", "0.3+0.1*abs(y)"],
                           dict(vertices=120, sizing=lambda x, y, z: 0.3 + 0.1 * np.abs(y)))):
        theirs, mine = tmp_path / "cli.mesh", tmp_path / "py.mesh"
        subprocess.run([cli, "-q", "mesh3d", sphere, *flags, "-o", str(theirs)], check=True)
        voroclip.mesh3d(sphere, vectorized=True, **kwargs).write(mine)
        assert mine.read_bytes() == theirs.read_bytes(), flags


def test_vectorized_errors(data):
    sphere = voroclip.domain3(str(data / "surfaces" / "sphere.obj"))
    sites = voroclip.random_points(sphere, 50, seed=1)
    with pytest.raises(ValueError, match=r"^density: the vectorized callable returned an array "
                       r"of shape \(\d+, 1\) for \d+ points; expected \(\d+,\) or one number$"):
        voroclip.clip3d(sphere, sites, density=lambda x, y, z: np.ones((len(x), 1)),
                        vectorized=True)
    with pytest.raises(ValueError, match=r"shape \(2,\) for \d+ points"):
        voroclip.clip3d(sphere, sites, density=lambda x, y, z: np.ones(2), vectorized=True)
    with pytest.raises(TypeError, match="^density: the vectorized callable must return an "
                       "array of numbers, got 'abc'$"):
        voroclip.clip3d(sphere, sites, density=lambda x, y, z: "abc", vectorized=True)
    with pytest.raises(voroclip.Error, match=r"^density: the callable returned -1\.0 at \("):
        voroclip.clip3d(sphere, sites, density=lambda x, y, z: np.where(x > 0.5, -1.0, 1.0),
                        vectorized=True)
    with pytest.raises(voroclip.Error, match=r"^sizing: the callable returned nan at \("):
        voroclip.mesh3d(sphere, 100, sizing=lambda x, y, z: x * np.nan, vectorized=True)

    def boom(x, y, z):
        raise KeyError("boom")

    with pytest.raises(KeyError, match="boom"):
        voroclip.cvt3d(sphere, sites, iterations=2, density=boom, vectorized=True)
    with pytest.raises(voroclip.Error, match="^vectorized: expected a callable, got 3$"):
        voroclip._core.Vectorized(3)
    # A number is not a callable: vectorized changes nothing.
    a = voroclip.clip3d(sphere, sites, density=2.0, vectorized=True)
    assert np.array_equal(a.masses, voroclip.clip3d(sphere, sites, density=2.0).masses)


def test_mesh2d_sizing_as_the_cli(cli, tmp_path):
    # Python's mesh2d had no sizing (the CLI's --sizing): a callable h(x, y), plain or
    # vectorized, gives the CLI's mesh byte for byte, alone (h absolute) or with vertices.
    square = tmp_path / "square.json"
    square.write_text("[[[0, 0], [1, 0], [1, 1], [0, 1]]]")
    for flags, kwargs in ((["--sizing", "0.05+0.1*x"], {}),
                          (["--vertices", "150", "--sizing", "0.05+0.1*x"], dict(vertices=150))):
        theirs = tmp_path / "cli.msh"
        subprocess.run([cli, "-q", "mesh2d", str(square), *flags, "-o", str(theirs)], check=True)
        for vectorized in (False, True):
            mine = tmp_path / "py.msh"
            voroclip.mesh2d(str(square), sizing=lambda x, y: 0.05 + 0.1 * x,
                            vectorized=vectorized, **kwargs).write(mine)
            assert mine.read_bytes() == theirs.read_bytes(), (flags, vectorized)
    # A number is the edge length.
    assert np.array_equal(voroclip.mesh2d(str(square), sizing=0.1).points,
                          voroclip.mesh2d(str(square), edge_length=0.1).points)
    with pytest.raises(voroclip.Error, match="sizing and edge_length exclude each other"):
        voroclip.mesh2d(str(square), edge_length=0.1, sizing=0.1)
    with pytest.raises(voroclip.Error, match="density and sizing exclude each other"):
        voroclip.mesh2d(str(square), sizing=0.1, density=2.0)
    with pytest.raises(voroclip.Error, match=r"^sizing: the callable returned 0\.0 at \("):
        voroclip.mesh2d(str(square), 100, sizing=lambda x, y: 0.0)


def test_mesh2d_implied_vertices(tmp_path):
    # The CLI's note "about N vertices for this size": stats and the progress callback.
    square = tmp_path / "square.json"
    square.write_text("[[[0, 0], [1, 0], [1, 1], [0, 1]]]")
    events = []
    m = voroclip.mesh2d(str(square), sizing=lambda x, y: 0.05, callback=events.append)
    implied = m.stats["implied_vertices"]
    assert abs(implied - 2 / 3 ** 0.5 / 0.05 ** 2) <= 1
    assert [e["implied_vertices"] for e in events if "implied_vertices" in e] == [implied]
    assert 0.8 * implied <= len(m.points) <= 1.25 * implied
    assert voroclip.mesh2d(str(square), 100).stats["implied_vertices"] is None


def test_mesh3d_implied_vertices(data):
    # The count an absolute size asks for, once, before anything else (the CLI checks it
    # against the memory and says "about 2340 vertices for this size"); False stops there.
    sphere = str(data / "surfaces" / "sphere.obj")
    events = []
    m = voroclip.mesh3d(sphere, sizing=0.15, callback=events.append)
    assert [e.get("implied_vertices") for e in events][:1] == [2338]
    assert sum("implied_vertices" in e for e in events) == 1
    assert 0.9 * 2338 <= len(m.points) <= 1.1 * 2338
    stopped = voroclip.mesh3d(sphere, sizing=0.15,
                              callback=lambda e: "implied_vertices" not in e)
    assert stopped.stats["cancelled"] and stopped.cells.shape == (0, 4)
    counted = []
    voroclip.mesh3d(sphere, 300, callback=counted.append)  # a vertex count: no such event
    assert not any("implied_vertices" in e for e in counted)
