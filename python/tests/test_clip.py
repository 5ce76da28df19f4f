"""clip2d / clip3d: cell measures against scipy (Voronoi cells cut by the box with a
half-space intersection, measured by ConvexHull), partition of the domain, 1 vs N threads
bit for bit, geometry and neighbours consistent with the measures, every domain input
form, and the errors bad input gets."""

import os
import re

import numpy as np
import pytest
from scipy.spatial import ConvexHull, HalfspaceIntersection, Voronoi

import voroclip

CUBE_V = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
# Outward triangles of the unit cube (vertex index = 4x + 2y + z).
CUBE_T = np.array([
    (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
    (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])


def box_cells(sites):
    """Per site: the volume (area) of its Voronoi cell cut by the unit box, from the
    half-spaces of its Voronoi ridges (scipy.spatial.Voronoi) and of the box."""
    n, dim = sites.shape
    vor = Voronoi(sites)
    nbrs = [[] for _ in range(n)]
    for i, j in vor.ridge_points:
        nbrs[i].append(j)
        nbrs[j].append(i)
    out = np.empty(n)
    eye = np.eye(dim)
    for i in range(n):
        p = sites[i]
        # Half-spaces A x + b <= 0: (pj - pi) . x <= (|pj|^2 - |pi|^2) / 2, and the box.
        q = sites[nbrs[i]]
        a = np.vstack([q - p, -eye, eye])
        b = np.concatenate([-(q * q - p * p).sum(1) / 2, np.zeros(dim), -np.ones(dim)])
        hs = HalfspaceIntersection(np.column_stack([a, b]), p)
        out[i] = ConvexHull(hs.intersections).volume
    return out


def test_clip3d_unit_cube_matches_scipy():
    rng = np.random.default_rng(2024)
    sites = rng.random((1000, 3))
    cells = voroclip.clip3d((CUBE_V, CUBE_T), sites)
    ref = box_cells(sites)
    err = np.abs(cells.volumes - ref).max()
    print(f"max |volume - scipy| = {err:.3g}")
    assert err <= 1e-9
    assert cells.total_measure == pytest.approx(1.0, rel=1e-12, abs=0)
    # Centroids inside their cells' box and the energy positive.
    assert (cells.energies > 0).all()
    assert cells.boundary.dtype == bool and 0 < cells.boundary.sum() < 1000


def test_clip2d_unit_square_matches_scipy():
    rng = np.random.default_rng(99)
    sites = rng.random((1000, 2))
    square = [np.array([(0, 0), (1, 0), (1, 1), (0, 1)], float)]
    cells = voroclip.clip2d(square, sites)
    ref = box_cells(sites)
    err = np.abs(cells.areas - ref).max()
    print(f"max |area - scipy| = {err:.3g}")
    assert err <= 1e-12
    assert cells.total_measure == pytest.approx(1.0, rel=1e-13, abs=0)


def test_sites_are_read_in_place_and_converted_otherwise():
    sites = np.random.default_rng(1).random((50, 3))
    cells = voroclip.clip3d((CUBE_V, CUBE_T), sites)
    assert cells.sites is sites  # C-contiguous float64: no copy
    f32 = sites.astype(np.float32)
    strided = np.asfortranarray(sites)
    a = voroclip.clip3d((CUBE_V, CUBE_T), f32)
    b = voroclip.clip3d((CUBE_V, CUBE_T), strided)
    assert a.sites is not f32 and a.sites.dtype == np.float64
    assert np.array_equal(b.volumes, cells.volumes)


def test_one_and_two_threads_identical(outside):
    rng = np.random.default_rng(5)
    sites3 = rng.random((20000, 3))
    a = voroclip.clip3d((CUBE_V, CUBE_T), sites3, threads=1)
    b = voroclip.clip3d((CUBE_V, CUBE_T), sites3, threads=2)
    for key in ("volumes", "centroids", "energies", "surface_areas", "boundary"):
        assert np.array_equal(getattr(a, key), getattr(b, key)), key
    sites2 = rng.random((20000, 2))
    ring = [[(0, 0), (1, 0), (1, 1), (0, 1)], [(0.3, 0.3), (0.3, 0.6), (0.6, 0.6), (0.6, 0.3)]]
    a = outside(voroclip.clip2d, ring, sites2, threads=1, neighbors=True)
    b = outside(voroclip.clip2d, ring, sites2, threads=2, neighbors=True)
    for key in ("areas", "centroids", "energies", "boundary"):
        assert np.array_equal(getattr(a, key), getattr(b, key)), key
    assert np.array_equal(a.neighbors.indices, b.neighbors.indices)


def signed_area(ring):
    x, y = ring[:, 0] - ring[0, 0], ring[:, 1] - ring[0, 1]
    return 0.5 * (x * np.roll(y, -1) - np.roll(x, -1) * y).sum()


def test_clip2d_geometry_and_neighbors(outside):
    rng = np.random.default_rng(8)
    outer = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]  # an L: not convex
    hole = [(0.2, 0.2), (0.4, 0.2), (0.4, 0.4), (0.2, 0.4)]
    d = voroclip.domain2([outer, hole])
    assert d.area == pytest.approx(3 - 0.04, rel=1e-15)
    sites = rng.random((400, 2)) * 2
    cells = outside(voroclip.clip2d, d, sites, geometry=True, neighbors=True)
    assert cells.total_measure == pytest.approx(d.area, rel=1e-13)
    for i in range(len(cells)):
        area = sum(signed_area(r) for r in cells.polygons(i))
        assert area == pytest.approx(cells.areas[i], abs=1e-13)
    ip, ix = cells.neighbors
    pairs = {(i, j) for i in range(len(cells)) for j in ix[ip[i]:ip[i + 1]]}
    assert all((j, i) in pairs for i, j in pairs)  # symmetric
    dt = voroclip.Delaunay2(sites)
    dip, dix = dt.vertex_neighbor_vertices
    for i in range(len(cells)):
        delaunay = set(dix[dip[i]:dip[i + 1]])
        mine = set(ix[ip[i]:ip[i + 1]])
        assert mine <= delaunay
        if cells.areas[i] > 0 and not cells.boundary[i]:
            assert mine == delaunay  # an inner cell keeps every Voronoi edge
    # A site outside the L: its (convex) cell is empty or crosses the boundary.
    outside = (sites[:, 0] > 1) & (sites[:, 1] > 1)
    assert (cells.areas[outside] == 0).any()
    assert (cells.boundary[outside] | (cells.areas[outside] == 0)).all()


def test_clip3d_geometry_and_neighbors():
    rng = np.random.default_rng(4)
    sites = rng.random((300, 3))
    cells = voroclip.clip3d((CUBE_V, CUBE_T), sites, geometry=True, neighbors=True)
    for i in range(len(cells)):
        vol = 0.0
        for pts, across in cells.faces(i):
            c = pts.mean(0)
            for k in range(len(pts)):
                a, b = pts[k] - c, pts[(k + 1) % len(pts)] - c
                vol += np.dot(c, np.cross(a, b)) / 6
        # Counter-clockwise seen from outside the cell, as the CLI's .vtu: the signed sum is
        # the volume (it was minus the volume).
        assert vol == pytest.approx(cells.volumes[i], rel=1e-9)
    ip, ix = cells.neighbors
    pairs = {(i, j) for i in range(len(cells)) for j in ix[ip[i]:ip[i + 1]]}
    assert all((j, i) in pairs for i, j in pairs)
    vor_pairs = {tuple(p) for p in Voronoi(sites).ridge_points.tolist()}
    vor_pairs |= {(j, i) for i, j in vor_pairs}
    assert pairs <= vor_pairs
    across = set(zip(cells.face_site.tolist(), cells.face_across.tolist()))
    assert {(i, j) for i, j in across if j >= 0} == pairs
    assert all(cells.boundary[i] for i, j in across if j == -1)


class FakeRing:
    def __init__(self, pts):
        self.coords = [tuple(p) for p in pts] + [tuple(pts[0])]  # closed, like shapely


class FakePolygon:
    def __init__(self, exterior, interiors=()):
        self.exterior = FakeRing(exterior)
        self.interiors = [FakeRing(r) for r in interiors]


def test_domain2_input_forms(data, tmp_path, outside):
    outer = [(0, 0), (1, 0), (1, 1), (0, 1)]
    hole = [(0.25, 0.25), (0.75, 0.25), (0.75, 0.75), (0.25, 0.75)]
    sites = np.random.default_rng(3).random((200, 2))
    a = outside(voroclip.clip2d, [np.array(outer), np.array(hole)], sites)
    b = outside(voroclip.clip2d, FakePolygon(outer, [hole]), sites)
    path = tmp_path / "square.poly"
    path.write_text("8 2 0 0\n" + "".join(f"{k} {x} {y}\n" for k, (x, y) in
                                        enumerate(outer + hole)) +
                    "8 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n4 4 5\n5 5 6\n6 6 7\n7 7 4\n"
                    "1\n0 0.5 0.5\n")
    c = outside(voroclip.clip2d, str(path), sites)
    assert np.array_equal(a.areas, b.areas) and np.array_equal(a.areas, c.areas)

    class FakeMulti:  # shapely's MultiPolygon: .geoms
        geoms = [FakePolygon([(0, 0), (1, 0), (1, 1), (0, 1)]),
                 FakePolygon([(2, 0), (3, 0), (3, 1), (2, 1)], [[(2.4, 0.4), (2.6, 0.4),
                                                                (2.6, 0.6), (2.4, 0.6)]])]

    m = outside(voroclip.clip2d, FakeMulti(), sites * [3, 1])
    assert m.total_measure == pytest.approx(2 - 0.04, rel=1e-14)
    assert voroclip.domain2(FakeMulti.geoms).area == pytest.approx(2 - 0.04, rel=1e-15)
    assert a.total_measure == pytest.approx(0.75, rel=1e-14)
    for f in sorted((data / "polygons" / "valid").glob("*.json")):
        d = voroclip.domain2(f)
        lo = np.array(d.bounds[:2])
        hi = np.array(d.bounds[2:])
        s = lo + np.random.default_rng(1).random((500, 2)) * (hi - lo)
        cells = outside(voroclip.clip2d, d, s, expected=outside.count2d(d, s))
        assert cells.total_measure == pytest.approx(d.area, rel=1e-12), f.name


def test_gzip_compressed_domain_files_are_read(data, tmp_path):
    import gzip

    for sub, name in (("surfaces", "sphere.obj"), ("tetmeshes", "sphere.mesh")):
        plain = voroclip.domain3(data / sub / name)
        packed = tmp_path / (name + ".gz")
        packed.write_bytes(gzip.compress((data / sub / name).read_bytes()))
        d = voroclip.domain3(packed)
        assert d.volume == plain.volume
        assert np.array_equal(d.surface()[0], plain.surface()[0])
    with pytest.raises(voroclip.Error, match="the gzip data is truncated"):
        cut = tmp_path / "cut.obj.gz"
        cut.write_bytes(packed.read_bytes()[:200])
        voroclip.domain3(cut)


def test_domain3_input_forms(data, outside):
    import meshio

    sites = np.random.default_rng(6).random((3000, 3)) * 1.6 - 0.8
    by_surface = outside(voroclip.clip3d, data / "surfaces" / "sphere.obj", sites)
    by_tets = outside(voroclip.clip3d, str(data / "tetmeshes" / "sphere.mesh"), sites)
    by_meshio = outside(voroclip.clip3d, meshio.read(data / "tetmeshes" / "sphere.mesh"), sites)
    d = voroclip.domain3(data / "surfaces" / "sphere.obj")
    v, t = d.surface()
    by_pair = outside(voroclip.clip3d, (v, t), sites)
    assert repr(d) == "Domain3(source=%r, triangles=%d, volume=%r)" % (d.source, len(t), d.volume)
    assert by_surface.total_measure == pytest.approx(d.volume, rel=1e-12)
    # The same surface (the tet mesh's boundary is the OBJ's triangles): the same cells.
    np.testing.assert_allclose(by_tets.volumes, by_surface.volumes, rtol=0, atol=1e-14)
    assert np.array_equal(by_meshio.volumes, by_tets.volumes)
    assert np.array_equal(by_pair.volumes, by_surface.volumes)


def test_density():
    sites = np.random.default_rng(2).random((200, 2))
    sq = [[(0, 0), (1, 0), (1, 1), (0, 1)]]
    c2 = voroclip.clip2d(sq, sites, density=2.0)
    c1 = voroclip.clip2d(sq, sites)
    assert np.array_equal(c2.masses, 2 * c1.masses)
    # Linear rho = 1 + x on a grid is integrated exactly; the callable with the degree-5
    # rule (7 points per fan triangle, clip/src/clip2d.cpp) is exact for it too.
    grid = (np.array([[1.0, 2.0], [1.0, 2.0]]), (0, 0), (1, 1))
    g = voroclip.clip2d(sq, sites, density=grid)
    f = voroclip.clip2d(sq, sites, density=lambda x, y: 1 + x)
    assert g.total_mass == pytest.approx(1.5, rel=1e-13)
    np.testing.assert_allclose(f.masses, g.masses, rtol=1e-12, atol=1e-15)
    with pytest.raises(ZeroDivisionError):
        voroclip.clip2d(sq, sites, density=lambda x, y: 1 / 0)


def test_bad_input_raises_error():
    sites = np.random.default_rng(1).random((20, 3))
    bad = sites.copy()
    bad[7, 1] = np.nan
    with pytest.raises(voroclip.Error, match="finite"):
        voroclip.clip3d((CUBE_V, CUBE_T), bad)
    with pytest.raises(voroclip.Error, match=r"sites: expected an \(n, 3\) array"):
        voroclip.clip3d((CUBE_V, CUBE_T), sites[:, :2])
    with pytest.raises(voroclip.Error, match="edge"):
        voroclip.clip3d((CUBE_V, CUBE_T[:-1]), sites)  # an open surface
    with pytest.raises(voroclip.Error, match="out of range"):
        voroclip.domain3((CUBE_V, CUBE_T + 1))
    with pytest.raises(voroclip.Error, match="ring"):
        voroclip.clip2d([[(0, 0), (1, 1), (1, 0), (0, 1)]], sites[:, :2])  # a bow tie
    with pytest.raises(voroclip.Error, match="at least 1 site"):
        voroclip.clip3d((CUBE_V, CUBE_T), np.empty((0, 3)))
    with pytest.raises(voroclip.Error, match="^surface: no triangles; a domain is the volume"):
        voroclip.domain3((np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)))
    with pytest.raises(voroclip.Error, match="^from_tets: no tets"):
        voroclip.Domain3.from_tets(CUBE_V, np.zeros((0, 4), dtype=np.int64), [], [], [], "")
    with pytest.raises(voroclip.Error, match="is a directory, not a file"):
        voroclip.domain3(os.path.dirname(__file__))
    # An inside-out surface: the message says what changes it in Python.
    with pytest.raises(voroclip.Error) as inside_out:
        voroclip.domain3((CUBE_V, CUBE_T[:, ::-1]))
    assert "reorient=True" in str(inside_out.value)
    assert "Surface3Options" not in str(inside_out.value)
    assert len(voroclip.domain3((CUBE_V, CUBE_T[:, ::-1]), reorient=True).surface()[1]) == 12


def csr_pairs(csr):
    ip, ix = csr
    return {(i, int(j)) for i in range(len(ip) - 1) for j in ix[ip[i]:ip[i + 1]]}


def brute_force_neighbors3(sites, samples):
    """Pairs of cells that share a face inside the unit cube, by sampling: for random
    points x, the two nearest sites i, j; where |x - s_j| - |x - s_i| is tiny, x is near
    their bisector, so (i, j) share a face there (a subset of the true pairs; with enough
    samples all of them for faces that are not tiny)."""
    d = np.linalg.norm(samples[:, None, :] - sites[None, :, :], axis=2)
    order = np.argsort(d, axis=1)[:, :2]
    gap = np.take_along_axis(d, order, axis=1)
    near = gap[:, 1] - gap[:, 0] < 2e-3
    return {(int(min(a, b)), int(max(a, b))) for a, b in order[near]}


def test_neighbors_without_the_flag_are_computed_on_first_access():
    rng = np.random.default_rng(8)
    sites = rng.random((40, 3))
    plain = voroclip.clip3d((CUBE_V, CUBE_T), sites)
    flagged = voroclip.clip3d((CUBE_V, CUBE_T), sites, neighbors=True)
    with_geometry = voroclip.clip3d((CUBE_V, CUBE_T), sites, geometry=True)
    lazy = csr_pairs(plain.neighbors)
    assert lazy == csr_pairs(flagged.neighbors) == csr_pairs(with_geometry.neighbors)
    assert np.array_equal(plain.neighbors.indptr, flagged.neighbors.indptr)
    # Symmetric, Delaunay edges (scipy), and every pair found by sampling near bisectors.
    assert all((j, i) in lazy for i, j in lazy)
    vor = {tuple(sorted(p)) for p in Voronoi(sites).ridge_points.tolist()}
    assert {(i, j) for i, j in lazy if i < j} <= vor
    sampled = brute_force_neighbors3(sites, rng.random((200000, 3)))
    assert sampled <= lazy
    # 2D alike.
    sq = [[(0, 0), (1, 0), (1, 1), (0, 1)]]
    s2 = rng.random((50, 2))
    assert csr_pairs(voroclip.clip2d(sq, s2).neighbors) == \
        csr_pairs(voroclip.clip2d(sq, s2, neighbors=True).neighbors)


def test_clip_callback_reports_phases_cancels_and_changes_nothing():
    rng = np.random.default_rng(9)
    sites = rng.random((5000, 3))
    domain = voroclip.domain3((CUBE_V, CUBE_T))
    phases = []
    with_cb = voroclip.clip3d(domain, sites, geometry=True,
                              callback=lambda info: phases.append(dict(info)))
    plain = voroclip.clip3d(domain, sites, geometry=True)
    assert [p["phase"] for p in phases if p["done"] == 0][:5] == [
        "delaunay", "surface", "boundary cells", "inner cells", "geometry"]
    assert all(p["done"] <= p["total"] for p in phases)
    for key in ("volumes", "centroids", "energies", "face_points"):
        assert np.array_equal(getattr(with_cb, key), getattr(plain, key))
    for phase in ("delaunay", "surface", "boundary cells", "inner cells"):
        with pytest.raises(voroclip.Error, match="clip3d: cancelled"):
            voroclip.clip3d(domain, sites, callback=lambda info: info["phase"] != phase)
    with pytest.raises(voroclip.Error, match="clip2d: cancelled"):
        voroclip.clip2d([[(0, 0), (1, 0), (1, 1), (0, 1)]], sites[:, :2], callback=lambda i: False)
    with pytest.raises(ZeroDivisionError):
        voroclip.clip3d(domain, sites, callback=lambda info: 1 / 0)
    # The diagram is whole again after a cancelled run.
    again = voroclip.clip3d(domain, sites, geometry=True)
    assert np.array_equal(again.volumes, plain.volumes)


@pytest.mark.parametrize("dim", [2, 3])
def test_ctrl_c_cancels_a_long_clip(dim, sigint_interrupts):
    import os
    import signal
    import threading

    rng = np.random.default_rng(10)
    if dim == 3:
        domain, sites = voroclip.domain3((CUBE_V, CUBE_T)), rng.random((200000, 3))
        clip = voroclip.clip3d
    else:
        domain, sites = voroclip.domain2([[(0, 0), (1, 0), (1, 1), (0, 1)]]), rng.random((1000000, 2))
        clip = voroclip.clip2d
    timer = threading.Timer(0.1, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            clip(domain, sites, geometry=True)
    finally:
        timer.cancel()


def test_regression_domain2_ring_index_is_checked():
    # Domain2.is_hole was bound without a range check: on a one-ring domain is_hole(1)
    # returned True (read past the ring flags) and is_hole(10**6) crashed; ring(-1) and
    # is_hole(-1) raised pybind11's TypeError.
    d = voroclip.domain2([[(0, 0), (1, 0), (1, 1), (0, 1)]])
    assert d.nb_rings == 1 and d.is_hole(0) is False
    for r in (1, 5, 10**6, 2**32 - 1, 2**64, -1):
        with pytest.raises(voroclip.Error, match=rf"^is_hole: no ring {r} \(rings 0 to 0\)$"):
            d.is_hole(r)
        with pytest.raises(voroclip.Error, match=rf"^ring: no ring {r} \(rings 0 to 0\)$"):
            d.ring(r)
    with pytest.raises(voroclip.Error, match="^is_hole: expected an integer, got float 0.5$"):
        d.is_hole(0.5)
    holed = voroclip.domain2([[(0, 0), (4, 0), (4, 4), (0, 4)], [(1, 1), (2, 1), (2, 2)]])
    assert [holed.is_hole(np.int64(r)) for r in range(holed.nb_rings)] == [False, True]
    assert holed.ring(1).shape == (3, 2)
    with pytest.raises(voroclip.Error, match=r"^is_hole: no ring 2 \(rings 0 to 1\)$"):
        holed.is_hole(2)


@pytest.mark.parametrize("bad", [-1.0, 0.0, float("nan"), float("inf")])
def test_regression_density_callable_values_are_checked(bad):
    # A callable density's values went unchecked in clip2d, clip3d and cvt2d: rho = -1 gave
    # negative masses, NaN NaN masses and a NaN energy, with no error. Now the first value
    # that is not finite and positive raises, naming the point; here rho is 1 for x < 0.5.
    rng = np.random.default_rng(8)
    s2, s3 = rng.random((30, 2)), rng.random((30, 3))
    sq = [[(0, 0), (1, 0), (1, 1), (0, 1)]]
    cube = voroclip.domain3((CUBE_V, CUBE_T))

    def rho(x, y, z=0.0):
        return 1.0 if x < 0.5 else bad

    calls = {
        "clip2d": lambda: voroclip.clip2d(sq, s2, density=rho, threads=1),
        "clip3d": lambda: voroclip.clip3d(cube, s3, density=rho, threads=1),
        "cvt2d": lambda: voroclip.cvt2d(sq, s2, density=rho, iterations=5, threads=1),
        "cvt3d": lambda: voroclip.cvt3d(cube, s3, density=rho, iterations=5, threads=1),
        "mesh2d": lambda: voroclip.mesh2d(sq, vertices=50, density=rho, threads=1),
        "random_points": lambda: voroclip.random_points(cube, 100, density=rho, threads=1),
    }
    number = r"(-?[0-9.e+-]+)"
    for name, call in calls.items():
        with pytest.raises(voroclip.Error) as e:
            call()
        m = re.fullmatch(r"density: the callable returned %s at \(%s\): the density must be "
                         r"finite and positive" % (re.escape(repr(bad)), ", ".join(
                             [number] * (2 if name in ("clip2d", "cvt2d", "mesh2d") else 3))),
                         str(e.value))
        assert m, (name, str(e.value))
        point = [float(t) for t in m.groups()]
        # In 2D the quadrature points lie in the domain; in 3D in cells that meet it.
        assert 0.5 <= point[0] <= (1 if len(point) == 2 else 2), (name, point)


def test_regression_a_bare_ring_is_the_outer_boundary():
    # clip2d(np.array of (x, y)) read each point as a ring: "ring 0: expected an (n, 2)
    # array of n >= 3 points, got shape (2,)".
    square = [(0, 0), (1, 0), (1, 1), (0, 1)]
    sites = np.random.default_rng(5).random((50, 2))
    ref = voroclip.clip2d([square], sites)
    for ring in (np.array(square, float), square, [list(p) for p in square],
                 np.array(square, np.int32), tuple(square)):
        d = voroclip.domain2(ring)
        assert d.nb_rings == 1 and not d.is_hole(0) and d.area == 1
        assert np.array_equal(voroclip.clip2d(ring, sites).areas, ref.areas)
    assert voroclip.cvt2d(np.array(square, float), sites, iterations=3).sites.shape == (50, 2)
    assert voroclip.mesh2d(np.array(square, float), vertices=50).stats["check"] == ""
    # A list of rings still is one (equal lengths: a (k, n, 2) array-like too).
    hole = [(0.25, 0.25), (0.75, 0.25), (0.75, 0.75), (0.25, 0.75)]
    for rings in ([square, hole], np.array([square, hole], float)):
        assert voroclip.domain2(rings).area == pytest.approx(0.75, rel=1e-15)
    # Numbers in another shape are neither form: said so.
    for bad in ([0, 0, 1, 0, 1, 1], np.zeros((4, 3)), [(0, 0, 0), (1, 0, 0), (1, 1, 0)]):
        with pytest.raises(voroclip.Error, match=r"a list of rings or one ring as an \(n, 2\)"):
            voroclip.domain2(bad)
    with pytest.raises(voroclip.Error, match=r"ring 0: .* n >= 3 points, got shape \(2, 2\)"):
        voroclip.domain2([(0, 0), (1, 1)])
    with pytest.raises(voroclip.Error, match="no ring"):
        voroclip.domain2([])


def _no_warning(f, *args):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return f(*args)


def test_regression_site_warning_for_sites_outside_or_repeated():
    # clip2d / clip3d said nothing about given sites outside the domain or repeated, where
    # the CLI warns: a voroclip.SiteWarning now, with the count and the first index.
    assert issubclass(voroclip.SiteWarning, UserWarning) and "SiteWarning" in voroclip.__all__
    square = [[(0, 0), (1, 0), (1, 1), (0, 1)]]
    rng = np.random.default_rng(11)
    inside = 0.05 + 0.9 * rng.random((40, 2))
    _no_warning(voroclip.clip2d, square, inside)
    s = inside.copy()
    s[[7, 30]] = (2, 0.5)  # outside (a repeat of each other too)
    s[3] = (1, 0.5)  # on the boundary: inside the closed domain, no warning
    with pytest.warns(voroclip.SiteWarning) as w:
        voroclip.clip2d(square, s)
    assert len(w) == 1 and w[0].filename == __file__
    assert str(w[0].message) == ("clip2d: 2 sites outside the domain (first: index 7, from 0); "
                                 "1 site repeats an earlier site (first: index 30, from 0; "
                                 "its cell is empty)")
    s = np.vstack([inside, inside[[5, 2, 5]], [[-0.0, 0.2]], [[0.0, 0.2]]])  # -0.0 == 0.0
    with pytest.warns(voroclip.SiteWarning, match=r"^clip2d: 4 sites repeat an earlier site "
                      r"\(first: index 40, from 0; their cells are empty\)$"):
        voroclip.clip2d(square, s)

    inside3 = 0.05 + 0.9 * rng.random((300, 3))
    _no_warning(voroclip.clip3d, (CUBE_V, CUBE_T), inside3)
    # Repeats anywhere in input order (the 3D triangulation sorts the sites): the first of
    # each group in input order keeps its cell, the others are counted.
    s3 = inside3.copy()
    s3[[250, 20, 199]] = s3[100]
    s3[[5, 6]] = (0.5, 0.5, 1.5)
    with pytest.warns(voroclip.SiteWarning) as w:
        cells = voroclip.clip3d((CUBE_V, CUBE_T), s3)
    assert str(w[0].message) == ("clip3d: 2 sites outside the domain (first: index 5, from 0); "
                                 "4 sites repeat an earlier site (first: index 6, from 0; "
                                 "their cells are empty)")
    assert cells.volumes[20] > 0 and cells.volumes[[100, 199, 250, 5, 6]].max() == 0
    # Fewer than 4 independent sites (auxiliary sites are added inside): only the given count.
    with pytest.warns(voroclip.SiteWarning, match=r"^clip3d: 1 site repeats an earlier site "
                      r"\(first: index 1,"):
        voroclip.clip3d((CUBE_V, CUBE_T), [(0.5, 0.5, 0.5)] * 2)
    _no_warning(voroclip.clip3d, (CUBE_V, CUBE_T), [(0.5, 0.5, 0.5)])


def test_regression_clip2d_and_cvt2d_take_one_site_or_sites_on_a_line():
    # They raised "sites: at least 3 sites are needed" (2D has no triangulation of fewer
    # than 3 independent points); the library now adds far auxiliary sites, as in 3D.
    holed = [[(0, 0), (1, 0), (1, 1), (0, 1)], [(0.1, 0.6), (0.3, 0.6), (0.3, 0.9), (0.1, 0.9)]]
    one = voroclip.clip2d(holed, [(0.7, 0.2)], geometry=True, neighbors=True)
    assert len(one) == 1 and one.areas[0] == pytest.approx(0.94, abs=1e-15)
    assert one.centroids[0] == pytest.approx([(0.5 - 0.012) / 0.94, (0.5 - 0.045) / 0.94],
                                             abs=1e-15)
    assert sorted(round(abs(signed_area(r)), 12) for r in one.polygons(0)) == [0.06, 1.0]
    ip, ix = one.neighbors
    assert list(ip) == [0, 0] and len(ix) == 0
    # On the diagonal: strips cut by x + y = 0.6 and x + y = 1.4.
    line = voroclip.clip2d(holed[:1], [(0.1, 0.1), (0.5, 0.5), (0.9, 0.9)], neighbors=True)
    assert line.areas == pytest.approx([0.18, 0.64, 0.18], abs=1e-15)
    ip, ix = line.neighbors
    assert [sorted(ix[ip[i]:ip[i + 1]]) for i in range(3)] == [[1], [0, 2], [1]]
    with pytest.warns(voroclip.SiteWarning, match=r"1 site repeats an earlier site"):
        two = voroclip.clip2d(holed[:1], [(0.3, 0.3), (0.3, 0.3)])
    assert list(two.areas) == [pytest.approx(1, abs=1e-15), 0]
    r = voroclip.cvt2d(holed, [(0.8, 0.1)], tolerance=1e-9)
    assert r.converged
    assert r.sites[0] == pytest.approx([(0.5 - 0.012) / 0.94, (0.5 - 0.045) / 0.94], abs=1e-9)
    with pytest.raises(voroclip.Error, match=r"sites: at least 1 site is needed, got 0"):
        voroclip.clip2d(holed, np.zeros((0, 2)))
