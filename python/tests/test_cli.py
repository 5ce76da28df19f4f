"""Python and the command-line tool agree to the bit on the same inputs: clip2d, clip3d,
mesh2d and mesh3d, compared through --stats json and the tool's output files (JSON with
round-trip doubles, ASCII .vtu with 17 significant digits)."""

import json
import subprocess

import meshio
import numpy as np
import pytest

import voroclip


def run(cli, *args):
    out = subprocess.run([cli, *map(str, args), "--stats", "json", "-q"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def write_sites(path, sites):
    path.write_text("".join(" ".join(repr(float(x)) for x in p) + "\n" for p in sites))


def test_clip2d_agrees_with_cli(cli, data, tmp_path, outside):
    domain = sorted((data / "polygons" / "valid").glob("*.json"))[0]
    d = voroclip.domain2(domain)
    lo, hi = np.array(d.bounds[:2]), np.array(d.bounds[2:])
    sites = lo + np.random.default_rng(10).random((2000, 2)) * (hi - lo)
    write_sites(tmp_path / "s.txt", sites)
    stats = run(cli, "clip2d", domain, "--sites", tmp_path / "s.txt", "-o", tmp_path / "c.json")
    cells = outside(voroclip.clip2d, domain, sites, expected=outside.count2d(d, sites))
    assert stats["cells_area_sum"] == cells.total_measure
    assert stats["energy"] == cells.total_energy
    assert stats["boundary_sites"] == cells.nb_boundary
    ref = json.loads((tmp_path / "c.json").read_text())["cells"]
    assert [c["area"] for c in ref] == cells.areas.tolist()
    assert [c["energy"] for c in ref] == cells.energies.tolist()
    assert [c["centroid"] for c in ref] == cells.centroids.tolist()
    assert [c["boundary"] for c in ref] == cells.boundary.tolist()


def test_clip3d_agrees_with_cli(cli, data, tmp_path, outside):
    domain = data / "surfaces" / "bunny.obj"
    d = voroclip.domain3(domain)
    lo, hi = np.array(d.bounds[:3]), np.array(d.bounds[3:])
    sites = lo + np.random.default_rng(11).random((5000, 3)) * (hi - lo)
    write_sites(tmp_path / "s.txt", sites)
    stats = run(cli, "clip3d", domain, "--sites", tmp_path / "s.txt", "-o", tmp_path / "c.json")
    cells = outside(voroclip.clip3d, d, sites)
    assert stats["cells_volume_sum"] == cells.total_measure
    assert stats["surface_area_sum"] == cells.total_surface_area
    assert stats["boundary_sites"] == cells.nb_boundary
    ref = json.loads((tmp_path / "c.json").read_text())["cells"]
    assert [c["volume"] for c in ref] == cells.volumes.tolist()
    assert [c["energy"] for c in ref] == cells.energies.tolist()
    assert [c["centroid"] for c in ref] == cells.centroids.tolist()


def test_clip3d_vtu_polygons_face_out_of_their_cells(cli, data, tmp_path):
    # Each cell's polygons, shrunk by 0.9 towards its centroid, enclose 0.729 times its
    # volume with the sign of their orientation (divergence theorem): + when they face out.
    domain = data / "surfaces" / "bunny.obj"
    stats = run(cli, "clip3d", domain, "--random", 300, "-o", tmp_path / "c.vtu")
    run(cli, "clip3d", domain, "--random", 300, "-o", tmp_path / "c.json")
    volumes = np.array([c["volume"] for c in
                        json.loads((tmp_path / "c.json").read_text())["cells"]])
    m = meshio.read(tmp_path / "c.vtu")
    site = np.concatenate(m.cell_data["site_id"])
    enclosed = np.zeros(len(volumes))
    k = 0
    for block in m.cells:
        for poly in block.data:
            p = m.points[poly]
            enclosed[site[k]] += sum(np.dot(p[0], np.cross(p[j], p[j + 1]))
                                     for j in range(1, len(p) - 1)) / 6
            k += 1
    assert stats["sites"] == len(volumes)
    np.testing.assert_allclose(enclosed, 0.729 * volumes, rtol=1e-9, atol=1e-12)


def test_random_points_2d_are_the_clis_random_sites(cli, data, tmp_path):
    # The CLI's start sites (cvt2d --iterations 0), uniform and with a density: cvt2d draws
    # with rho^(1/2), so --density (1+10*x)^2 draws with 1 + 10x (sqrt(v*v) == v exactly).
    domain = data / "polygons" / "valid" / "dude.json"
    for extra, density in (([], None), (["--density", "(1+10*x)^2"], lambda x, y: 1 + 10 * x)):
        out = tmp_path / "s.txt"
        run(cli, "cvt2d", domain, "--random", 500, "--seed", 3, "--iterations", 0, "-o", out,
            *extra)
        cli_sites = np.loadtxt(out)
        points = voroclip.random_points(domain, 500, seed=3, density=density)
        assert points.shape == (500, 2)
        assert np.array_equal(points, cli_sites)
        assert (voroclip.domain2(domain).locate(points) == 1).all()
    # rho = 1 + 10x pulls the points to larger x.
    d = voroclip.domain2(domain)
    assert (voroclip.random_points(d, 2000, density=lambda x, y: 1 + 10 * x)[:, 0].mean()
            > voroclip.random_points(d, 2000)[:, 0].mean())


def test_mesh2d_agrees_with_cli(cli, tmp_path):
    import meshio

    domain = tmp_path / "d.json"
    domain.write_text("[[[0,0],[3,0],[3,2],[0,2]],[[1,0.5],[1,1.5],[2,1.5],[2,0.5]]]")
    stats = run(cli, "mesh2d", domain, "--vertices", 400, "-o", tmp_path / "m.vtu")
    m = voroclip.mesh2d(domain, vertices=400)
    back = meshio.read(tmp_path / "m.vtu")
    assert np.array_equal(back.points[:, :2], m.points)
    assert np.array_equal(back.cells_dict["triangle"], m.cells)
    assert stats["vertices"] == len(m.points) and stats["triangles"] == len(m.cells)
    assert stats["relative_gradient"] == m.stats["relative_gradient"]
    for key in ("feature_vertices", "refined_vertices", "smoothed_vertices", "vertex_count_note",
                "flips", "mean_angle_note"):
        assert stats[key] == m.stats[key], key
    # The mean smallest angle reaches 53 degrees here: no note.
    assert stats["quality"]["mean_min_angle_deg"] >= 53 and stats["mean_angle_note"] is None


def test_mesh3d_agrees_with_cli(cli, data, tmp_path):
    import meshio

    domain = data / "surfaces" / "sphere.obj"
    stats = run(cli, "mesh3d", domain, "--vertices", 400, "-o", tmp_path / "m.vtu")
    m = voroclip.mesh3d(domain, vertices=400)
    back = meshio.read(tmp_path / "m.vtu")
    assert np.array_equal(back.points, m.points)
    assert np.array_equal(back.cells_dict["tetra"], m.cells)
    assert np.array_equal(back.cells_dict["triangle"], m.boundary_triangles)
    assert stats["vertices"] == len(m.points)
    # The dihedral verdict, as the CLI gives it.
    bound = stats["dihedral_bound"]
    assert m.stats["dihedral_bound_deg"] == bound["bound_deg"] == 20
    assert m.stats["input_sharpest_dihedral_deg"] == bound["input_sharpest_dihedral_deg"]
    q1 = voroclip.quality(m.points, m.cells).q1
    assert m.stats["tets_below_dihedral_bound"] == bound["tets_below"] == int((q1 < 20).sum())
    # The distance check: the boundary's Hausdorff distance to the input, as the CLI reports
    # it, over the uniform edge length cbrt(1.9 V / N), V the volume the input's triangles
    # enclose (divergence theorem).
    assert m.stats["hausdorff"] == stats["hausdorff"]
    assert m.stats["hausdorff_to_edge_length"] == stats["hausdorff_to_edge_length"]
    xyz, tri = [], []
    for line in open(domain):
        f = line.split()
        if f and f[0] == "v":
            xyz.append([float(x) for x in f[1:4]])
        elif f and f[0] == "f":
            tri.append([int(x.split("/")[0]) - 1 for x in f[1:4]])
    a, b, c = (np.array(xyz)[np.array(tri)[:, k]] for k in range(3))
    volume = abs(np.einsum("ij,ij->i", a, np.cross(b, c)).sum()) / 6
    edge = (1.9 * volume / 400) ** (1 / 3)
    assert m.stats["hausdorff_to_edge_length"] == pytest.approx(stats["hausdorff"] / edge, 1e-9)
    assert 0 < m.stats["hausdorff_to_edge_length"] <= 1


def kuhn_cubes(path, cubes):
    """A Medit file of unit cubes (x0, y0, z0, ref), six Kuhn tets each."""
    pts = sorted({(x0 + (k & 1), y0 + ((k >> 1) & 1), z0 + ((k >> 2) & 1))
                  for x0, y0, z0, _ in cubes for k in range(8)})
    index = {p: i + 1 for i, p in enumerate(pts)}
    lines = ["MeshVersionFormatted 2", "Dimension 3", "Vertices", str(len(pts))]
    lines += ["%g %g %g 0" % p for p in pts]
    tets = []
    for x0, y0, z0, ref in cubes:
        c = [index[(x0 + (k & 1), y0 + ((k >> 1) & 1), z0 + ((k >> 2) & 1))] for k in range(8)]
        for a, b in ((1, 2), (1, 4), (2, 1), (2, 4), (4, 1), (4, 2)):
            tets.append("%d %d %d %d %d" % (c[0], c[a], c[a + b], c[7], ref))
    lines += ["Tetrahedra", str(len(tets))] + tets + ["End"]
    path.write_text("\n".join(lines) + "\n")


def test_mesh3d_follows_the_interface_between_two_cubes(cli, tmp_path):
    # Two unit cubes side by side, regions 1 (x <= 1) and 2 (x >= 1): the interface meets the
    # boundary along the square's four sides.
    domain = tmp_path / "two.mesh"
    kuhn_cubes(domain, [(0, 0, 0, 1), (1, 0, 0, 2)])
    stats = run(cli, "mesh3d", domain, "--vertices", 300, "-o", tmp_path / "m.mesh")
    m = voroclip.mesh3d(domain, vertices=300)
    x = m.points[m.cells][:, :, 0]
    tags = np.asarray(m.cell_tags)
    # No tet of region 1 with a vertex at x > 1, nor of region 2 with one at x < 1 (vertices
    # on the interface are projected onto it: 1e-12).
    eps = 1e-12
    assert not (((tags == 1) & (x.max(1) > 1 + eps)) | ((tags == 2) & (x.min(1) < 1 - eps))).any()
    regions = stats["regions"]
    assert 0 <= regions.pop("interface_distance_to_edge_length") <= 1
    assert regions == {"input_regions": 2, "tets_across_interfaces": 0,
                       "interfaces_followed": 1, "interfaces_not_followed": ""}
    assert m.stats["region_interfaces_followed"] == 1
    assert m.stats["tets_across_region_interfaces"] == 0
    assert set(m.interface_tags.tolist()) == {int(m.boundary_tags.max()) + 1}


def test_mesh3d_counts_tets_across_regions_it_cannot_follow(cli, tmp_path):
    # Region 2: two cubes that share an edge only, so it is no volume of its own.
    domain = tmp_path / "edge.mesh"
    kuhn_cubes(domain, [(0, 0, 0, 2), (1, 0, 0, 1), (0, 1, 0, 1), (1, 1, 0, 2)])
    stats = run(cli, "mesh3d", domain, "--vertices", 300, "-o", tmp_path / "m.mesh")
    m = voroclip.mesh3d(domain, vertices=300)
    p = m.points[m.cells]
    tags = np.asarray(m.cell_tags)
    # A tet with a vertex strictly inside a cube of the other region.
    def inside(lo, hi):
        return ((p[:, :, 0] > lo[0]) & (p[:, :, 0] < hi[0]) & (p[:, :, 1] > lo[1])
                & (p[:, :, 1] < hi[1])).any(axis=1)
    in2 = inside((0, 0), (1, 1)) | inside((1, 1), (2, 2))
    in1 = inside((1, 0), (2, 1)) | inside((0, 1), (1, 2))
    across = int((((tags == 1) & in2) | ((tags == 2) & in1)).sum())
    assert across > 0
    why = stats["regions"]["interfaces_not_followed"]
    assert "meet along an edge only" in why
    assert stats["regions"]["interfaces_followed"] == 0
    assert stats["regions"]["tets_across_interfaces"] == m.stats["tets_across_region_interfaces"]
    assert stats["regions"]["tets_across_interfaces"] >= across
    assert m.stats["region_interfaces_not_followed"] == why


def test_mesh3d_follows_the_interface_around_an_inclusion(cli, tmp_path):
    # The unit cube as 6^3 voxels of six Kuhn tets, the middle 2^3 voxels (the box
    # [1/3, 2/3]^3) region 2, the rest region 1: the interface is a closed surface inside.
    n = 6
    index = {}
    pts = []
    tets = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                ref = 2 if all(2 <= c < 4 for c in (i, j, k)) else 1
                for axes in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
                    c = [i, j, k]
                    path = [tuple(c)]
                    for a in axes:
                        c[a] += 1
                        path.append(tuple(c))
                    for p in path:
                        if p not in index:
                            index[p] = len(pts) + 1
                            pts.append(p)
                    tets.append("%d %d %d %d %d" % (*(index[p] for p in path), ref))
    lines = ["MeshVersionFormatted 2", "Dimension 3", "Vertices", str(len(pts))]
    lines += ["%r %r %r 0" % tuple(c / n for c in p) for p in pts]
    lines += ["Tetrahedra", str(len(tets))] + tets + ["End"]
    domain = tmp_path / "inclusion.mesh"
    domain.write_text("\n".join(lines) + "\n")
    out = tmp_path / "m.msh"
    stats = run(cli, "mesh3d", domain, "--vertices", 1500, "-o", out)
    regions = stats["regions"]
    assert 0 < regions.pop("interface_distance_to_edge_length") <= 1
    assert regions == {"input_regions": 2, "tets_across_interfaces": 0,
                       "interfaces_followed": 1, "interfaces_not_followed": ""}
    assert stats["shape_problem"] == ""
    back = meshio.read(out, file_format="gmsh")
    p = back.points
    t = back.cells_dict["tetra"]
    tags = back.cell_data_dict["gmsh:physical"]["tetra"]
    assert set(tags.tolist()) == {1, 2}
    # The boundary's six patches (1 .. 6), then the interface (7), named.
    tri = back.cells_dict["triangle"]
    tri_tags = back.cell_data_dict["gmsh:physical"]["triangle"]
    assert set(tri_tags.tolist()) == {1, 2, 3, 4, 5, 6, 7}
    assert back.field_data["interface 1-2"].tolist() == [7, 2]
    assert stats["interface_triangles"] == int((tri_tags == 7).sum()) > 0
    # Every tet on its side of the box: region 2's vertices in the closed box, region 1's
    # outside the open one (vertices on the interface are projected onto it: 1e-12).
    lo, hi, eps = 1 / 3, 2 / 3, 1e-12
    inner = ((p > lo + eps) & (p < hi - eps)).all(axis=1)
    closed = ((p >= lo - eps) & (p <= hi + eps)).all(axis=1)
    assert closed[t[tags == 2]].all()
    assert not inner[t[tags == 1]].any()
    a, b, c, d = (p[t[:, k]] for k in range(4))
    vol = np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))) / 6
    assert vol.sum() == pytest.approx(1, rel=1e-9)
    assert vol[tags == 2].sum() == pytest.approx(1 / 27, rel=0.05)
    # The interface triangles: on the box's surface, and each a face of a tet of each region.
    it = tri[tri_tags == 7]
    assert closed[it].all() and not inner[it].any()
    faces = {}
    for k, cell in enumerate(t):
        for f in range(4):
            faces.setdefault(tuple(sorted(np.delete(cell, f))), set()).add(int(tags[k]))
    assert all(faces[tuple(sorted(x))] == {1, 2} for x in it)
    # Python: the same mesh, its interface triangles and their tag among the triangles.
    m = voroclip.mesh3d(domain, vertices=1500)
    assert m.stats["region_interfaces_followed"] == 1
    assert m.stats["region_interfaces_not_followed"] == ""
    assert len(m.points) == len(p) and len(m.cells) == len(t)
    assert m.interface_triangles.shape == (len(it), 3)
    assert set(m.interface_tags.tolist()) == {7}
    mm = m.to_meshio()
    assert len(mm.cells_dict["triangle"]) == len(m.boundary_triangles) + len(it)


def test_mesh3d_facet_distance_agrees_with_cli(cli, tmp_path):
    # A box without feature lines: the uniform spacing cuts its corners off, and
    # facet_distance fixes sites there, as the CLI's --facet-distance.
    box = tmp_path / "box.obj"
    v = [(2 * (k & 1), 3 * ((k >> 1) & 1), (k >> 2) & 1) for k in range(8)]
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    box.write_text("".join("v %d %d %d\n" % p for p in v) + "".join(
        "f %d %d %d\nf %d %d %d\n" % (a + 1, b + 1, c + 1, a + 1, c + 1, d + 1)
        for a, b, c, d in faces))
    stats = run(cli, "mesh3d", box, "--vertices", 400, "--no-features", "--facet-distance", 0.15,
                "-o", tmp_path / "m.vtu")
    m = voroclip.mesh3d(box, vertices=400, features=False, facet_distance=0.15)
    assert stats["facet_distance"]["sites"] == m.stats["distance_sites"] > 0
    assert stats["facet_distance"]["sites_added"] == m.stats["distance_sites_added"]
    assert stats["vertices"] == len(m.points)
    import meshio

    back = meshio.read(tmp_path / "m.vtu")
    assert np.array_equal(back.points, m.points)
    # The sites it fixed are box corners, bitwise (the box has no other vertices); without
    # the option no corner is a vertex.
    corners = [p for p in v if (m.points == np.array(p, dtype=float)).all(axis=1).any()]
    assert corners
    plain = voroclip.mesh3d(box, vertices=400, features=False)
    assert not any((plain.points == np.array(p, dtype=float)).all(axis=1).any() for p in v)


def test_mesh3d_flip_angle_agrees_with_cli(cli, data, tmp_path):
    # The last step (flips, moves, insertions against the tets below flip_angle) raises the
    # smallest dihedral angle and keeps the boundary; flip_angle=0 (--flip-angle 0) skips it.
    domain = data / "surfaces" / "fandisk.obj"
    off = run(cli, "mesh3d", domain, "--vertices", 1500, "--flip-angle", 0,
              "-o", tmp_path / "a.msh")
    on = run(cli, "mesh3d", domain, "--vertices", 1500, "-o", tmp_path / "b.msh")
    assert off["perturbation"]["flips"] == off["perturbation"]["flip_moves"] == 0
    assert on["perturbation"]["flips"] + on["perturbation"]["flip_moves"] > 0
    assert on["min_dihedral_deg"] > off["min_dihedral_deg"]
    assert 0 <= on["perturbation"]["boundary_flips"] <= on["perturbation"]["flips"]
    m = voroclip.mesh3d(domain, vertices=1500, flip_angle=0)
    assert m.stats["flips"] == m.stats["flip_moves"] == m.stats["flip_sites"] == 0
    assert m.stats["boundary_flips"] == 0
    assert len(m.cells) == off["tets"] and len(m.points) == off["vertices"]
    with pytest.raises(voroclip.Error, match="flip_dihedral_deg"):
        voroclip.mesh3d(domain, vertices=1500, flip_angle=80)


def test_mesh3d_mean_rounds_agrees_with_cli(cli, data, tmp_path):
    # Step 7d (flips and moves for the mean smallest dihedral angle) raises the mean and keeps
    # the smallest angle; mean_rounds=0 (--mean-rounds 0) skips it.
    domain = data / "surfaces" / "fandisk.obj"
    off = run(cli, "mesh3d", domain, "--vertices", 1500, "--mean-rounds", 0,
              "-o", tmp_path / "a.msh")
    on = run(cli, "mesh3d", domain, "--vertices", 1500, "-o", tmp_path / "b.msh")
    assert off["perturbation"]["mean_flips"] == off["perturbation"]["mean_moves"] == 0
    assert on["perturbation"]["mean_flips"] + on["perturbation"]["mean_moves"] > 0
    assert 1 <= on["perturbation"]["mean_rounds"] <= 3
    assert on["mean_min_dihedral_deg"] > off["mean_min_dihedral_deg"]
    assert on["perturbation"]["mean_q1_before_deg"] == pytest.approx(off["mean_min_dihedral_deg"])
    assert on["perturbation"]["mean_q1_after_deg"] == pytest.approx(on["mean_min_dihedral_deg"])
    assert on["min_dihedral_deg"] >= min(off["min_dihedral_deg"], 30) - 1e-9
    assert on["boundary_triangles"] == off["boundary_triangles"]
    m = voroclip.mesh3d(domain, vertices=1500, mean_rounds=0)
    assert m.stats["mean_flips"] == m.stats["mean_moves"] == m.stats["mean_rounds"] == 0
    assert len(m.cells) == off["tets"] and len(m.points) == off["vertices"]
    bad = subprocess.run([cli, "mesh3d", str(domain), "--vertices", "100", "--flip-angle", "-1"],
                         capture_output=True, text=True)
    assert bad.returncode != 0 and "--flip-angle" in bad.stderr


def test_random_sites_as_the_cli_draws_them(cli, data, tmp_path):
    domain = data / "surfaces" / "sphere.obj"
    stats = run(cli, "clip3d", domain, "--random", 3000, "--seed", 7, "-o", tmp_path / "c.json")
    sites = voroclip.random_points(domain, 3000, seed=7)
    d = voroclip.domain3(domain)
    assert (d.locate(sites) > 0).all()
    ref = json.loads((tmp_path / "c.json").read_text())["cells"]
    assert [c["site"] for c in ref] == sites.tolist()
    cells = voroclip.clip3d(d, sites)
    assert stats["cells_volume_sum"] == cells.total_measure


def test_mesh3d_files_are_the_cli_files_byte_for_byte(cli, data, tmp_path):
    """Mesh.write uses the library's writers: .msh (Gmsh 4.1, ASCII and binary), .mesh,
    TetGen and .vtu files (with the quality array) are the bytes `voroclip mesh3d -o` writes
    for the same mesh."""
    import meshio

    domain = data / "surfaces" / "sphere.obj"
    m = voroclip.mesh3d(domain, vertices=300)
    for name, flags, binary, compress in (
            ("m.msh", [], False, False), ("b.msh", ["--binary"], True, False),
            ("m.mesh", [], False, False), ("t.node", [], False, False),
            ("m.vtu", [], False, False), ("z.vtu", ["--compress"], False, True)):
        ours = tmp_path / ("py_" + name)
        theirs = tmp_path / ("cli_" + name)
        m.write(ours, binary=binary, compress=compress)
        run(cli, "mesh3d", domain, "--vertices", 300, *flags, "-o", theirs)
        assert ours.read_bytes() == theirs.read_bytes(), name
        if name.endswith(".node"):
            for ext in (".ele", ".face"):
                assert ours.with_suffix(ext).read_bytes() == theirs.with_suffix(ext).read_bytes()
    assert (tmp_path / "py_m.msh").read_text().startswith("$MeshFormat\n4.1 0 8\n")
    back = meshio.read(tmp_path / "py_m.msh", file_format="gmsh")
    assert np.array_equal(back.points, m.points)
    assert np.array_equal(back.cells_dict["tetra"], m.cells)
    with pytest.raises(voroclip.Error, match="binary"):
        m.write(tmp_path / "x.mesh", binary=True)


def test_mesh2d_files_are_the_cli_files_byte_for_byte(cli, tmp_path):
    domain = tmp_path / "d.json"
    domain.write_text("[[[0,0],[3,0],[3,2],[0,2]],[[1,0.5],[1,1.5],[2,1.5],[2,0.5]]]")
    m = voroclip.mesh2d(domain, vertices=300)
    for name, flags, version, options in (
            ("m.msh", [], "4.1", {}), ("v22.msh", ["--msh-version", "2.2"], "2.2", {}),
            ("m.mesh", [], "4.1", {}), ("m.vtu", [], "4.1", {}),
            ("b.vtu", ["--binary"], "4.1", {"binary": True}),
            ("z.vtu", ["--compress"], "4.1", {"compress": True})):
        ours, theirs = tmp_path / ("py_" + name), tmp_path / ("cli_" + name)
        m.write(ours, msh_version=version, **options)
        run(cli, "mesh2d", domain, "--vertices", 300, *flags, "-o", theirs)
        assert ours.read_bytes() == theirs.read_bytes(), name
    assert (tmp_path / "py_m.msh").read_text().startswith("$MeshFormat\n4.1 0 8\n")
    assert b'format="appended"' in (tmp_path / "py_b.vtu").read_bytes()
    assert b"vtkZLibDataCompressor" in (tmp_path / "py_z.vtu").read_bytes()
    with pytest.raises(voroclip.Error, match="binary and compress: .vtu only"):
        m.write(tmp_path / "x.mesh", compress=True)


def test_cli_failure_stats_parse(cli, tmp_path):
    # A failing command with --stats json prints one JSON object too (it printed nothing):
    # ok false and the error line that stderr shows.
    missing = tmp_path / "none.json"
    for args, status in [(["clip2d", missing, "--random", 10], 1),
                         (["mesh2d", "square-holes:2,0.4", "--vertices", "x"], 2)]:
        p = subprocess.run([cli, "--stats", "json", *map(str, args)], capture_output=True,
                           text=True)
        assert p.returncode == status
        stats = json.loads(p.stdout)
        assert stats["command"] == args[0] and stats["ok"] is False
        assert p.stderr == "voroclip: error: " + stats["error"] + "\n"
    ok = run(cli, "clip2d", "square-holes:2,0.4", "--random", 10)
    assert ok["command"] == "clip2d" and ok["ok"] is True
