"""voroclip: exact clipped Voronoi diagrams, centroidal Voronoi tessellations and CVT
meshing in 2D (polygons with holes) and 3D (volumes bounded by triangle surfaces).

numpy in, numpy out. Every combinatorial decision (which cell, which side, which
triangle) is exact; only constructed coordinates are rounded. Bad input raises
:class:`Error` (a ValueError) with the library's message. Heavy calls release the GIL,
take ``threads=`` (None or 0: all cores; a count above the cores runs on the cores) and
give the same bits for any thread count.

Main entry points: :func:`clip2d`, :func:`clip3d`, :func:`cvt2d`, :func:`cvt3d`,
:func:`mesh2d`, :func:`mesh3d`, :func:`quality`, :func:`random_points`, :class:`Delaunay2`, :class:`Delaunay3`,
the predicates :func:`orient2d`, :func:`incircle`, :func:`orient3d`, :func:`insphere`,
and :func:`domain2` / :func:`domain3` to validate a domain once for several calls.
"""

from __future__ import annotations

from . import _core
from ._api import (
    CSR,
    Cells,
    CvtResult,
    Mesh,
    Quality,
    SiteWarning,
    clip2d,
    clip3d,
    cvt2d,
    cvt3d,
    mesh2d,
    mesh3d,
    quality,
    random_points,
)
from ._core import Domain2, Domain3, Error
from ._domains import domain2, domain3

__version__ = _core.__version__

__all__ = [
    "CSR", "Cells", "CvtResult", "Delaunay2", "Delaunay3", "Domain2", "Domain3", "Error",
    "Mesh", "Quality", "SiteWarning", "clip2d", "clip3d", "cvt2d", "cvt3d", "domain2", "domain3",
    "incircle", "insphere", "mesh2d", "mesh3d", "orient2d", "orient3d", "quality", "random_points",
]


class Delaunay2(_core.Delaunay2):
    """The Delaunay triangulation of (n, 2) points, exact (filtered predicates, symbolic
    perturbation: degenerate input such as grids gives a valid, unique triangulation).

    scipy.spatial.Delaunay's conventions: ``simplices`` (m, 3) int32 point indices,
    counter-clockwise; ``neighbors`` (m, 3): the triangle opposite vertex k, -1 on the
    hull; ``find_simplex(xi)`` the triangle holding each point of xi, shaped (..., 2), -1
    outside, in shape (...) (one point (2,): a 0-d array);
    ``vertex_neighbor_vertices`` (indptr, indices). Also ``vertex_neighbors(v)`` (counter-
    clockwise around v, as in ``vertex_neighbor_vertices``; Delaunay3's are sorted),
    ``nearest_vertex(xi)`` (exact nearest point), ``ndim``, ``nsimplex``, ``convex_hull``
    (h, 2) int32 hull edges, counter-clockwise (points on a hull edge are vertices of it, as
    in scipy), ``hull_vertices`` (h,) counter-clockwise from the smallest index
    (scipy.spatial.ConvexHull.vertices' 2D order), ``duplicate_of`` (for each point, the smallest index with the same coordinates; only
    that one is a vertex), ``check()`` ('' when valid and Delaunay, checked exactly).
    The points are copied. Raises :class:`Error` for non-finite coordinates or fewer than 3
    affinely independent points."""

    def __init__(self, points, threads=None):
        super().__init__(points, threads)


class Delaunay3(_core.Delaunay3):
    """The Delaunay tetrahedralisation of (n, 3) points, exact; as :class:`Delaunay2`
    with ``simplices`` / ``neighbors`` (m, 4), ``convex_hull`` (h, 3) int32 hull triangles,
    counter-clockwise seen from outside (coplanar points on the hull are vertices of it, its
    faces triangulated: the diagonals may differ from scipy's), and ``hull_vertices``
    sorted (scipy.spatial.ConvexHull.vertices' 3D order). The tets of ``simplices`` have det(p1 - p0, p2 - p0, p3 - p0) < 0
    (orient3d(p0, p1, p2, p3) = +1, Shewchuk's convention), exactly: the opposite of
    :attr:`Mesh.cells` and VTK (det > 0); ``simplices[:, [1, 0, 2, 3]]`` turns them so.
    Raises :class:`Error` for non-finite coordinates or fewer than 4 affinely independent
    points."""

    def __init__(self, points, threads=None):
        super().__init__(points, threads)


def orient2d(a, b, c):
    """Exact sign of the orientation of triangles (a, b, c): +1 counter-clockwise, -1
    clockwise, 0 collinear. Each argument an (n, 2) array or one point (broadcast).
    Returns (n,) int8."""
    return _core.orient2d(a, b, c)


def incircle(a, b, c, d):
    """Exact sign of d against the circle through a, b, c: +1 inside when (a, b, c) is
    counter-clockwise (Shewchuk's convention), 0 on it. (n, 2) arrays -> (n,) int8."""
    return _core.incircle(a, b, c, d)


def orient3d(a, b, c, d):
    """Exact sign of the orientation of (a, b, c, d) with Shewchuk's convention: +1 when
    d lies below the plane of (a, b, c), a, b, c appearing counter-clockwise from above.
    (n, 3) arrays -> (n,) int8."""
    return _core.orient3d(a, b, c, d)


def insphere(a, b, c, d, e):
    """Exact sign of e against the sphere through a, b, c, d: +1 inside when
    orient3d(a, b, c, d) > 0 (Shewchuk's convention), 0 on it. (n, 3) arrays -> (n,)
    int8."""
    return _core.insphere(a, b, c, d, e)
