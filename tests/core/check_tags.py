#!/usr/bin/python3
"""check_tags.py HELPER DIR: the tet mesh files voroclip writes, read back by third-party
readers, and the files they write read back by voroclip.

Runs HELPER (write_tagged_meshes) to write a tagged mesh in every format into DIR, with
DIR/expected.json, then reads every file with meshio (points, tetra and triangle cells in
order, the tags: cell data medit:ref, tetgen:ref, gmsh:physical, region/patch; field_data
for the Gmsh names) and the .msh files with Gmsh's Python module (physical groups, their
names, entities and elements, the nodes). Meshio does not read TetGen's .face: the file is
checked here against TetGen's layout. The other way round, Gmsh saves the mesh again (MSH
4.1, 2.2, and 4.1 partitioned in two, each ASCII and binary) and meshio writes what it read
(.vtu ASCII, and inline base64 uncompressed or zlib-compressed (its default) with UInt32
or UInt64 headers; .vtk ASCII and binary; .mesh; .msh 2.2 ASCII and binary), and
`HELPER --read` must find the same tetrahedra and triangles with the same tags (compared
as sets of cells by their corners' coordinates, as these writers renumber and print 16
digits). Prints one line per mismatch and exits with 1 when there is any, 0 otherwise.

Needs the Debian packages python3-meshio and python3-gmsh: an import error fails the test.
"""

import json
import os
import shutil
import subprocess
import sys

import gmsh
import meshio
import numpy as np

failures = []


def check(what, got, expected):
    if got != expected:
        failures.append(f"{what}: got {got!r}, expected {expected!r}")


def as_list(array):
    return np.asarray(array).tolist()


def cells_of(mesh, cell_type):
    """The cells of one type, all blocks in order, and the indices of those blocks."""
    blocks = [i for i, block in enumerate(mesh.cells) if block.type == cell_type]
    cells = [c for i in blocks for c in as_list(mesh.cells[i].data)]
    return cells, blocks


def tags_of(mesh, name, blocks):
    """Cell data `name` over the given blocks, in order (None when absent)."""
    if name not in mesh.cell_data:
        return None
    # One value per cell (meshio gives legacy VTK SCALARS as columns of one component).
    values = [np.asarray(mesh.cell_data[name][i]) for i in blocks]
    for i, v in zip(blocks, values):
        check(f"cell data {name}: values of block {i}", v.size, len(mesh.cells[i].data))
    return [int(t) for v in values for t in v.ravel().tolist()]


def node_entities(exp):
    """Per node, the (dimension, entity) of a .msh 4.1 voroclip writes: the entity of lowest
    dimension that holds it, as Gmsh classifies nodes: a triangle corner on the surface
    entity of the lowest tag among its triangles, any other node on the volume entity of
    its first tet (1: of no tet); entity k is the k-th distinct tag of its dimension."""
    def entities(refs):
        tags = sorted(set(refs)) or [0]
        return {t: k + 1 for k, t in enumerate(tags)}
    volumes, surfaces = entities(exp["tet_ref"]), entities(exp["triangle_ref"])
    got = [None] * len(exp["points"])
    for cell, tag in zip(exp["triangles"], exp["triangle_ref"] or [0] * len(exp["triangles"])):
        for v in cell:
            e = surfaces[tag]
            got[v] = (2, e) if got[v] is None else (2, min(got[v][1], e))
    for cell, tag in zip(exp["tets"], exp["tet_ref"] or [0] * len(exp["tets"])):
        for v in cell:
            if got[v] is None:
                got[v] = (3, volumes[tag])
    return [list(d) if d is not None else [3, 1] for d in got]


def check_with_meshio(path, fmt, exp):
    """fmt: medit, tetgen, gmsh22, gmsh41, vtk."""
    mesh = meshio.read(path)
    where = os.path.basename(path) + " (meshio)"
    check(f"{where}: points", as_list(mesh.points), exp["points"])
    tets, tet_blocks = cells_of(mesh, "tetra")
    triangles, triangle_blocks = cells_of(mesh, "triangle")
    check(f"{where}: tetra cells", tets, exp["tets"])
    kinds = {block.type for block in mesh.cells}
    if fmt == "tetgen":
        check(f"{where}: cell types", kinds, {"tetra"})  # meshio reads no .face
    else:
        check(f"{where}: triangle cells", triangles, exp["triangles"])
        check(f"{where}: cell types", kinds, {"tetra", "triangle"})
    any_tag = any(exp["tet_ref"]) or any(exp["triangle_ref"])
    if fmt == "medit":
        check(f"{where}: tetra medit:ref", tags_of(mesh, "medit:ref", tet_blocks), exp["tet_ref"])
        check(f"{where}: triangle medit:ref", tags_of(mesh, "medit:ref", triangle_blocks),
              exp["triangle_ref"])
    elif fmt == "tetgen":
        check(f"{where}: tetgen:ref", tags_of(mesh, "tetgen:ref", tet_blocks),
              exp["tet_ref"] if any(exp["tet_ref"]) else None)
    elif fmt in ("gmsh22", "gmsh41"):
        physical = "gmsh:physical"
        expected_tets = exp["tet_ref"] if any_tag or fmt == "gmsh22" else None
        expected_triangles = exp["triangle_ref"] if any_tag or fmt == "gmsh22" else None
        check(f"{where}: tetra {physical}", tags_of(mesh, physical, tet_blocks), expected_tets)
        check(f"{where}: triangle {physical}", tags_of(mesh, physical, triangle_blocks),
              expected_triangles)
        fields = {name: as_list(value) for name, value in mesh.field_data.items()}
        check(f"{where}: field_data", fields,
              {name: [tag, dim] for dim, tag, name in exp["names"]})
        if fmt == "gmsh41":
            # The nodes' entities (all in volume 1 before, so a surface had no nodes).
            check(f"{where}: gmsh:dim_tags", as_list(mesh.point_data["gmsh:dim_tags"]),
                  node_entities(exp))
    else:
        n_tets = len(exp["tets"])
        expected_region = exp["tet_ref"] if any(exp["tet_ref"]) else None
        expected_patch = exp["triangle_ref"] if any(exp["triangle_ref"]) else None
        region = tags_of(mesh, "region", tet_blocks)
        patch = tags_of(mesh, "patch", triangle_blocks)
        check(f"{where}: tetra region", region, expected_region)
        check(f"{where}: triangle patch", patch, expected_patch)
        # The other kind of cell carries 0.
        if expected_region is not None:
            check(f"{where}: triangle region", tags_of(mesh, "region", triangle_blocks),
                  [0] * len(exp["triangles"]))
        if expected_patch is not None:
            check(f"{where}: tetra patch", tags_of(mesh, "patch", tet_blocks), [0] * n_tets)
        check(f"{where}: cell_id", tags_of(mesh, "cell_id", tet_blocks + triangle_blocks),
              list(range(n_tets + len(exp["triangles"]))))


def check_face_file(path, exp):
    """TetGen's .face layout: "count markers", then "number a b c [marker]" from 1."""
    with open(path) as f:
        rows = [line.split() for line in f if line.strip() and not line.startswith("#")]
    where = os.path.basename(path)
    markers = 1 if any(exp["triangle_ref"]) else 0
    check(f"{where}: header", rows[0], [str(len(exp["triangles"])), str(markers)])
    faces = [[int(v) - 1 for v in row[1:4]] for row in rows[1:]]
    check(f"{where}: faces", faces, exp["triangles"])
    check(f"{where}: numbers", [int(row[0]) for row in rows[1:]],
          list(range(1, len(exp["triangles"]) + 1)))
    if markers:
        check(f"{where}: markers", [int(row[4]) for row in rows[1:]], exp["triangle_ref"])


def check_with_gmsh(path, version, exp):
    where = os.path.basename(path) + " (gmsh)"
    gmsh.clear()
    gmsh.open(path)
    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    points = {int(t): as_list(coords[3 * i:3 * i + 3]) for i, t in enumerate(node_tags)}
    # Gmsh's 2.2 reader keeps only the nodes that elements use (4.1: every node of $Nodes).
    used = {v for cells in (exp["tets"], exp["triangles"]) for c in cells for v in c}
    check(f"{where}: nodes", points,
          {i + 1: p for i, p in enumerate(exp["points"]) if version == 41 or i in used})
    if version == 41:
        # Each node on the entity of lowest dimension that holds it, as Gmsh writes them:
        # getNodes(2, entity) gives a patch's nodes (nothing before: all were in volume 1).
        classified = {}
        for dim, entity in gmsh.model.getEntities():
            tags, _, _ = gmsh.model.mesh.getNodes(dim, entity)
            for t in tags:
                classified[int(t)] = [dim, entity]
        check(f"{where}: nodes' entities", classified,
              {i + 1: d for i, d in enumerate(node_entities(exp))})
    # Physical groups: one per tag of each dimension; tag 0 is no group, except in 4.1
    # files with some tag other than 0, where untagged entities are in group 0.
    any_tag = any(exp["tet_ref"]) or any(exp["triangle_ref"])
    kinds = ((3, 4, "tets", "tet_ref"), (2, 2, "triangles", "triangle_ref"))
    expected_groups = set()
    for dim, _, cells, refs in kinds:
        if exp[cells]:
            expected_groups |= {(dim, t) for t in exp[refs] if t != 0 or (version == 41 and any_tag)}
    groups = set(gmsh.model.getPhysicalGroups())
    check(f"{where}: physical groups", sorted(groups), sorted(expected_groups))
    names = {(dim, tag): name for dim, tag, name in exp["names"]}
    for dim, element_type, cells, refs in kinds:
        for tag in sorted({t for d, t in groups if d == dim}):
            check(f"{where}: name of ({dim}, {tag})", gmsh.model.getPhysicalName(dim, tag),
                  names.get((dim, tag), ""))
            got = []
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                types, _, nodes = gmsh.model.mesh.getElements(dim, int(entity))
                for t, n in zip(types, nodes):
                    check(f"{where}: element type in ({dim}, {tag})", int(t), element_type)
                    per = 4 if element_type == 4 else 3
                    got += [[int(v) - 1 for v in n[per * i:per * i + per]]
                            for i in range(len(n) // per)]
            expected = [c for c, r in zip(exp[cells], exp[refs]) if r == tag]
            check(f"{where}: {cells} of group ({dim}, {tag})", sorted(got), sorted(expected))
    # Every element, in a group or not: element tags 1..nt for the tets, then the triangles.
    for dim, element_type, cells, _ in kinds:
        types, tags, _ = gmsh.model.mesh.getElements(dim)
        got = sorted(int(t) for ty, ts in zip(types, tags) if ty == element_type for t in ts)
        first = 1 if dim == 3 else len(exp["tets"]) + 1
        check(f"{where}: {cells} element tags", got, list(range(first, first + len(exp[cells]))))


def by_corners(points, cells, tags):
    """Cells as sorted (corner coordinates to 12 digits, tag) pairs: independent of the
    numbering and of the last digits printed."""
    key = [tuple(float(f"{x:.12g}") for x in p) for p in points]
    return sorted((tuple(sorted(key[v] for v in c)), t) for c, t in zip(cells, tags))


def check_read_by_voroclip(helper, path, exp, extra_triangles=False):
    """`helper --read path` against exp; extra_triangles: the file may list more (Gmsh's
    partition interfaces), the expected ones must be among them."""
    where = os.path.basename(path) + " (voroclip)"
    got = json.loads(subprocess.run([helper, "--read", path], check=True,
                                    capture_output=True, text=True).stdout)
    check(f"{where}: tets", by_corners(got["points"], got["tets"], got["tet_ref"]),
          by_corners(exp["points"], exp["tets"], exp["tet_ref"]))
    triangles = by_corners(got["points"], got["triangles"], got["triangle_ref"])
    expected = by_corners(exp["points"], exp["triangles"], exp["triangle_ref"])
    if extra_triangles:
        missing = [t for t in expected if t not in triangles]
        check(f"{where}: expected triangles missing", missing, [])
    else:
        check(f"{where}: triangles", triangles, expected)
    if path.endswith(".msh"):
        check(f"{where}: names", sorted(map(tuple, got["names"])),
              sorted(map(tuple, exp["names"])))


def check_others_written(helper, directory, name, exp):
    """Gmsh and meshio write the mesh again; voroclip reads their files."""
    base = os.path.join(directory, name)
    out = os.path.join(directory, "others")
    os.makedirs(out, exist_ok=True)
    gmsh.clear()
    gmsh.open(base + "41.msh")
    written = 0
    for binary in (0, 1):
        gmsh.option.setNumber("Mesh.Binary", binary)
        for version in (4.1, 2.2):
            gmsh.option.setNumber("Mesh.MshFileVersion", version)
            path = os.path.join(out, f"{name}_gmsh{int(version * 10)}{'b' if binary else ''}.msh")
            gmsh.write(path)
            check_read_by_voroclip(helper, path, exp)
            written += 1
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.model.mesh.partition(2)
    for binary in (0, 1):
        gmsh.option.setNumber("Mesh.Binary", binary)
        path = os.path.join(out, f"{name}_gmsh_partitioned{'b' if binary else ''}.msh")
        gmsh.write(path)
        check_read_by_voroclip(helper, path, exp, extra_triangles=True)
        written += 1
    gmsh.option.setNumber("Mesh.Binary", 0)

    for source, target, options in (
            (".vtu", "_meshio.vtu", {"compression": None}),
            (".vtu", "_meshio_zlib.vtu", {}),  # meshio's default: zlib, inline base64
            (".vtu", "_meshio_zlib64.vtu", {"header_type": "UInt64"}),
            (".vtu", "_meshio_ascii.vtu", {"binary": False}),
            (".vtu", "_meshio.vtk", {"binary": False}),
            (".vtu", "_meshio_binary.vtk", {"binary": True}),
            (".mesh", "_meshio.mesh", {}),
            ("22.msh", "_meshio22.msh", {"file_format": "gmsh22", "binary": False}),
            ("22.msh", "_meshio22b.msh", {"file_format": "gmsh22", "binary": True})):
        # (meshio 5.0 writes no MSH 4.1 with tets and triangles without gmsh:dim_tags;
        # Gmsh's own 4.1 files are read above.)
        path = os.path.join(out, name + target)
        meshio.write(path, meshio.read(base + source), **options)
        check_read_by_voroclip(helper, path, exp)
        written += 1
    return written


def main():
    if len(sys.argv) != 3:
        print("usage: check_tags.py HELPER DIR", file=sys.stderr)
        return 2
    helper, directory = sys.argv[1], sys.argv[2]
    shutil.rmtree(directory, ignore_errors=True)
    subprocess.run([helper, directory], check=True)
    with open(os.path.join(directory, "expected.json")) as f:
        expected = json.load(f)
    gmsh.initialize(["check_tags"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    files = gmsh_files = others = 0
    for name, exp in expected.items():
        base = os.path.join(directory, name)
        for suffix, fmt in ((".mesh", "medit"), (".node", "tetgen"), ("22.msh", "gmsh22"),
                            ("41.msh", "gmsh41"), ("41b.msh", "gmsh41"), (".vtk", "vtk"),
                            (".vtu", "vtk"), ("_ascii.vtu", "vtk"), ("_zlib.vtu", "vtk")):
            check_with_meshio(base + suffix, fmt, exp)
            files += 1
        check_face_file(base + ".face", exp)
        check_with_gmsh(base + "22.msh", 22, exp)
        check_with_gmsh(base + "41.msh", 41, exp)
        check_with_gmsh(base + "41b.msh", 41, exp)
        gmsh_files += 3
        for suffix in ("41b.msh", "_zlib.vtu"):  # voroclip's own binary files, read back
            check_read_by_voroclip(helper, base + suffix, exp)
        others += check_others_written(helper, directory, name, exp)
    gmsh.finalize()
    for f in failures:
        print("check_tags: MISMATCH:", f)
    print(f"check_tags: meshio read {files} files, gmsh {gmsh_files}, .face checked "
          f"{len(expected)}; voroclip read {others} files written by Gmsh and "
          f"meshio: {len(failures)} mismatch(es)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
