"""Delaunay2 / Delaunay3 against scipy.spatial.Delaunay (Qhull) on generic random input:
the same simplices as sets, the same neighbour structure, the same point location; and the
exact checker on degenerate input, where Qhull and voroclip may legitimately differ."""

import numpy as np
import pytest
from scipy.spatial import Delaunay as ScipyDelaunay

import voroclip


def simplex_set(simplices):
    return {tuple(sorted(s)) for s in simplices.tolist()}


@pytest.mark.parametrize("dim,n", [(2, 2000), (3, 1000)])
def test_same_simplices_as_scipy(dim, n):
    rng = np.random.default_rng(7 + dim)
    pts = rng.random((n, dim))
    ours = (voroclip.Delaunay2 if dim == 2 else voroclip.Delaunay3)(pts)
    ref = ScipyDelaunay(pts)
    assert ours.check() == ""
    assert ours.simplices.dtype == np.int32 and ours.simplices.shape[1] == dim + 1
    assert simplex_set(ours.simplices) == simplex_set(ref.simplices)

    # neighbors: the simplex opposite vertex k, -1 on the hull, mapped through the sets.
    index = {tuple(sorted(s)): i for i, s in enumerate(ref.simplices.tolist())}
    to_ref = np.array([index[tuple(sorted(s))] for s in ours.simplices.tolist()])
    for t, s in enumerate(ours.simplices):
        for k in range(dim + 1):
            nb = ours.neighbors[t, k]
            r = to_ref[t]
            kr = list(ref.simplices[r]).index(s[k])
            expected = ref.neighbors[r, kr]
            assert (nb == -1) == (expected == -1)
            if nb != -1:
                assert to_ref[nb] == expected
    # Hull facets = neighbours -1: a closed hull needs dim-1 faces with -1 exactly on it.
    assert (ours.neighbors == -1).sum() == (ref.neighbors == -1).sum()

    # Point location: generic queries, inside and outside.
    q = rng.random((500, dim)) * 1.2 - 0.1
    found = ours.find_simplex(q)
    expected = ref.find_simplex(q)
    assert ((found == -1) == (expected == -1)).all()
    inside = found >= 0
    assert (to_ref[found[inside]] == expected[inside]).all()

    # Vertex neighbours: scipy's (indptr, indices) as sets per vertex.
    ip, ix = ours.vertex_neighbor_vertices
    rip, rix = ref.vertex_neighbor_vertices
    for v in range(n):
        assert set(ix[ip[v]:ip[v + 1]]) == set(rix[rip[v]:rip[v + 1]])
        assert sorted(ours.vertex_neighbors(v)) == sorted(rix[rip[v]:rip[v + 1]])


def test_nearest_vertex_is_exact_nearest():
    rng = np.random.default_rng(3)
    pts = rng.random((300, 2))
    d = voroclip.Delaunay2(pts)
    q = rng.random((200, 2))
    brute = np.argmin(((q[:, None, :] - pts[None]) ** 2).sum(-1), axis=1)
    assert (d.nearest_vertex(q) == brute).all()


def test_degenerate_grid_and_duplicates():
    g = np.array([(x, y) for x in range(20) for y in range(20)], dtype=float)
    pts = np.vstack([g, g[:10]])  # 10 duplicates at the end
    d = voroclip.Delaunay2(pts)
    assert d.check() == ""
    # A 20 x 20 grid: 2 * 19 * 19 triangles; duplicates are not vertices.
    assert len(d.simplices) == 2 * 19 * 19
    assert (d.duplicate_of[400:] == np.arange(10)).all()
    assert len(d.vertex_neighbors(405)) == 0
    cube = np.array([(x, y, z) for x in range(5) for y in range(5) for z in range(5)], float)
    d3 = voroclip.Delaunay3(cube)
    assert d3.check() == ""
    # The tets tile the cube: volumes sum to 4^3 exactly (integer coordinates).
    p = cube[d3.simplices]
    vol = np.abs(np.linalg.det(p[:, 1:] - p[:, :1])).sum() / 6
    assert vol == pytest.approx(64, abs=1e-12)


def test_same_result_any_thread_count():
    pts = np.random.default_rng(11).random((50000, 2))
    a = voroclip.Delaunay2(pts, threads=1)
    b = voroclip.Delaunay2(pts, threads=2)
    assert np.array_equal(a.simplices, b.simplices)
    assert np.array_equal(a.neighbors, b.neighbors)


@pytest.mark.parametrize("cls,dim", [(voroclip.Delaunay2, 2), (voroclip.Delaunay3, 3)])
def test_bad_input_raises(cls, dim):
    with pytest.raises(voroclip.Error, match=r"expected an \(n, %d\) array" % dim):
        cls(np.zeros((5, dim + 1)))
    pts = np.random.default_rng(1).random((10, dim))
    pts[4, 0] = np.nan
    with pytest.raises(voroclip.Error, match="finite"):
        cls(pts)
    with pytest.raises(voroclip.Error):
        cls(np.zeros((10, dim)))  # all points equal: no triangulation
    assert issubclass(voroclip.Error, ValueError)


@pytest.mark.parametrize("cls,dim", [(voroclip.Delaunay2, 2), (voroclip.Delaunay3, 3)])
def test_regression_vertex_neighbors_index_is_checked(cls, dim):
    # vertex_neighbors(-1) raised pybind11's TypeError (an unsigned C++ argument).
    d = cls(np.random.default_rng(5).random((20, dim)))
    assert len(d.vertex_neighbors(np.int32(19))) >= dim
    for v in (20, 2**32, -1):
        with pytest.raises(voroclip.Error, match=rf"^vertex_neighbors: no point {v} "
                                                 r"\(points 0 to 19\)$"):
            d.vertex_neighbors(v)
    with pytest.raises(voroclip.Error, match="^vertex_neighbors: expected an integer, got str"):
        d.vertex_neighbors("3")


@pytest.mark.parametrize("cls,dim", [(voroclip.Delaunay2, 2), (voroclip.Delaunay3, 3)])
def test_regression_find_simplex_takes_one_point_as_scipy_does(cls, dim):
    # find_simplex / nearest_vertex of one point, shape (d,), raised "expected an (n, d)
    # array"; scipy.spatial.Delaunay.find_simplex takes xi of any shape (..., d) and answers
    # in shape (...): a 0-d array for one point.
    rng = np.random.default_rng(12 + dim)
    pts = rng.random((200, dim))
    ours, ref = cls(pts), ScipyDelaunay(pts)
    q = rng.random((4, 5, dim)) * 1.2 - 0.1
    flat = ours.find_simplex(q.reshape(-1, dim))
    got = ours.find_simplex(q)
    assert got.shape == ref.find_simplex(q).shape == (4, 5)
    assert np.array_equal(got.ravel(), flat)
    assert np.array_equal(got == -1, ref.find_simplex(q) == -1)
    for k in range(20):
        one = ours.find_simplex(q[k // 5, k % 5])
        assert one.shape == ref.find_simplex(q[k // 5, k % 5]).shape == ()
        assert one == flat[k] and ours.find_simplex(list(q[k // 5, k % 5])) == flat[k]
        near = ours.nearest_vertex(q[k // 5, k % 5])
        assert near.shape == () and near == np.argmin(((pts - q[k // 5, k % 5]) ** 2).sum(1))
    assert np.array_equal(ours.nearest_vertex(q).ravel(),
                          ours.nearest_vertex(q.reshape(-1, dim)))
    for bad in (np.zeros(dim + 1), np.zeros((2, dim - 1)), 0.5):
        shape = ", ".join(map(str, np.shape(bad))) + ("," if np.ndim(bad) == 1 else "")
        for f in (ours.find_simplex, ours.nearest_vertex):
            with pytest.raises(voroclip.Error, match=rf"^xi: expected an \(n, {dim}\) array or "
                                                     rf"one point \({dim},\), got shape "
                                                     rf"\({shape}\)$"):
                f(bad)


def test_delaunay3_simplices_orientation_is_documented_and_holds():
    # Delaunay3's tets are the opposite of Mesh.cells' (det > 0): det(p1 - p0, p2 - p0,
    # p3 - p0) < 0, i.e. orient3d(p0, p1, p2, p3) = +1, exactly, on generic and degenerate
    # (grid) input; the docstring says so (it said nothing). Delaunay2's are counter-clockwise.
    grid = np.array([(x, y, z) for x in range(4) for y in range(4) for z in range(4)], float)
    for pts in (np.random.default_rng(9).random((500, 3)), grid):
        p = pts[voroclip.Delaunay3(pts).simplices]
        assert (voroclip.orient3d(p[:, 0], p[:, 1], p[:, 2], p[:, 3]) == 1).all()
        assert (np.linalg.det(p[:, 1:] - p[:, :1]) < 0).all()
    p = grid[:16, 1:][voroclip.Delaunay2(grid[:16, 1:]).simplices]
    assert (voroclip.orient2d(p[:, 0], p[:, 1], p[:, 2]) == 1).all()
    assert "det(p1 - p0, p2 - p0, p3 - p0) < 0" in voroclip.Delaunay3.simplices.__doc__
    assert "orient3d(p0, p1, p2, p3) = +1" in voroclip.Delaunay3.simplices.__doc__
    assert "counter-clockwise" in voroclip.Delaunay2.simplices.__doc__


def test_vertex_neighbors_2d_go_counter_clockwise():
    pts = np.random.default_rng(8).random((200, 2))
    dt = voroclip.Delaunay2(pts)
    hull = set(np.unique(dt.convex_hull).tolist())
    indptr, indices = dt.vertex_neighbor_vertices
    checked = 0
    for v in range(len(pts)):
        ring = dt.vertex_neighbors(v)
        assert np.array_equal(ring, indices[indptr[v]:indptr[v + 1]])
        if v in hull:
            continue
        a, b = pts[ring] - pts[v], pts[np.roll(ring, -1)] - pts[v]
        assert np.all(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] > 0)
        checked += 1
    assert checked > 150


def facet_set(facets):
    return {tuple(sorted(f)) for f in facets.tolist()}


@pytest.mark.parametrize("dim,n", [(2, 500), (3, 400)])
def test_regression_scipy_attributes_ndim_nsimplex_convex_hull_hull_vertices(dim, n):
    # Delaunay3 had no convex_hull, Delaunay2 no hull_vertices, neither ndim nor nsimplex.
    from scipy.spatial import ConvexHull

    seed = 17 + dim
    pts = np.random.default_rng(seed).random((n, dim))
    ours = (voroclip.Delaunay2 if dim == 2 else voroclip.Delaunay3)(pts)
    ref = ScipyDelaunay(pts)
    assert type(ours.ndim) is int and ours.ndim == ref.ndim == dim, seed
    assert type(ours.nsimplex) is int and ours.nsimplex == ref.nsimplex == len(ours.simplices)
    hull = ours.convex_hull
    assert hull.dtype == ref.convex_hull.dtype == np.int32 and hull.shape[1] == dim
    assert len(hull) == len(ref.convex_hull) and facet_set(hull) == facet_set(ref.convex_hull)
    # Outward: counter-clockwise seen from outside, exactly (the centroid is inside).
    c = pts.mean(axis=0)
    if dim == 2:
        assert (voroclip.orient2d(pts[hull[:, 0]], pts[hull[:, 1]], c) == 1).all()
    else:
        assert (voroclip.orient3d(pts[hull[:, 0]], pts[hull[:, 1]], pts[hull[:, 2]], c) == 1).all()
    hv = ours.hull_vertices
    assert hv.dtype == np.int32
    ch = ConvexHull(pts).vertices
    if dim == 2:  # scipy's 2D order: counter-clockwise (from a vertex of its own)
        k = int(np.flatnonzero(ch == hv[0])[0])
        assert np.array_equal(np.roll(ch, -k), hv) and hv[0] == hv.min()
        assert np.array_equal(hull[:, 0], hv)
    else:
        assert np.array_equal(hv, np.sort(ch))
    assert set(np.unique(hull).tolist()) == set(hv.tolist())


def test_regression_hull_attributes_on_degenerate_input():
    # Points on the hull's edges and faces are vertices of it, as in scipy (Qhull with Qz /
    # Qt): a grid's 2D hull edges are scipy's; in 3D the coplanar faces are triangulated
    # (the diagonals may differ from Qhull's: the same vertices, count and area).
    g = np.array([(x, y) for x in range(6) for y in range(4)], float)
    pts = np.vstack([g, g[:3]])  # duplicates: only the first is a vertex
    d, ref = voroclip.Delaunay2(pts), ScipyDelaunay(g)
    assert d.nsimplex == ref.nsimplex == 2 * 5 * 3 and d.ndim == 2
    assert facet_set(d.convex_hull) == facet_set(ref.convex_hull)
    assert len(d.hull_vertices) == 2 * (5 + 3) and d.hull_vertices[0] == 0
    assert (voroclip.orient2d(pts[d.convex_hull[:, 0]], pts[d.convex_hull[:, 1]], (2.5, 1.5))
            == 1).all()
    for pts3 in (np.array([(x, y, z) for x in range(3) for y in range(3) for z in range(4)], float),
                 CUBE8, np.vstack([CUBE8, CUBE8[::-1]]),
                 np.vstack([np.eye(3), -np.eye(3)])):  # cospherical: cube, octahedron
        d3, ref3 = voroclip.Delaunay3(pts3), ScipyDelaunay(pts3)
        assert d3.check() == "" and d3.ndim == 3 and d3.nsimplex == len(d3.simplices)
        hull = d3.convex_hull
        assert hull.shape == ref3.convex_hull.shape and hull.dtype == np.int32
        assert set(np.unique(hull).tolist()) == set(d3.hull_vertices.tolist())
        first = d3.duplicate_of[np.unique(ref3.convex_hull)]
        assert set(d3.hull_vertices.tolist()) == set(first.tolist())
        a, b, c = (pts3[hull[:, k]] for k in range(3))
        area = np.linalg.norm(np.cross(b - a, c - a), axis=1).sum() / 2
        r = pts3[ref3.convex_hull]
        ref_area = np.linalg.norm(np.cross(r[:, 1] - r[:, 0], r[:, 2] - r[:, 0]), axis=1).sum() / 2
        assert area == pytest.approx(ref_area, rel=1e-14)
        centre = pts3.mean(axis=0)
        assert (voroclip.orient3d(a, b, c, centre) == 1).all()


CUBE8 = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
