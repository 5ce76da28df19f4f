"""cvt2d / cvt3d, mesh2d / mesh3d, to_meshio round trips, quality, callbacks and Ctrl-C."""

import os
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

import voroclip

SQUARE = [[(0, 0), (1, 0), (1, 1), (0, 1)]]
CUBE_V = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
CUBE_T = np.array([
    (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
    (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])


@pytest.mark.parametrize("method", ["lbfgs", "lloyd"])
def test_cvt2d_lowers_the_energy_to_a_centroidal_configuration(method):
    sites = np.random.default_rng(1).random((100, 2))
    r = voroclip.cvt2d(SQUARE, sites, method=method, iterations=300, tolerance=1e-3)
    assert r.sites.shape == (100, 2) and not np.shares_memory(r.sites, sites)
    assert r.energy_history[0] > r.energy_history[-1] == r.energy
    assert r.converged and r.gradient_norm <= 1e-3 * r.initial_gradient_norm
    # Centroidal: each site near its cell's centroid, by the clipped diagram itself.
    cells = voroclip.clip2d(SQUARE, r.sites)
    assert cells.total_energy == pytest.approx(r.energy, rel=1e-12)
    assert np.abs(cells.centroids - r.sites).max() < 0.01
    assert len(r.energy_history) == r.iterations + 1


def test_cvt_threads_and_callback_stop():
    sites = np.random.default_rng(2).random((300, 3))
    a = voroclip.cvt3d((CUBE_V, CUBE_T), sites, iterations=10, threads=1)
    b = voroclip.cvt3d((CUBE_V, CUBE_T), sites, iterations=10, threads=2)
    assert np.array_equal(a.sites, b.sites) and a.energy == b.energy
    seen = []

    def stop_at_3(info):
        seen.append(info["iteration"])
        return info["iteration"] < 3

    c = voroclip.cvt3d((CUBE_V, CUBE_T), sites, iterations=10, callback=stop_at_3)
    assert c.cancelled and not c.converged and seen[-1] == 3 and c.iterations == 3
    # Any truth value: 0 stops at the start; an object whose truth raises, raises.
    z = voroclip.cvt2d(SQUARE, sites[:, :2], callback=lambda info: 0)
    assert z.cancelled and z.iterations == 0 and np.array_equal(z.sites, sites[:, :2])

    class NoTruth:
        def __bool__(self):
            raise TypeError("no truth")

    with pytest.raises(TypeError, match="no truth"):
        voroclip.cvt2d(SQUARE, sites[:, :2], callback=lambda info: NoTruth())
    with pytest.raises(voroclip.Error, match="threads"):
        voroclip.cvt2d(SQUARE, sites[:, :2], threads=-1)
    with pytest.raises(RuntimeError, match="boom"):
        voroclip.cvt2d(SQUARE, sites[:, :2], callback=lambda info: (_ for _ in ()).throw(
            RuntimeError("boom")))


def test_ctrl_c_cancels_a_long_run(sigint_interrupts):
    sites = np.random.default_rng(3).random((3000, 3))
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            voroclip.cvt3d((CUBE_V, CUBE_T), sites, iterations=100000, tolerance=0)
    finally:
        timer.cancel()


def test_mesh2d_to_meshio_round_trip(tmp_path):
    import meshio

    ring = [[(0, 0), (2, 0), (2, 1), (0, 1)], [(0.5, 0.4), (0.5, 0.6), (0.7, 0.6), (0.7, 0.4)]]
    m = voroclip.mesh2d(ring, vertices=300)
    assert m.points.shape[1] == 2 and m.cells.shape[1] == 3 and len(m.cells) > 300
    p = m.points[m.cells]
    area = ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
            - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])) / 2
    assert (area > 0).all()
    # Conforming (the library's default): the triangles cover the domain exactly, up to the
    # rounding of the boundary vertices; the mesh passed its own checks.
    assert area.sum() == pytest.approx(2 - 0.04, rel=1e-12)
    assert m.stats["check"] == ""
    paper = voroclip.mesh2d(ring, vertices=300, conforming=False)
    assert paper.stats["covered_fraction"] < 1
    q = voroclip.quality(m)
    assert q.report["nb_triangles"] == len(m.cells)
    assert q.q1.min() == pytest.approx(q.report["min_angle_deg"], rel=1e-9)
    for ext in (".msh", ".vtu"):
        f = tmp_path / ("m2" + ext)
        m.write(f)
        back = meshio.read(f, file_format="gmsh" if ext == ".msh" else None)
        assert np.array_equal(back.points[:, :2], m.points)
        assert np.array_equal(back.cells_dict["triangle"], m.cells)


def test_mesh3d_sphere_round_trips_and_quality(data, tmp_path):
    import meshio

    m = voroclip.mesh3d(data / "surfaces" / "sphere.obj", vertices=400, threads=2)
    assert m.shape_problem == ""
    assert len(m.points) >= 300 and m.cells.shape[1] == 4
    p = m.points[m.cells]
    det = np.linalg.det(p[:, 1:] - p[:, :1])
    assert (det > 0).all()
    assert len(m.boundary_triangles) == len(m.boundary_tags) and len(m.cell_tags) == len(m.cells)
    q = voroclip.quality(m)
    assert q.report["tets"] == len(m.cells) and q.report["inverted_tets"] == 0
    assert q.q1.min() == q.report["min_min_dihedral_deg"]
    assert q.q3.min() == q.report["min_q3"] and q.q4.min() == q.report["min_q4"]
    assert q.dihedral.min() == q.report["min_dihedral_deg"]
    np.testing.assert_allclose(q.volume, det / 6, rtol=1e-12)
    q1 = voroclip.quality(m.points, m.cells, threads=1)
    assert np.array_equal(q1.q4, q.q4) and q1.report == q.report
    one = voroclip.mesh3d(data / "surfaces" / "sphere.obj", vertices=400, threads=1)
    assert np.array_equal(one.points, m.points) and np.array_equal(one.cells, m.cells)
    for ext in (".msh", ".vtu", ".mesh"):
        f = tmp_path / ("m3" + ext)
        m.write(f)
        back = meshio.read(f, file_format="gmsh" if ext == ".msh" else None)
        assert np.array_equal(back.points, m.points)
        assert np.array_equal(back.cells_dict["tetra"], m.cells)
        assert np.array_equal(back.cells_dict["triangle"], m.boundary_triangles)
        if ext != ".vtu":
            tags = back.cell_data_dict["gmsh:physical" if ext == ".msh" else "medit:ref"]
            assert np.array_equal(tags["tetra"], m.cell_tags)
            assert np.array_equal(tags["triangle"], m.boundary_tags)
        if ext == ".msh":
            # Every physical group named ($PhysicalNames): a surface has no names of its own.
            expected = {f"patch {t}": [t, 2] for t in set(m.boundary_tags.tolist())}
            expected.update({f"region {t}": [t, 3] for t in set(m.cell_tags.tolist())})
            assert {k: v.tolist() for k, v in back.field_data.items()} == expected
            assert (3, 1, "region 1") in m.tag_names
    # The .msh file read back by voroclip as a domain (its own Gmsh reader).
    d = voroclip.domain3(tmp_path / "m3.msh")
    assert d.has_tets and d.nb_tets == len(m.cells)
    cells = voroclip.clip3d(d, m.points)
    assert cells.total_measure == pytest.approx(d.volume, rel=1e-12)


def test_mesh_callback_and_errors():
    phases = set()

    def cb(info):
        phases.add(info["phase"])

    voroclip.mesh2d(SQUARE, vertices=50, callback=cb)
    assert {"sampling", "unconstrained CVT", "constrained CVT"} <= phases
    with pytest.raises(voroclip.Error):
        voroclip.mesh2d(SQUARE)  # neither vertices nor edge_length
    with pytest.raises(voroclip.Error):
        voroclip.mesh3d((CUBE_V, CUBE_T), vertices=2)
    with pytest.raises(voroclip.Error, match="unknown option 'vertex'"):
        voroclip.mesh2d(SQUARE, vertex=50)
    with pytest.raises(voroclip.Error, match="option 'seed': expected an integer, got str 'one'"):
        voroclip.mesh3d((CUBE_V, CUBE_T), vertices=50, seed="one")
    with pytest.raises(voroclip.Error, match="option 'gradation': a value of the wrong type"):
        voroclip.mesh2d(SQUARE, vertices=50, gradation="steep")
    with pytest.raises(voroclip.Error, match="method"):
        voroclip.cvt2d(SQUARE, np.random.default_rng(0).random((10, 2)), method="newton")


def test_mesh2d_tags_reach_python_and_meshio(tmp_path):
    import meshio

    poly = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "apps", "tagged_square.poly")
    m = voroclip.mesh2d(poly, vertices=400)
    # Markers of tagged_square.poly: bottom halves 5 and 7, other outer sides 3, hole 9;
    # regional attribute 42.
    assert set(m.boundary_tags.tolist()) == {3, 5, 7, 9}
    assert set(m.cell_tags.tolist()) == {42}
    assert m.boundary_edges.shape == (len(m.boundary_tags), 2)
    # Boundary edges = the triangles' edges used once.
    e = np.sort(np.concatenate([m.cells[:, [0, 1]], m.cells[:, [1, 2]], m.cells[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(e, axis=0, return_counts=True)
    assert {tuple(x) for x in uniq[count == 1]} == {tuple(sorted(x)) for x in m.boundary_edges.tolist()}
    lengths = {}
    for (i, j), t in zip(m.boundary_edges.tolist(), m.boundary_tags.tolist()):
        lengths[t] = lengths.get(t, 0) + float(np.hypot(*(m.points[i] - m.points[j])))
    for t, total in {5: 2, 7: 2, 3: 12, 9: 8}.items():
        assert lengths[t] == pytest.approx(total, rel=1e-12)
    for ext, fmt, key in ((".msh", "gmsh", "gmsh:physical"), (".mesh", None, "medit:ref")):
        f = tmp_path / ("tagged" + ext)
        m.write(f)
        back = meshio.read(f, file_format=fmt)
        lines = np.concatenate([d for c, d in zip(back.cells, back.cell_data[key]) if c.type == "line"])
        tris = np.concatenate([d for c, d in zip(back.cells, back.cell_data[key]) if c.type == "triangle"])
        assert set(lines.tolist()) == {3, 5, 7, 9}
        assert set(tris.tolist()) == {42}


def test_mesh2d_mean_angle_raise_and_exact_vertices():
    # A target the domain misses at 300 vertices: by default meshed again with more
    # vertices (one run here), the callback told first; exact_vertices keeps the count and
    # the note says what is missed.
    ring = [[(0, 0), (2, 0), (2, 1), (0, 1)], [(0.5, 0.4), (0.5, 0.6), (0.7, 0.6), (0.7, 0.4)]]
    kept = voroclip.mesh2d(ring, vertices=300, exact_vertices=True, mean_angle_target=59)
    assert kept.stats["mean_angle_runs"] == 0 and kept.stats["mean_angle_raise"] is None
    assert kept.stats["mean_angle_note"].startswith("mean smallest angle ")
    assert abs(len(kept.points) - 300) <= 30
    retries = []

    def watch(info):
        if "retry_vertices" in info:
            retries.append(info["retry_vertices"])

    raised = voroclip.mesh2d(ring, vertices=300, mean_angle_target=59, max_mean_angle_runs=1,
                             callback=watch)
    assert len(retries) == 1 and retries[0] >= 1.2 * len(kept.points)
    s = raised.stats
    assert s["mean_angle_runs"] == 1 and s["requested_vertices"] == 300
    assert s["mean_angle_raise"].startswith("the mean smallest angle was ")
    assert "meshed again with %d vertices" % len(raised.points) in s["mean_angle_raise"]
    assert s["mean_angle_raise"].endswith("kept the best")
    assert len(raised.points) > 1.1 * 300
    assert s["vertex_count_note"].startswith("%d vertices for 300 asked" % len(raised.points))
    with pytest.raises(voroclip.Error, match="mean angle target"):
        voroclip.mesh2d(ring, vertices=300, mean_angle_target=60)


def test_mesh3d_meshes_each_body_on_its_own():
    # Two unit boxes 0.01 apart along x: each body meshed with its share of the vertices,
    # no tet across the gap, the region tag its box's (in shell order).
    cube_v = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    cube_t = np.array([
        (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
        (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])
    vertices = np.vstack([cube_v, cube_v + [1.01, 0, 0]])
    triangles = np.vstack([cube_t, cube_t + 8])
    starts = []

    def callback(info):
        if "body_vertices" in info:
            starts.append((info["body"], info["nb_bodies"], info["body_vertices"]))

    mesh = voroclip.mesh3d((vertices, triangles), 400, callback=callback, threads=2,
                           unconstrained_iterations=8, constrained_iterations=12)
    assert starts == [(1, 2, 200), (2, 2, 200)]
    assert mesh.stats["bodies"] == 2
    assert mesh.shape_problem == ""
    x = mesh.points[mesh.cells][:, :, 0]
    right = (x > 1.005).all(axis=1)
    assert ((x > 1.005).any(axis=1) == right).all()  # no tet across the gap
    assert (mesh.cell_tags == np.where(right, 2, 1)).all()
    assert sorted(set(mesh.boundary_tags.tolist())) == list(range(1, 13))


def test_regression_mesh3d_stats_list_the_embedded_surfaces_not_followed(tmp_path):
    # A "sensor" surface inside a one-region tet mesh was dropped without a word. Here the
    # unit cube as six Kuhn tets, region 1, its inner triangle (1, 2, 8) tagged 9 (Medit,
    # from 1), between two tets of region 1.
    corners = "".join(f"{v & 1} {v >> 1 & 1} {v >> 2 & 1} 0\n" for v in range(8))
    tets = ["1 2 4 8", "1 3 4 8", "1 2 6 8", "1 3 7 8", "1 5 6 8", "1 5 7 8"]
    path = tmp_path / "sensor.mesh"
    path.write_text("MeshVersionFormatted 2\nDimension 3\nVertices\n8\n" + corners +
                    "Triangles\n1\n1 2 8 9\nTetrahedra\n6\n" +
                    "".join(t + " 1\n" for t in tets) + "End\n")
    mesh = voroclip.mesh3d(str(path), vertices=200, threads=2)
    assert mesh.stats["embedded_tags_not_followed"] == [{"tag": 9, "name": "", "triangles": 1}]
    assert 9 not in mesh.boundary_tags.tolist()
    plain = voroclip.mesh3d((CUBE_V, CUBE_T), 200, threads=2)
    assert plain.stats["embedded_tags_not_followed"] == []


def test_regression_mesh2d_vertices_and_edge_length_together_raise():
    # mesh2d(vertices=100, edge_length=0.01) meshed at 100 vertices (108) and dropped the
    # edge length without a word; the CLI refuses both ("give exactly one of --vertices N
    # and --edge-length H"), and so does Python now.
    with pytest.raises(voroclip.Error, match=r"^mesh2d: give exactly one of vertices and "
                                             r"edge_length, got vertices=100 and "
                                             r"edge_length=0\.01$"):
        voroclip.mesh2d(SQUARE, vertices=100, edge_length=0.01)
    with pytest.raises(voroclip.Error, match="give a number of vertices or a positive edge"):
        voroclip.mesh2d(SQUARE)
    by_length = voroclip.mesh2d(SQUARE, edge_length=0.2, threads=1)
    assert by_length.stats["edge_length"] == 0.2


def test_mesh3d_max_topology_sites_and_capped_stats():
    # Mesh3Options::max_topology_sites (the topology phase adds at most this many times the
    # vertices) and Mesh3Result::topology_capped / topology_capped_near reach Python. A
    # 1 x 1 x 0.1 slab at 100 vertices needs 45 topology sites (4 rounds): a cap of 0 stops
    # the rounds at once, with the defects of round 0 left; a cap of 0.5 (50 sites) does not.
    slab = (CUBE_V * (1, 1, 0.1), CUBE_T)
    free = voroclip.mesh3d(slab, vertices=100, threads=1)
    assert free.stats["topology_capped"] is False and free.stats["topology_capped_near"] is None
    assert free.stats["topology_defects_left"] == 0
    assert 0 < free.stats["topology_sites"] <= 50
    roomy = voroclip.mesh3d(slab, vertices=100, max_topology_sites=0.5, threads=1)
    assert roomy.stats["topology_capped"] is False
    assert np.array_equal(roomy.points, free.points) and np.array_equal(roomy.cells, free.cells)
    capped = voroclip.mesh3d(slab, vertices=100, max_topology_sites=0, threads=1)
    s = capped.stats
    assert s["topology_capped"] is True
    assert s["topology_sites"] == 0 and s["topology_defects_left"] > 0
    x, y, z = s["topology_capped_near"]
    assert 0 <= x <= 1 and 0 <= y <= 1 and 0 <= z <= 0.1
    with pytest.raises(voroclip.Error, match="a part far thinner than the spacing"):
        voroclip.mesh3d(slab, vertices=100, max_topology_sites=0, exact_vertices=True)
    with pytest.raises(voroclip.Error, match="option 'max_topology_sites': a value of the wrong"):
        voroclip.mesh3d(slab, vertices=100, max_topology_sites="four")


def test_regression_write_msh_version_3d_is_honoured_and_checked(cli, tmp_path):
    # mesh3d's write() ignored msh_version (always 4.1) and took any value; the CLI's
    # `mesh3d --msh-version 2.2` writes 2.2. Now the same bytes as the CLI's, both versions.
    import meshio

    obj = tmp_path / "cube.obj"
    obj.write_text("".join("v %g %g %g\n" % tuple(p) for p in CUBE_V) +
                   "".join("f %d %d %d\n" % tuple(t + 1) for t in CUBE_T))
    m = voroclip.mesh3d(obj, vertices=300)
    for version, flags in (("2.2", ["--msh-version", "2.2"]), ("4.1", [])):
        ours, theirs = tmp_path / f"py{version}.msh", tmp_path / f"cli{version}.msh"
        m.write(ours, msh_version=version)
        subprocess.run([cli, "mesh3d", str(obj), "--vertices", "300", *flags, "-o", str(theirs),
                        "-q"], check=True)
        assert ours.read_text().startswith(f"$MeshFormat\n{version} 0 8\n")
        assert ours.read_bytes() == theirs.read_bytes(), version
        back = meshio.read(ours, file_format="gmsh")
        assert np.array_equal(back.points, m.points)
        assert np.array_equal(back.cells_dict["tetra"], m.cells)
        assert np.array_equal(back.cell_data_dict["gmsh:physical"]["tetra"], m.cell_tags)
    for mesh in (m, voroclip.mesh2d(SQUARE, vertices=50)):
        for bad in ("9.9", "4", 4.1, None):
            with pytest.raises(voroclip.Error, match="msh_version: expected '4.1' or '2.2'"):
                mesh.write(tmp_path / "bad.msh", msh_version=bad)
        with pytest.raises(voroclip.Error, match="only a .msh file"):
            mesh.write(tmp_path / "bad.vtu", msh_version="2.2")
    with pytest.raises(voroclip.Error, match="binary=True: Gmsh 2.2"):
        m.write(tmp_path / "bad.msh", msh_version="2.2", binary=True)
    assert not (tmp_path / "bad.msh").exists() and not (tmp_path / "bad.vtu").exists()


def gmsh_physical_groups(path):
    """{(dim, tag): (name, element count)} of a .msh file as the gmsh module reads it."""
    import gmsh

    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.open(str(path))
        out = {}
        for dim, tag in gmsh.model.getPhysicalGroups():
            count = 0
            for e in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                _, elements, _ = gmsh.model.mesh.getElements(dim, int(e))
                count += sum(len(x) for x in elements)
            out[(dim, tag)] = (gmsh.model.getPhysicalName(dim, tag), count)
        return out
    finally:
        gmsh.finalize()


def check_to_meshio_writes_gmsh(m, names, blocks, tmp_path):
    """to_meshio() of m: the tag names in field_data as meshio's Gmsh reader gives them
    (names: {name: [tag, dim]}), and a file meshio writes as Gmsh 4.1 and 2.2 that meshio and
    gmsh read back with the same physical groups, names and elements. blocks: [(meshio type,
    dim, cells, tags)]."""
    import meshio

    mm = m.to_meshio()
    assert {k: v.tolist() for k, v in mm.field_data.items()} == names

    def by_coordinates(points, cells):  # meshio's Gmsh writer renumbers the points
        return [tuple(sorted(map(tuple, points[c].tolist()))) for c in cells]

    expected = {}  # (dim, tag) -> sorted cells, each by its vertices' coordinates
    for kind, dim, cells, tags in blocks:
        for t in np.unique(tags):
            expected[(dim, int(t))] = sorted(by_coordinates(mm.points, cells[tags == t]))
    names_of = {(dim, tag): name for name, (tag, dim) in names.items()}
    assert set(names_of) == set(expected)
    for fmt in ("gmsh", "gmsh22"):
        f = tmp_path / f"via_meshio_{fmt}_{m.dim}d.msh"
        meshio.write(f, mm, file_format=fmt, binary=False)
        back = meshio.read(f, file_format="gmsh")
        assert {k: v.tolist() for k, v in back.field_data.items()} == names
        assert len(back.points) == len(mm.points)
        got = {}
        for block, phys in zip(back.cells, back.cell_data["gmsh:physical"]):
            dim = {"tetra": 3, "triangle": 2, "line": 1}[block.type]
            for t in np.unique(phys):
                got.setdefault((dim, int(t)), []).extend(
                    by_coordinates(back.points, block.data[phys == t]))
        assert {k: sorted(v) for k, v in got.items()} == expected
        groups = gmsh_physical_groups(f)
        assert groups == {k: (names_of[k], len(v)) for k, v in expected.items()}


def test_regression_to_meshio_2d_names_and_gmsh_writing(tmp_path):
    # to_meshio() gave no field_data and no gmsh:dim_tags: meshio could not write it as Gmsh
    # ("Specify entity information"), and the names of the library's Gmsh files were lost.
    ring = [[(0, 0), (2, 0), (2, 1), (0, 1)], [(0.5, 0.4), (0.5, 0.6), (0.7, 0.6), (0.7, 0.4)]]
    m = voroclip.mesh2d(ring, vertices=200)
    assert set(m.boundary_tags.tolist()) == {1, 2}
    # The names of the library's 2D Gmsh writer.
    names = {"boundary 1": [1, 1], "boundary 2": [2, 1], "region 1": [1, 2]}
    check_to_meshio_writes_gmsh(m, names, [("triangle", 2, m.cells, m.cell_tags),
                                    ("line", 1, m.boundary_edges, m.boundary_tags)], tmp_path)
    mm = m.to_meshio()
    assert mm.field_data["boundary 2"].tolist() == [2, 1]
    assert mm.field_data["region 1"].tolist() == [1, 2]
    # The library's own Gmsh file has the same names.
    import meshio

    m.write(tmp_path / "lib.msh")
    lib = meshio.read(tmp_path / "lib.msh", file_format="gmsh")
    assert {k: v.tolist() for k, v in lib.field_data.items()} == \
        {k: v.tolist() for k, v in mm.field_data.items()}


def test_regression_to_meshio_3d_names_and_gmsh_writing(tmp_path):
    # to_meshio() of a mesh with tag_names gave field_data == {}.
    import meshio

    # Two unit cubes side by side, regions 1 and 2, six Kuhn tets each (a meshio.Mesh domain).
    pts = np.array([(x, y, z) for x in range(3) for y in range(2) for z in range(2)], float)
    index = {tuple(p): i for i, p in enumerate(pts.astype(int).tolist())}
    tets, regions = [], []
    for x0, ref in ((0, 1), (1, 2)):
        c = [index[(x0 + (k & 1), (k >> 1) & 1, (k >> 2) & 1)] for k in range(8)]
        for a, b in ((1, 2), (1, 4), (2, 1), (2, 4), (4, 1), (4, 2)):
            tets.append((c[0], c[a], c[a + b], c[7]))
            regions.append(ref)
    domain = meshio.Mesh(pts, [("tetra", np.array(tets))],
                         cell_data={"gmsh:physical": [np.array(regions)]})
    m = voroclip.mesh3d(domain, vertices=300)
    assert m.stats["region_interfaces_followed"] == 1
    names = {name for _, _, name in m.tag_names}
    assert {"region 1", "region 2"} <= names and any(n.startswith("interface") for n in names)
    triangles = np.vstack([m.boundary_triangles, m.interface_triangles])
    tags = np.concatenate([m.boundary_tags, m.interface_tags])
    names = {name: [tag, dim] for dim, tag, name in m.tag_names}
    check_to_meshio_writes_gmsh(m, names, [("tetra", 3, m.cells, m.cell_tags),
                                    ("triangle", 2, triangles, tags)], tmp_path)
    # Named as in tag_names, and as the library's own Gmsh file names them.
    mm = m.to_meshio()
    m.write(tmp_path / "lib.msh")
    lib = meshio.read(tmp_path / "lib.msh", file_format="gmsh")
    assert {k: v.tolist() for k, v in lib.field_data.items()} == \
        {k: v.tolist() for k, v in mm.field_data.items()}
    # Medit tags: one block per type, in the mesh's order.
    med = m.to_meshio("medit")
    assert np.array_equal(med.cells_dict["tetra"], m.cells)
    assert np.array_equal(med.cell_data_dict["medit:ref"]["triangle"], tags)


def test_regression_density_callable_on_two_threads_does_not_deadlock(data):
    # PyDensity took the GIL, then a mutex; while one worker ran the callable (holding the
    # mutex) the interpreter handed the GIL to another, which then waited for the mutex: a
    # hang at 0 % CPU that Ctrl-C could not stop (2 runs of 2 hung with the switch interval
    # below). A liveness check in a child process: the timeout is a hang's, not a speed's.
    child = (
        "import sys, warnings, voroclip\n"
        "sys.setswitchinterval(1e-6)\n"
        "warnings.simplefilter('ignore')\n"
        "d = voroclip.domain3(sys.argv[1])\n"
        "s = voroclip.random_points(d, 100, seed=1)\n"
        "r = voroclip.cvt3d(d, s, iterations=3, density=lambda x, y, z: 1.0 + x * x, threads=2)\n"
        "c = voroclip.clip2d([(0, 0), (1, 0), (1, 1), (0, 1)], [(0.2, 0.3), (0.7, 0.6)],\n"
        "                    density=lambda x, y: 1.0 + y, threads=2)\n"
        "print(r.iterations, round(c.total_mass, 12))\n")
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(voroclip.__file__)))
    for _ in range(3):
        out = subprocess.run([sys.executable, "-c", child, str(data / "tetmeshes" / "sphere.mesh")],
                             capture_output=True, text=True, timeout=300, env=env)
        assert out.returncode == 0, out.stderr
        assert out.stdout.split() == ["3", "1.5"]


@pytest.mark.parametrize("option, value, name", [
    ("sliver_angle", float("nan"), "sliver angle"), ("sliver_angle", 80.0, "sliver angle"),
    ("sliver_angle", -1.0, "sliver angle"), ("lfs_cap", -1.0, "lfs_cap"),
    ("lfs_cap", float("nan"), "lfs_cap"), ("gradient_tolerance", float("nan"), "gradient_tolerance"),
    ("gradient_tolerance", -1e-4, "gradient_tolerance"),
    ("min_feature_length", float("nan"), "min_feature_length")])
def test_regression_mesh3d_refuses_options_the_cli_refuses(option, value, name):
    # They were taken (sliver_angle=nan even changed the mesh); the CLI refuses its
    # equivalents as usage errors. Now the library refuses them before any work.
    with pytest.raises(voroclip.Error, match="^mesh3d: " + name):
        voroclip.mesh3d((CUBE_V, CUBE_T), vertices=300, **{option: value})


def test_regression_meshio_domain_keeps_names_and_the_readers_tag_order():
    # A meshio.Mesh domain lost field_data's names ('region 7', not 'steel') and took
    # gmsh:physical before region (the file readers take region first, README).
    import meshio

    tets = np.array([(0, 1, 3, 7), (0, 1, 7, 5), (0, 5, 7, 4), (0, 3, 2, 7), (0, 2, 6, 7),
                     (0, 6, 4, 7)])
    x = CUBE_V[tets]
    det = np.einsum("ij,ij->i", np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), x[:, 3] - x[:, 0])
    tets[det < 0] = tets[det < 0][:, [0, 2, 1, 3]]
    tris = np.array(CUBE_T)
    mesh = meshio.Mesh(CUBE_V, [("tetra", tets), ("triangle", tris)],
                       cell_data={"gmsh:physical": [np.full(6, 3), np.full(12, 4)],
                                  "region": [np.full(6, 7), np.zeros(12, dtype=int)],
                                  "patch": [np.zeros(6, dtype=int), np.full(12, 5)]},
                       field_data={"steel": np.array([7, 3]), "skin": np.array([5, 2]),
                                   "point": np.array([1, 0])})
    m = voroclip.mesh3d(mesh, vertices=200, threads=1)
    assert set(m.cell_tags.tolist()) == {7}
    assert set(m.boundary_tags.tolist()) == {5}
    assert (3, 7, "steel") in m.tag_names and (2, 5, "skin") in m.tag_names


def test_mesh3d_density_and_sizing_as_the_cli(data, cli, tmp_path):
    # Python's mesh3d had no density or sizing. Callables give the CLI's --density /
    # --sizing meshes byte for byte (the same values: the formulas are exact in both).
    sphere = str(data / "surfaces" / "sphere.obj")
    for flags, kwargs in ((["--vertices", "80", "--density", "1+x*x"],
                           dict(vertices=80, density=lambda x, y, z: 1 + x * x)),
                          (["--sizing", "0.5"], dict(sizing=lambda x, y, z: 0.5))):
        theirs, mine = tmp_path / "cli.mesh", tmp_path / "py.mesh"
        subprocess.run([cli, "-q", "mesh3d", sphere, *flags, "-o", str(theirs)], check=True)
        voroclip.mesh3d(sphere, threads=1, **kwargs).write(mine)
        assert mine.read_bytes() == theirs.read_bytes(), flags
    # A number: a uniform size (h the edge length without vertices; no effect with them).
    assert len(voroclip.mesh3d(sphere, sizing=0.5).points) == 63
    with pytest.raises(voroclip.Error, match=r"^sizing: the callable returned -1\.0 at \("):
        voroclip.mesh3d(sphere, 100, sizing=lambda x, y, z: -1.0)
    with pytest.raises(voroclip.Error, match="density and sizing exclude each other"):
        voroclip.mesh3d(sphere, 100, density=2.0, sizing=0.1)
    with pytest.raises(voroclip.Error, match="sizing: expected a finite number > 0"):
        voroclip.mesh3d(sphere, sizing=0.0)
