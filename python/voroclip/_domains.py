"""Conversions of what users hold (arrays, files, shapely and meshio objects) to the
library's validated domains, :class:`Domain2` and :class:`Domain3`."""

from __future__ import annotations

import os

import numpy as np

from . import _core
from ._core import Error


def _ring_array(ring, where):
    coords = getattr(ring, "coords", ring)  # shapely LinearRing or an array
    try:
        a = np.asarray(coords, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise Error(f"{where}: expected an (n, 2) array of numbers ({e})") from None
    if a.ndim != 2 or a.shape[1] not in (2, 3) or a.shape[0] < 3:
        raise Error(f"{where}: expected an (n, 2) array of n >= 3 points, got shape {a.shape}")
    return a[:, :2]


def _bare_ring(domain):
    # [ring] when `domain` is an array-like of numbers shaped (n, 2): one ring given alone
    # (a list of rings converts to 3 dimensions, or fails to convert when ragged); None when
    # it is not an array of numbers at all. Numbers of another shape raise: neither form.
    try:
        a = np.asarray(domain, dtype=np.float64)
    except (TypeError, ValueError):
        return None
    if a.size == 0:
        return None
    if a.ndim == 2 and a.shape[1] == 2:
        return [a]
    if a.ndim in (1, 2):
        raise Error("domain: expected a list of rings or one ring as an (n, 2) array of "
                    f"points, got numbers of shape {a.shape}")
    return None


def _generator2(spec):
    # The command line's generators (apps/clip_cmd.cpp, load_rings): the same names, the
    # same limits, the same messages; None when `spec` names none (a path, then).
    for prefix, usage, count in (("annulus:", "annulus:R_IN,R_OUT,SEGMENTS", 3),
                                 ("square-holes:", "square-holes:K,FRACTION", 2)):
        if not spec.startswith(prefix):
            continue
        text = spec[len(prefix):]
        try:
            v = [float(t) for t in text.split(",")]
        except ValueError:
            v = []
        if len(v) != count or not all(np.isfinite(v)):
            raise Error(f"{usage}: expected {count} comma-separated numbers, got '{text}'")
        if prefix == "annulus:":
            if not (0 < v[0] < v[1]) or not (3 <= v[2] <= 1e7) or v[2] != int(v[2]):
                raise Error(f"{usage} needs 0 < R_IN < R_OUT and 3 <= SEGMENTS")
            return _core.Domain2.annulus(v[0], v[1], int(v[2]))
        if not (1 <= v[0] <= 1000) or v[0] != int(v[0]) or not (0 < v[1] < 1):
            raise Error(f"{usage} needs 1 <= K <= 1000 and 0 < FRACTION < 1")
        return _core.Domain2.square_holes(int(v[0]), v[1])
    return None


def domain2(domain) -> _core.Domain2:
    """A validated polygonal domain (with holes) from

    * a :class:`Domain2` (returned as it is);
    * a path (``str`` or ``os.PathLike``) to a ``.poly`` (Triangle) or ``.json`` file;
    * a list of rings, each an (n, 2) array-like of points: ring 0 is the outer boundary,
      the others are holes (orientation free; a repeated closing point is dropped);
    * one ring, an (n, 2) array-like of numbers (an array, a list of (x, y) pairs): the
      outer boundary of a polygon without holes (a list of rings has one more level of
      nesting, so the two cannot be confused; other shapes of numbers raise :class:`Error`);
    * a shapely-like polygon (``.exterior`` and ``.interiors`` with ``.coords``), a list of
      them, or a multi-polygon (``.geoms``);
    * the command line's generators, ``"annulus:R_IN,R_OUT,SEGMENTS"`` (as
      :meth:`Domain2.annulus`) and ``"square-holes:K,FRACTION"`` (as
      :meth:`Domain2.square_holes`), with its limits.

    Several polygons (a list of them, a multi-polygon, a JSON file of several) give
    mesh2d's triangles the region of their polygon (1, 2, ... in the order given) and its
    boundary edges the tag of their ring (1, 2, ... over all rings in that order, each
    polygon's exterior then its holes).

    Raises :class:`voroclip.Error` naming the ring and points for an invalid polygon (self
    intersections, rings that touch, a hole outside its polygon, a non-finite coordinate).
    """
    if isinstance(domain, _core.Domain2):
        return domain
    if isinstance(domain, str):
        generated = _generator2(domain)
        if generated is not None:
            return generated
    if isinstance(domain, (str, os.PathLike)):
        return _core.Domain2.read(os.fspath(domain))
    if hasattr(domain, "geoms"):
        polygons = list(domain.geoms)
    elif hasattr(domain, "exterior"):
        polygons = [domain]
    else:
        try:
            items = list(domain)
        except TypeError:
            raise Error(
                "domain: expected a Domain2, a path, a list of rings or a shapely-like "
                f"polygon, got {type(domain).__name__}"
            ) from None
        if items and all(hasattr(p, "exterior") for p in items):
            polygons = items
        else:
            polygons = [_bare_ring(domain) or items]
    xy, begin, polygon = [], [0], []
    for p, poly in enumerate(polygons):
        if hasattr(poly, "exterior"):
            rings = [poly.exterior, *list(poly.interiors)]
        else:
            rings = poly
        if len(rings) == 0:
            raise Error(f"domain: polygon {p} has no ring")
        for r, ring in enumerate(rings):
            a = _ring_array(ring, f"domain: polygon {p}, ring {r}" if len(polygons) > 1
                            else f"domain: ring {r}")
            xy.append(a)
            begin.append(begin[-1] + a.shape[0])
            polygon.append(p)
    return _core.Domain2(np.concatenate(xy), np.asarray(begin, dtype=np.int64),
                         np.asarray(polygon, dtype=np.int64), "rings")


_TET_TAGS = ("region", "gmsh:physical", "medit:ref", "cell_tags")
_TRI_TAGS = ("patch", "gmsh:physical", "medit:ref", "cell_tags")


def _meshio_domain(mesh, reorient):
    points = np.asarray(mesh.points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3:
        raise Error(f"domain: a meshio.Mesh with 3D points is needed, got shape {points.shape}")
    blocks = {"tetra": [], "triangle": []}
    tags = {"tetra": [], "triangle": []}
    for k, block in enumerate(mesh.cells):
        if block.type in blocks:
            blocks[block.type].append(np.asarray(block.data, dtype=np.int64))
            names = _TET_TAGS if block.type == "tetra" else _TRI_TAGS
            name = next((n for n in names if n in mesh.cell_data), None)
            tags[block.type].append(
                None if name is None else np.asarray(mesh.cell_data[name][k], dtype=np.int64))

    def join(kind, width):
        if not blocks[kind]:
            return np.zeros((0, width), dtype=np.int64), np.zeros(0, dtype=np.int64)
        cells = np.concatenate(blocks[kind])
        if any(t is None for t in tags[kind]):
            return cells, np.zeros(0, dtype=np.int64)
        return cells, np.concatenate(tags[kind])

    tets, tet_tags = join("tetra", 4)
    triangles, tri_tags = join("triangle", 3)
    # Physical names, as meshio keeps them: field_data {name: [tag, dimension]}.
    names = []
    for name, value in (getattr(mesh, "field_data", None) or {}).items():
        v = np.asarray(value).ravel()
        if v.size == 2 and int(v[1]) in (2, 3):
            names.append((int(v[1]), int(v[0]), str(name)))
    if len(tets):
        return _core.Domain3.from_tets(points, tets, triangles, tet_tags, tri_tags, "meshio.Mesh",
                                       sorted(names))
    if len(triangles):
        return _core.Domain3.from_surface(points, triangles, "meshio.Mesh", reorient)
    raise Error("domain: the meshio.Mesh has neither tetra nor triangle cells")


def domain3(domain, reorient: bool = False) -> _core.Domain3:
    """A validated 3D domain (a volume bounded by a closed triangle surface, possibly with a
    tet mesh of it) from

    * a :class:`Domain3` (returned as it is);
    * a path to a surface (``.obj``, ``.off``, ``.stl``, ``.ply``) or a tet mesh (``.mesh``,
      ``.node``/``.ele``, ``.msh``, ``.vtk``, ``.vtu``);
    * a ``(vertices, triangles)`` pair: (n, 3) float coordinates and (m, 3) vertex indices
      from 0, the triangles oriented outward (``reorient=True`` fixes inside-out shells);
    * a ``meshio.Mesh`` with ``tetra`` cells (a tet mesh; ``triangle`` cells, their tags
      and the names in ``field_data`` come along: a tet's tag from the cell data
      ``region``, else ``gmsh:physical``, else ``medit:ref``, a triangle's from ``patch``,
      else ``gmsh:physical``, else ``medit:ref``, as the files' readers take them) or only
      ``triangle`` cells.

    Raises :class:`voroclip.Error` for an open, non-manifold or self-intersecting surface,
    naming the faces.
    """
    if isinstance(domain, _core.Domain3):
        return domain
    if isinstance(domain, (str, os.PathLike)):
        return _core.Domain3.read(os.fspath(domain), reorient)
    if hasattr(domain, "points") and hasattr(domain, "cells"):
        return _meshio_domain(domain, reorient)
    if isinstance(domain, (tuple, list)) and len(domain) == 2:
        try:
            vertices = np.asarray(domain[0], dtype=np.float64)
            triangles = np.asarray(domain[1])
        except (TypeError, ValueError) as e:
            raise Error(f"domain: expected (vertices, triangles) arrays ({e})") from None
        if triangles.dtype.kind not in "iu":
            raise Error(f"triangles: expected integer vertex indices, got dtype {triangles.dtype}")
        return _core.Domain3.from_surface(vertices, triangles.astype(np.int64, copy=False),
                                          "surface", reorient)
    raise Error(
        "domain: expected a Domain3, a path, a (vertices, triangles) pair or a meshio.Mesh, "
        f"got {type(domain).__name__}"
    )
