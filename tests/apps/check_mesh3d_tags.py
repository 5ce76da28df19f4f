#!/usr/bin/python3
"""check_mesh3d_tags.py VOROCLIP WRITER DIR DATA: what `voroclip mesh3d` writes for a
solver, read back by meshio and Gmsh's Python module.

WRITER (write_tagged_meshes) writes the tagged Kuhn cube (tests/core/tagged_mesh.h: six
tets in regions 1 and 2, its faces tagged by axis, x 10, y 11, z 12, four tag names) into
DIR; `voroclip mesh3d` meshes its Gmsh 4.1 file (which carries the names) with 400 vertices
into .mesh, .msh 4.1, .msh 2.2 and .vtu (also binary 4.1, compressed .vtu and TetGen
.node/.ele/.face), and meshes DATA/surfaces/bunny.obj into a .msh 4.1. For each file: the
triangles are the faces of exactly one tetrahedron (numpy over sorted corner triples),
oriented outward (their cones from the centroid add up to the volume), each triangle's tag
is its cube face's axis tag (by its corners' coordinates), the tetrahedra's tags are {1,
2}; Gmsh finds physical groups of dimension 3 and 2 with the file's names ("patch 11" for the
unnamed y faces). The bunny's .msh: one region, patch tags from 1, named "region 1" and
"patch <tag>" for Gmsh and in meshio's field_data. Prints one line per mismatch and exits
with 1 when there is any.
"""

import json
import os
import subprocess
import sys

import gmsh
import meshio
import numpy as np

failures = []


def check(what, ok, detail=""):
    if not ok:
        failures.append(f"{what} {detail}".strip())


def blocks(mesh, cell_type, data_names):
    """All cells of one type and, per name, their cell data (None when absent)."""
    idx = [i for i, b in enumerate(mesh.cells) if b.type == cell_type]
    cells = np.concatenate([mesh.cells[i].data for i in idx]) if idx else np.zeros((0, 3), int)
    data = {}
    for name in data_names:
        if name in mesh.cell_data:
            data[name] = np.concatenate([np.asarray(mesh.cell_data[name][i]).ravel() for i in idx])
    return cells, data


def check_shape(what, points, tets, tris):
    faces = np.sort(np.concatenate([tets[:, [1, 2, 3]], tets[:, [0, 2, 3]],
                                    tets[:, [0, 1, 3]], tets[:, [0, 1, 2]]]), axis=1)
    uniq, counts = np.unique(faces, axis=0, return_counts=True)
    once = {tuple(f) for f in uniq[counts == 1]}
    got = [tuple(f) for f in np.sort(tris, axis=1)]
    check(f"{what}: triangles are the faces of one tet", set(got) == once and len(got) == len(once),
          f"({len(got)} triangles, {len(once)} faces)")
    p = points
    v = np.einsum("ij,ij->i", p[tets[:, 1]] - p[tets[:, 0]],
                  np.cross(p[tets[:, 2]] - p[tets[:, 0]], p[tets[:, 3]] - p[tets[:, 0]])) / 6
    check(f"{what}: tets right-handed", bool(np.all(v > 0)))
    c = p.mean(axis=0)
    cones = np.einsum("ij,ij->i", p[tris[:, 0]] - c,
                      np.cross(p[tris[:, 1]] - c, p[tris[:, 2]] - c)) / 6
    check(f"{what}: triangles outward", abs(cones.sum() - v.sum()) <= 1e-9 * abs(v.sum()),
          f"(cones {cones.sum()}, volume {v.sum()})")


def check_cube(path, tri_tag_name, tet_tag_name):
    m = meshio.read(path)
    tets, tet_data = blocks(m, "tetra", [tet_tag_name])
    tris, tri_data = blocks(m, "triangle", [tri_tag_name])
    check_shape(path, m.points, tets, tris)
    check(f"{path}: tet tags", tet_tag_name in tet_data and set(tet_data[tet_tag_name].tolist()) == {1, 2},
          str(set(tet_data.get(tet_tag_name, np.array([])).tolist())))
    if tri_tag_name not in tri_data:
        check(f"{path}: triangle tags present", False)
        return
    lo, hi = 1.0 / 3.0, 0.1 + 1.0 / 3.0
    wrong = 0
    for t, tag in zip(tris, tri_data[tri_tag_name].tolist()):
        c = m.points[t].mean(axis=0)
        axes = [k for k in range(3) if min(abs(c[k] - lo), abs(c[k] - hi)) <= 1e-9]
        if len(axes) != 1 or tag != 10 + axes[0]:
            wrong += 1
    check(f"{path}: triangle tags by cube face", wrong == 0, f"({wrong} of {len(tris)} wrong)")


def check_tetgen(path, writer):
    """TetGen: meshio reads the .node and .ele (tets, tetgen:ref); the .face (boundary
    triangles, markers) through `WRITER --read`, voroclip's reader, checked the same way."""
    m = meshio.read(path)
    tets, data = blocks(m, "tetra", ["tetgen:ref"])
    check(f"{path}: tet tags", set(data.get("tetgen:ref", np.array([])).tolist()) == {1, 2})
    r = subprocess.run([writer, "--read", path[:-5] + ".ele"], capture_output=True, text=True)
    check(f"{path}: read back by voroclip", r.returncode == 0, r.stderr.strip())
    if r.returncode != 0:
        return
    mesh = json.loads(r.stdout)
    points = np.asarray(mesh["points"], dtype=float)
    check(f"{path}: the same points as meshio's", np.array_equal(points, m.points))
    tris = np.asarray(mesh["triangles"], dtype=int).reshape(-1, 3)
    check_shape(path + " (.face)", points, tets, tris)
    check(f"{path}: .face markers", sorted(set(mesh["triangle_ref"])) == [10, 11, 12],
          str(sorted(set(mesh["triangle_ref"]))))


def gmsh_groups(path):
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.open(path)
        return {(d, t): gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
    finally:
        gmsh.finalize()


def check_gmsh_nodes(path):
    """A .msh 4.1's nodes each on the entity of lowest dimension that holds it, as Gmsh
    writes them: gmsh.model.mesh.getNodes(2, entity) gives a patch's nodes (it gave none:
    every node was in volume 1), each node on a surface entity among those of its
    triangles, on a volume entity among those of its tets otherwise."""
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.open(path)
        element_nodes, classified = {}, {}
        for dim, entity in gmsh.model.getEntities():
            _, _, nodes = gmsh.model.mesh.getElements(dim, entity)
            element_nodes[(dim, entity)] = {int(n) for block in nodes for n in block}
            for n in gmsh.model.mesh.getNodes(dim, entity)[0]:
                classified.setdefault(int(n), []).append((dim, entity))
        on_triangles = set().union(*(v for (d, _), v in element_nodes.items() if d == 2))
        bad = [(n, where) for n, where in classified.items()
               if len(where) != 1 or n not in element_nodes[where[0]]
               or (where[0][0] == 3) == (n in on_triangles)]
        check(f"{path}: each node once, on an entity of lowest dimension holding it", not bad,
              str(bad[:5]))
        empty = [e for e in element_nodes if e[0] == 2
                 and len(gmsh.model.mesh.getNodes(*e)[0]) == 0]
        check(f"{path}: getNodes(2, entity) finds nodes on every patch", not empty, str(empty))
        used = set().union(*element_nodes.values())
        check(f"{path}: every used node classified", used <= set(classified))
    finally:
        gmsh.finalize()


def main():
    voroclip, writer, out, data = sys.argv[1:5]
    os.makedirs(out, exist_ok=True)
    subprocess.run([writer, out], check=True)
    cube = os.path.join(out, "tagged41.msh")  # Gmsh: the tag names too
    for name, extra in [("cube.mesh", []), ("cube41.msh", []),
                        ("cube22.msh", ["--msh-version", "2.2"]), ("cube.vtu", []),
                        ("cube41b.msh", ["--binary"]), ("cube_zlib.vtu", ["--compress"]),
                        ("cube.node", [])]:
        path = os.path.join(out, name)
        if os.path.exists(path):
            os.remove(path)
        r = subprocess.run([voroclip, "mesh3d", cube, "--vertices", "400", "-o", path] + extra,
                           capture_output=True, text=True)
        check(f"mesh3d -o {name}: exit status", r.returncode == 0, r.stderr.strip())
        if r.returncode != 0:
            continue
        if name.endswith(".node"):
            check_tetgen(path, writer)
        elif name.endswith(".mesh"):
            check_cube(path, "medit:ref", "medit:ref")
        elif name.endswith(".msh"):
            check_cube(path, "gmsh:physical", "gmsh:physical")
            groups = gmsh_groups(path)
            # The file's names, and one made for the unnamed y faces.
            expected = {(3, 1): "steel", (3, 2): "copper region", (2, 10): "x faces",
                        (2, 11): "patch 11", (2, 12): "z"}
            check(f"{path}: Gmsh physical groups", groups == expected, str(groups))
            if "41" in name:
                check_gmsh_nodes(path)
        else:
            check_cube(path, "patch", "region")

    # The bunny (a surface: patches between feature lines, one region) only at full scale:
    # the sanitizer stage (VOROCLIP_TEST_SCALE < 1) runs the cube alone.
    if float(os.environ.get("VOROCLIP_TEST_SCALE") or 1) < 1:
        return report()
    bunny = os.path.join(out, "bunny.msh")
    r = subprocess.run([voroclip, "mesh3d", os.path.join(data, "surfaces", "bunny.obj"),
                        "--vertices", "1000", "-o", bunny], capture_output=True, text=True)
    check("mesh3d bunny.obj: exit status", r.returncode == 0, r.stderr.strip())
    if r.returncode == 0:
        m = meshio.read(bunny)
        tets, td = blocks(m, "tetra", ["gmsh:physical"])
        tris, fd = blocks(m, "triangle", ["gmsh:physical"])
        check_shape(bunny, m.points, tets, tris)
        check("bunny: one region", set(td["gmsh:physical"].tolist()) == {1})
        tri_blocks = sum(1 for b in m.cells if b.type == "triangle")
        patches_found = len(set(fd["gmsh:physical"].tolist()))
        check("bunny: one triangle block per patch", tri_blocks == patches_found,
              f"({tri_blocks} blocks, {patches_found} patches)")
        patches = sorted(set(fd["gmsh:physical"].tolist()))
        check("bunny: patch tags 1..K", patches == list(range(1, len(patches) + 1)), str(patches))
        groups = gmsh_groups(bunny)
        named = {(3, 1): "region 1"}
        named.update({(2, p): f"patch {p}" for p in patches})
        check("bunny: Gmsh finds the groups, each named", groups == named, str(groups))
        check("bunny: meshio's field_data has the names",
              {k: v.tolist() for k, v in m.field_data.items()}
              == {n: [t, d] for (d, t), n in named.items()}, str(m.field_data))

    return report()


def report():
    for f in failures:
        print(f)
    print(f"{len(failures)} mismatch(es)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
