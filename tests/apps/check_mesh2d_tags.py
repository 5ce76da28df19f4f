#!/usr/bin/python3
"""check_mesh2d_tags.py VOROCLIP DIR DATA: what `voroclip mesh2d` writes for a solver, read
back by meshio and Gmsh's Python module.

tagged_square.poly (next to this script) is the square [0, 4]^2 with the hole [1, 3]^2; its
bottom side is two segments with markers 5 (x in [0, 2]) and 7 (x in [2, 4]), its other
sides marker 3, the hole's sides 9, and a regional attribute 42. It is meshed with 400
vertices into .msh 4.1, .msh 2.2, .vtu and .mesh. For each file: the triangles' areas sum
to the domain's (12) to 1e-12; the boundary edges are the triangles' edges used once; each
boundary edge's tag is the marker of the side it lies on (by its coordinates), the edge
lengths per tag sum to the side lengths (5: 2, 7: 2, 3: 12, 9: 8); every triangle's tag is
42. Gmsh finds physical groups (1, 3/5/7/9) and (2, 42) with names "boundary N" and
"region 42". DATA/polygons/valid/issue34.json (one outer ring, seven holes, no markers):
boundary tags 1 on the outer ring and 2..8 on the holes, one per hole, region 1. A .poly
with segment marker 0 (no marker) on its outer ring: tag 1 there in .msh 4.1, 2.2 and .vtu,
every line in a Gmsh physical group. The .vtu written with --binary and with --compress
holds the ASCII one's points, cells and arrays exactly. Prints one
line per mismatch and exits with 1 when there is any.
"""

import os
import subprocess
import sys

import gmsh
import meshio
import numpy as np

failures = []


def check(what, ok, detail=""):
    if not ok:
        failures.append(what)
        print("FAILED:", what, detail)


def cells(mesh, kind, data_names):
    """Cells of a kind and their tag (the first cell-data array present)."""
    blocks, tags = [], []
    for i, block in enumerate(mesh.cells):
        if block.type != kind:
            continue
        blocks.append(block.data)
        for name in data_names:
            if name in mesh.cell_data:
                tags.append(np.asarray(mesh.cell_data[name][i]))
                break
    return np.concatenate(blocks), np.concatenate(tags)


def side_tag(p, q):
    """The marker of the side of tagged_square.poly holding the segment p-q."""
    if p[1] == 0 and q[1] == 0:
        return 5 if max(p[0], q[0]) <= 2 else 7
    if 1 <= min(p[0], q[0]) and max(p[0], q[0]) <= 3 and 1 <= min(p[1], q[1]) and max(p[1], q[1]) <= 3:
        return 9
    return 3


def check_file(path, data_names, line_names=None):
    """line_names: the boundary edges' tag array when not data_names' (.vtu: region on the
    triangles, patch on the edges, as mesh3d's .vtu; 0 on the other kind)."""
    name = os.path.basename(path)
    mesh = meshio.read(path)
    pts = mesh.points[:, :2]
    tri, regions = cells(mesh, "triangle", data_names)
    lines, tags = cells(mesh, "line", line_names or data_names)
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    area = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    check(name + ": triangles counter-clockwise", bool(np.all(area > 0)))
    check(name + ": area 12", abs(area.sum() - 12) <= 12e-12, str(area.sum()))
    check(name + ": regions all 42", set(regions.tolist()) == {42}, str(set(regions.tolist())))
    # Boundary edges: edges of one triangle.
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(edges, axis=0, return_counts=True)
    boundary = {tuple(e) for e in uniq[count == 1]}
    written = {tuple(sorted(e)) for e in lines.tolist()}
    check(name + ": boundary edges written = edges of one triangle", boundary == written,
          "%d vs %d" % (len(boundary), len(written)))
    lengths = {}
    for (i, j), t in zip(lines.tolist(), tags.tolist()):
        expected = side_tag(pts[i], pts[j])
        if t != expected:
            check(name + ": edge tag", False, "edge %s-%s tag %d, side %d" % (pts[i], pts[j], t, expected))
            break
        lengths[t] = lengths.get(t, 0) + float(np.hypot(*(pts[i] - pts[j])))
    for t, total in {5: 2, 7: 2, 3: 12, 9: 8}.items():
        check(name + ": length of tag %d" % t, abs(lengths.get(t, 0) - total) <= 1e-12, str(lengths.get(t)))


def main():
    voroclip, out, data = sys.argv[1], sys.argv[2], sys.argv[3]
    os.makedirs(out, exist_ok=True)
    poly = os.path.join(os.path.dirname(os.path.abspath(__file__)), "tagged_square.poly")
    files = {"square41.msh": [], "square22.msh": ["--msh-version", "2.2"], "square.vtu": [],
             "square.mesh": []}
    for f, extra in files.items():
        subprocess.run([voroclip, "mesh2d", poly, "--vertices", "400", "-o", os.path.join(out, f)] + extra,
                       check=True, stdout=subprocess.DEVNULL)
    check_file(os.path.join(out, "square41.msh"), ["gmsh:physical"])
    check_file(os.path.join(out, "square22.msh"), ["gmsh:physical"])
    check_file(os.path.join(out, "square.vtu"), ["region"], ["patch"])
    # The .vtu's tags are named as mesh3d's: region (0 on the edges), patch (0 on the
    # triangles); no array "tag" (the name before).
    vtu = meshio.read(os.path.join(out, "square.vtu"))
    check("square.vtu: cell data names", sorted(vtu.cell_data) == ["cell_id", "min_angle", "patch", "region"],
          str(sorted(vtu.cell_data)))
    for kind, name in (("line", "region"), ("triangle", "patch")):
        _, zeros = cells(vtu, kind, [name])
        check("square.vtu: %s 0 on the %ss" % (name, kind), set(zeros.tolist()) == {0})
    check_file(os.path.join(out, "square.mesh"), ["medit:ref"])

    # --binary and --compress (.vtu only): the ASCII file's points, cells and every array,
    # bit for bit, in base64 appended data and in zlib-compressed data.
    ascii = meshio.read(os.path.join(out, "square.vtu"))
    for f, flag in [("square_binary.vtu", "--binary"), ("square_zlib.vtu", "--compress")]:
        path = os.path.join(out, f)
        subprocess.run([voroclip, "mesh2d", poly, "--vertices", "400", "-o", path, flag],
                       check=True, stdout=subprocess.DEVNULL)
        with open(path) as text:
            head = text.read(1000)
        check(f + ": appended data", 'format="appended"' in head and "format=\"ascii\"" not in head)
        check(f + ": zlib compressor", ('compressor="vtkZLibDataCompressor"' in head) == (flag == "--compress"))
        m = meshio.read(path)
        check(f + ": same points", np.array_equal(m.points, ascii.points))
        check(f + ": same cells", [c.type for c in m.cells] == [c.type for c in ascii.cells] == ["triangle", "line"]
              and all(np.array_equal(a.data, b.data) for a, b in zip(m.cells, ascii.cells)))
        check(f + ": same cell data", sorted(m.cell_data) == sorted(ascii.cell_data) and all(
            np.array_equal(a, b) for k in ascii.cell_data for a, b in zip(m.cell_data[k], ascii.cell_data[k])),
            str(sorted(m.cell_data)))
        check(f + ": same point data", sorted(m.point_data) == sorted(ascii.point_data) == ["kind"] and
              np.array_equal(m.point_data["kind"], ascii.point_data["kind"]))
        check_file(path, ["region"], ["patch"])

    gmsh.initialize()
    gmsh.option.setNumber("General.Verbosity", 0)
    for f in ["square41.msh", "square22.msh"]:
        gmsh.open(os.path.join(out, f))
        groups = {(d, t): gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
        expected = {(1, t): "boundary %d" % t for t in (3, 5, 7, 9)}
        expected[(2, 42)] = "region 42"
        check(f + ": Gmsh physical groups and names", groups == expected, str(groups))
        gmsh.clear()
    gmsh.finalize()

    issue34 = os.path.join(out, "issue34.msh")
    subprocess.run([voroclip, "mesh2d", os.path.join(data, "polygons", "valid", "issue34.json"),
                    "--vertices", "600", "-o", issue34], check=True, stdout=subprocess.DEVNULL)
    mesh = meshio.read(issue34)
    _, tags = cells(mesh, "line", ["gmsh:physical"])
    _, regions = cells(mesh, "triangle", ["gmsh:physical"])
    check("issue34: ring tags 1..8", set(tags.tolist()) == set(range(1, 9)), str(set(tags.tolist())))
    check("issue34: region 1", set(regions.tolist()) == {1})

    # Segment marker 0 is "no marker" and gives tag 1 (Triangle's rule): Gmsh physical tags
    # are positive, and a tag 0 made a nameless group (in 2.2 the lines lost their group).
    # The outer ring has marker 0, the hole 4; .msh 4.1, 2.2 and .vtu carry the same tags.
    zero = os.path.join(out, "marker0.poly")
    with open(zero, "w") as f:
        f.write("8 2 0 0\n0 0 0\n1 4 0\n2 4 4\n3 0 4\n4 1 1\n5 3 1\n6 3 3\n7 1 3\n8 1\n"
                "0 0 1 0\n1 1 2 0\n2 2 3 0\n3 3 0 0\n4 4 5 4\n5 5 6 4\n6 6 7 4\n7 7 4 4\n"
                "1\n0 2 2\n")
    for f, extra in {"marker0_41.msh": [], "marker0_22.msh": ["--msh-version", "2.2"],
                     "marker0.vtu": []}.items():
        subprocess.run([voroclip, "mesh2d", zero, "--vertices", "300", "-o", os.path.join(out, f)] + extra,
                       check=True, stdout=subprocess.DEVNULL)
    gmsh.initialize()
    gmsh.option.setNumber("General.Verbosity", 0)
    for f in ["marker0_41.msh", "marker0_22.msh"]:
        gmsh.open(os.path.join(out, f))
        groups = {(d, t): gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
        expected = {(1, 1): "boundary 1", (1, 4): "boundary 4", (2, 1): "region 1"}
        check(f + ": marker 0 is tag 1 in Gmsh's physical groups", groups == expected, str(groups))
        # Every boundary line is in a physical group (2.2 dropped the tag-0 lines' group).
        lines = sum(len(gmsh.model.mesh.getElements(1, e)[1][0])
                    for _, e in gmsh.model.getEntities(1))
        grouped = sum(len(gmsh.model.mesh.getElements(1, e)[1][0])
                      for d, t in groups if d == 1
                      for e in gmsh.model.getEntitiesForPhysicalGroup(d, t))
        check(f + ": every boundary line in a physical group", lines == grouped and lines > 0,
              "%d lines, %d grouped" % (lines, grouped))
        gmsh.clear()
    gmsh.finalize()
    for f, names in [("marker0_41.msh", ["gmsh:physical"]), ("marker0.vtu", ["patch"])]:
        _, tags = cells(meshio.read(os.path.join(out, f)), "line", names)
        check(f + ": boundary tags 1 and 4", set(tags.tolist()) == {1, 4}, str(set(tags.tolist())))

    if failures:
        print("%d check(s) failed" % len(failures))
        sys.exit(1)
    print("check_mesh2d_tags: all checks passed")


if __name__ == "__main__":
    main()
