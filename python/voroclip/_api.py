"""The functions of the voroclip package: clipped Voronoi diagrams, CVT, meshing and
quality, as numpy arrays in and out. Units: the input's length unit L throughout (areas
L^2, volumes L^3, energies L^4 in 2D and L^5 in 3D, times a density's unit)."""

from __future__ import annotations

import json
import os
import warnings
from typing import Callable, NamedTuple, Optional

import numpy as np

from . import _core
from ._core import Error
from ._domains import domain2, domain3


class SiteWarning(UserWarning):
    """Warned by :func:`clip2d` / :func:`clip3d` for given sites outside the domain (their
    cells miss it: empty) or repeating an earlier site (equal coordinates: the first in input
    order gets the cell, the others are empty), as the CLI's ``clip`` / ``clip3d`` warn.
    ``warnings.simplefilter("error", voroclip.SiteWarning)`` makes it an error (the CLI's
    ``--strict``), ``"ignore"`` silences it."""


def _warn_sites(what: str, r: dict) -> None:
    # The core's lists of the sites the CLI warns about (input indices, increasing).
    parts = []
    for key, one, many, empty in (
            ("outside_sites", "site outside the domain", "sites outside the domain", ""),
            ("repeated_sites", "site repeats an earlier site", "sites repeat an earlier site",
             "; their cells are empty")):
        k = len(r[key])
        if k:
            parts.append(f"{k} {one if k == 1 else many} (first: index {int(r[key][0])}, from 0"
                         f"{empty.replace('their cells are', 'its cell is') if k == 1 else empty})")
    if parts:
        warnings.warn(f"{what}: " + "; ".join(parts), SiteWarning, stacklevel=3)


def _threads(threads: Optional[int]):
    # The core checks it (an integer >= 0; above the cores, the cores) and says what is wrong.
    return 0 if threads is None else threads


class CSR(NamedTuple):
    """Neighbour lists in compressed sparse row form: the neighbours of cell i are
    ``indices[indptr[i]:indptr[i + 1]]``, increasing (scipy.sparse's layout)."""

    indptr: np.ndarray
    indices: np.ndarray


class Cells:
    """The cells of a clipped Voronoi diagram, one per input site (a duplicate site, and a
    site whose cell misses the domain, has an empty cell: measure 0, centroid = the site).

    Attributes (n sites, d = 2 or 3):

    * ``sites`` (n, d): the sites, as given;
    * ``areas`` (2D) / ``volumes`` (3D), also ``measures``: (n,) L^d;
    * ``masses`` (n,): integral of the density over the cell (= measures for density 1);
    * ``centroids`` (n, d): mass centroids;
    * ``energies`` (n,): integral of rho |x - site|^2 over the cell, the CVT energy terms;
    * ``boundary`` (n,) bool: the cell meets the domain's boundary;
    * ``surface_areas`` (3D, (n,)): area of the cell's part of the boundary surface;
    * ``total_measure``, ``total_mass``, ``total_energy``: sums in index order.

    ``neighbors``: a :class:`CSR` of the cells sharing an edge (2D) or a face (3D) inside the
    domain (cospherical sites, such as a grid's, also give edges and faces of measure 0
    between cells that touch at a point: the symbolic perturbation's), read from the cells'
    geometry: computed with the diagram under ``neighbors=True``
    or ``geometry=True``, otherwise on first access (the diagram is computed again, with
    its geometry: a few times the plain call). With ``geometry=True``, flat arrays:

    * 2D: ``vertices`` (m, 2), ``ring_vertex_begin`` (R + 1,), ``cell_ring_begin`` (n + 1,):
      cell i has the rings ``cell_ring_begin[i]:cell_ring_begin[i+1]``, ring r the vertices
      ``vertices[ring_vertex_begin[r]:ring_vertex_begin[r+1]]``, counter-clockwise around
      pieces and clockwise around holes; :meth:`polygons` gives them per cell;
    * 3D: ``face_points`` (m, 3), ``face_begin`` (F + 1,), ``face_site`` (F,), ``face_across``
      (F,): face f is the polygon ``face_points[face_begin[f]:face_begin[f+1]]`` of cell
      ``face_site[f]``, on the bisector with site ``face_across[f]`` or, -1, on the domain's
      boundary; :meth:`faces` gives them per cell. A face's points go counter-clockwise
      seen from outside its cell (their right-hand normal points out of it), as in the
      CLI's ``.vtu``.
    """

    def __init__(self, dim: int, sites: np.ndarray, r: dict, recompute=None):
        self.dim = dim
        self._recompute = recompute  # () -> the core's dict with the neighbours
        self.sites = sites
        self.measures = r["areas"] if dim == 2 else r["volumes"]
        if dim == 2:
            self.areas = self.measures
            self.total_measure = r["total_area"]
        else:
            self.volumes = self.measures
            self.surface_areas = r["surface_areas"]
            self.total_measure = r["total_volume"]
            self.total_surface_area = r["total_surface_area"]
            self.seconds = r["seconds"]
        self.masses = r["masses"]
        self.centroids = r["centroids"]
        self.energies = r["energies"]
        self.boundary = r["boundary"]
        self.total_mass = r["total_mass"]
        self.total_energy = r["total_energy"]
        self.nb_boundary = r["nb_boundary"]
        self._neighbors = (
            CSR(r["neighbors_indptr"], r["neighbors_indices"]) if "neighbors_indptr" in r else None
        )
        self.has_geometry = ("vertices" in r) or ("face_points" in r)
        for key in ("vertices", "ring_vertex_begin", "cell_ring_begin", "face_points",
                    "face_begin", "face_site", "face_across"):
            if key in r:
                setattr(self, key, r[key])
        self._faces_by_cell = None

    def __len__(self) -> int:
        return len(self.measures)

    def __repr__(self) -> str:
        what = "areas" if self.dim == 2 else "volumes"
        return (f"<voroclip.Cells: {len(self)} cells in {self.dim}D, {self.nb_boundary} at the "
                f"boundary, sum of {what} {self.total_measure:.17g}>")

    @property
    def neighbors(self) -> CSR:
        if self._neighbors is None:
            if self._recompute is None:
                raise Error("neighbors: not computed; pass neighbors=True to clip2d/clip3d")
            r = self._recompute()
            self._neighbors = CSR(r["neighbors_indptr"], r["neighbors_indices"])
            self._recompute = None
        return self._neighbors

    def _need_geometry(self):
        if not self.has_geometry:
            raise Error("geometry: not computed; pass geometry=True to clip2d/clip3d")

    def _cell(self, i, what: str) -> int:
        if not isinstance(i, (int, np.integer)) or isinstance(i, bool) or \
                not 0 <= i < len(self):
            raise Error(f"{what}: no cell {i!r} (cells 0 to {len(self) - 1})")
        return int(i)

    def polygons(self, i: int) -> list:
        """2D: the rings of cell i, a list of (k, 2) arrays (pieces counter-clockwise,
        holes clockwise)."""
        self._need_geometry()
        if self.dim != 2:
            raise Error("polygons: a 2D diagram's; use faces(i) in 3D")
        i = self._cell(i, "polygons")
        b, e = self.cell_ring_begin[i], self.cell_ring_begin[i + 1]
        return [self.vertices[self.ring_vertex_begin[r]:self.ring_vertex_begin[r + 1]]
                for r in range(b, e)]

    def faces(self, i: int) -> list:
        """3D: the faces of cell i as (points (k, 3), across) pairs, ``across`` the site on
        the other side or -1 on the domain's boundary; the points counter-clockwise seen
        from outside the cell."""
        self._need_geometry()
        if self.dim != 3:
            raise Error("faces: a 3D diagram's; use polygons(i) in 2D")
        i = self._cell(i, "faces")
        if self._faces_by_cell is None:
            order = np.argsort(self.face_site, kind="stable")
            starts = np.searchsorted(self.face_site[order], np.arange(len(self) + 1))
            self._faces_by_cell = (order, starts)
        order, starts = self._faces_by_cell
        return [(self.face_points[self.face_begin[f]:self.face_begin[f + 1]],
                 int(self.face_across[f])) for f in order[starts[i]:starts[i + 1]]]


def _sites(sites, dim):
    # A C-contiguous float64 array passes through without a copy (the C++ side reads it in
    # place); anything else is converted once here.
    try:
        a = np.ascontiguousarray(sites, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise Error(f"sites: expected an (n, {dim}) array of numbers ({e})") from None
    if a.ndim != 2 or a.shape[1] != dim:
        raise Error(f"sites: expected an (n, {dim}) array, got shape {a.shape}")
    return a


def _vectorized(f, vectorized: bool):
    """A density or sizing argument for _core: a callable marked as taking arrays when
    ``vectorized`` (anything else as it is)."""
    if vectorized and callable(f):
        return _core.Vectorized(f)
    return f


def clip2d(domain, sites, density=None, *, geometry: bool = False, neighbors: bool = False,
           callback: Optional[Callable[[dict], object]] = None,
           threads: Optional[int] = None, vectorized: bool = False) -> Cells:
    """The Voronoi diagram of ``sites`` ((n, 2) array, n >= 1: one site or sites on a line
    too) clipped to a polygonal domain (anything :func:`domain2` takes), every
    combinatorial decision exact.

    ``density``: None (1), a number, a callable ``rho(x, y) -> float`` (integrated with a
    degree-5 rule, 7 points, per fan triangle: exact for rho of degree <= 3; called from
    worker threads, slow; a value that is not finite and positive raises :class:`Error`
    naming the point), or a grid tuple
    ``(values[ny, nx], (xmin, ymin), (xmax, ymax))`` interpolated linearly.
    ``vectorized``: the callable takes float64 arrays ``x, y`` of shape (k,) and returns k
    values (or one number for all), as scipy's ``vectorized`` options; in 2D it is called
    with one point per call (k = 1), in 3D with a few thousand points per call.
    ``geometry``/``neighbors``: also return the cells' rings / the neighbour lists (else
    computed on first access of ``neighbors``).
    ``callback(info)``: called now and then (a dict: phase, done, total, seconds) on the
    calling thread; returning False cancels (raises :class:`Error` "clip2d: cancelled").
    Ctrl-C cancels too and raises KeyboardInterrupt.
    ``threads``: TBB threads (None or 0: all cores; a count above the cores runs on the
    cores); the result is the same for any count.
    Sites outside the domain or repeating an earlier site (their cells are empty) give a
    :class:`SiteWarning` naming how many and the first index.
    Returns :class:`Cells`."""
    d = domain2(domain)
    s = _sites(sites, 2)
    rho = _vectorized(density, vectorized)
    r = _core.clip2d(d, s, rho, geometry, neighbors, callback, _threads(threads))
    _warn_sites("clip2d", r)
    return Cells(2, s, r, lambda: _core.clip2d(d, s, rho, False, True, callback,
                                                      _threads(threads)))


def clip3d(domain, sites, density=None, *, geometry: bool = False, neighbors: bool = False,
           callback: Optional[Callable[[dict], object]] = None,
           threads: Optional[int] = None, vectorized: bool = False) -> Cells:
    """The Voronoi diagram of ``sites`` ((n, 3) array, n >= 1: one site, sites on a line
    or in a plane too) clipped to the volume of a
    3D domain (anything :func:`domain3` takes: a surface, a tet mesh, a file, a
    meshio.Mesh). Inner cells come from the Delaunay triangulation; boundary cells are
    clipped by the surface exactly.

    ``density``: None (1), a number, a callable ``rho(x, y, z)`` (finite and positive on
    every cell that meets the volume; ``vectorized=True``: it takes arrays ``x, y, z`` and is
    called with a few thousand points at a time, as :func:`clip2d`), or one value per vertex
    of the domain's tet mesh (linear per tet). ``geometry``: also the faces of every cell (with the site across each
    face); ``neighbors``: the neighbour lists (both cost a few times the plain call; without
    them ``neighbors`` is computed on first access). ``callback(info)`` and Ctrl-C: as
    :func:`clip2d` (phases 'delaunay', 'surface', 'boundary cells', 'inner cells',
    'geometry').
    ``threads``: TBB threads (None or 0: all cores; a count above the cores runs on the
    cores); the result is the same for any count.
    Sites outside the domain or repeating an earlier site: a :class:`SiteWarning`, as
    :func:`clip2d`.
    Returns :class:`Cells` (``seconds``: the phases' wall times)."""
    d = domain3(domain)
    s = _sites(sites, 3)
    rho = _vectorized(density, vectorized)
    r = _core.clip3d(d, s, rho, geometry, neighbors, callback, _threads(threads))
    _warn_sites("clip3d", r)
    return Cells(3, s, r, lambda: _core.clip3d(d, s, rho, False, True, callback,
                                                      _threads(threads)))


def _is_2d_domain(domain) -> bool:
    if isinstance(domain, _core.Domain2):
        return True
    if isinstance(domain, str) and domain.startswith(("annulus:", "square-holes:")):
        return True
    if isinstance(domain, (str, os.PathLike)):
        name = os.fspath(domain).lower()
        if name.endswith(".gz"):
            name = name[:-3]
        return name.endswith((".json", ".poly"))
    return False


def random_points(domain, n: int, seed: int = 1, density=None, *,
                  threads: Optional[int] = None, vectorized: bool = False) -> np.ndarray:
    """Points strictly inside a domain, drawn independently with density ``density``,
    decided inside exactly:

    * 3D, (n, 3): a domain :func:`domain3` takes; ``density`` None (uniform), a callable
      rho(x, y, z) or one value per vertex of the domain's tet mesh;
    * 2D, (n, 2): a :class:`Domain2` (from :func:`domain2`), a ``.json`` / ``.poly``
      path or a generator (``"annulus:1,2,64"``); ``density`` None (uniform), a callable rho(x, y) or a grid tuple, as
      :func:`clip2d` takes it.

    ``vectorized``: the callable takes arrays, as :func:`clip2d` (called one point at a
    time here). A density is drawn by rejection against twice the largest value among the first
    max(1024, min(n, 65536)) uniform points. The library's generator (std::mt19937_64(seed),
    turned into doubles bit by bit): the same points on every platform, and, uniform, the
    CLI's ``--random n --seed seed`` sites (with a density, the CLI's ``cvt2d``/``cvt3d``
    draw with rho^(1/2) / rho^(3/5), the CVT's site density: pass that to get theirs)."""
    rho = _vectorized(density, vectorized)
    if _is_2d_domain(domain):
        return _core.random_points2(domain2(domain), n, seed, rho)
    return _core.random_points3(domain3(domain), n, seed, rho, _threads(threads))


class CvtResult(NamedTuple):
    """The outcome of a CVT optimisation.

    ``sites`` (n, d) the optimised sites; ``energy_history`` / ``gradient_history``: the
    energy and gradient norm at iteration 0 (start) and after every iteration;
    ``iterations``, ``evaluations`` (clipped diagrams computed), ``energy`` (final),
    ``gradient_norm``, ``initial_gradient_norm``, ``converged`` (|g| <= tolerance |g0|),
    ``cancelled`` (the callback returned False), ``seconds``, ``stop``: why it stopped, the
    CLI's words: 'converged', 'iteration budget', 'no progress' (L-BFGS: the line search
    found no lower energy at the energy's precision; the best sites so far) or
    'cancelled'."""

    sites: np.ndarray
    energy_history: np.ndarray
    gradient_history: np.ndarray
    iterations: int
    evaluations: int
    energy: float
    gradient_norm: float
    initial_gradient_norm: float
    converged: bool
    cancelled: bool
    seconds: float
    stop: str


def _number(tolerance) -> float:
    try:
        return float(tolerance)
    except (TypeError, ValueError):
        raise Error(f"tolerance: expected a number, got {tolerance!r}") from None


def _cvt_result(r: dict) -> CvtResult:
    return CvtResult(*(r[k] for k in CvtResult._fields))


def cvt2d(domain, sites, method: str = "lbfgs", iterations: int = 1000, tolerance: float = 1e-4,
          density=None, callback: Optional[Callable[[dict], object]] = None, *,
          threads: Optional[int] = None, vectorized: bool = False) -> CvtResult:
    """Centroidal Voronoi tessellation in a polygonal domain: minimises the CVT energy
    (sum of the cells' energies) from ``sites`` ((n, 2), n >= 1, not modified) by ``method``
    'lbfgs' (L-BFGS-B) or 'lloyd', for at most ``iterations`` iterations or until
    |gradient| <= ``tolerance`` x |initial gradient|. ``density`` and ``vectorized``: as
    :func:`clip2d` (a density's CVT: the sites' spacing about rho^(-1/4) in 2D, rho^(-1/5)
    in 3D). ``callback(info)``: called at the start
    and after every iteration with a dict (iteration, energy, gradient_norm, seconds);
    returning False stops (``cancelled``). Ctrl-C stops the run and raises
    KeyboardInterrupt. Deterministic for any ``threads``."""
    r = _core.cvt2d(domain2(domain), _sites(sites, 2), method, iterations, _number(tolerance),
                    _vectorized(density, vectorized), callback, _threads(threads))
    return _cvt_result(r)


def cvt3d(domain, sites, method: str = "lbfgs", iterations: int = 1000, tolerance: float = 1e-4,
          density=None, callback: Optional[Callable[[dict], object]] = None, *,
          threads: Optional[int] = None, vectorized: bool = False) -> CvtResult:
    """Centroidal Voronoi tessellation in a 3D volume; as :func:`cvt2d` with (n, 3)
    sites, n >= 1 (one site, sites on a line or in a plane too); ``density`` and
    ``vectorized`` as :func:`clip3d`."""
    r = _core.cvt3d(domain3(domain), _sites(sites, 3), method, iterations, _number(tolerance),
                    _vectorized(density, vectorized), callback, _threads(threads))
    return _cvt_result(r)


class Mesh:
    """A triangle (2D) or tetrahedral (3D) mesh made by :func:`mesh2d` / :func:`mesh3d`.

    * ``points`` (n, d) float64; ``cells`` (m, d + 1) int32 vertex indices (2D triangles
      counter-clockwise; 3D tets with det(p1 - p0, p2 - p0, p3 - p0) > 0, exactly);
    * ``vertex_kind`` (n,) uint8: 2D 0 interior, 1 sliding on the boundary, 2 fixed;
      3D 0 interior, 1 surface, 2 feature line, 3 corner;
    * 3D: ``boundary_triangles`` (k, 3) outward, ``boundary_tags`` (k,) patch tags,
      ``interface_triangles`` (j, 3), ``interface_tags`` (j,) (the interfaces between
      regions the mesh follows: outward from the lower region tag; else empty),
      ``cell_tags`` (m,) region tags, ``tag_names`` [(dimension, tag, name)],
      ``shape_problem`` ('' when the boundary has the domain's shape);
      2D: ``vertex_domain``, ``vertex_edge`` (the domain vertex / edge a boundary vertex
      lies on, -1 if none), ``boundary_edges`` (k, 2) int32 (the domain on their left),
      ``boundary_tags`` (k,) (the .poly segment marker of their side, else their ring's
      tag: 1 outer, 2, 3, ... holes; several polygons: 1, 2, ... over all rings in order,
      each exterior then its holes), ``cell_tags`` (m,) (the .poly regional attribute,
      else the polygon's number from 1);
    * ``stats``: a dict of the pipeline's figures (sites, iterations, energy, seconds...);
      3D also the dihedral verdict: ``input_sharpest_dihedral_deg`` (alpha, the smallest
      angle inside the volume between two boundary triangles sharing an edge),
      ``dihedral_bound_deg`` (min(20, alpha / 2)) and ``tets_below_dihedral_bound``.
    """

    def __init__(self, dim: int, r: dict):
        self.dim = dim
        self.points = r["points"]
        self.cells = r["triangles"] if dim == 2 else r["tets"]
        self.vertex_kind = r["vertex_kind"]
        self.stats = r["stats"]
        if dim == 2:
            self.vertex_domain = r["vertex_domain"]
            self.vertex_edge = r["vertex_edge"]
            self.boundary_edges = r["boundary_edges"]
            self.boundary_tags = r["boundary_tags"]
            self.cell_tags = r["triangle_regions"]
        else:
            self.boundary_triangles = r["boundary_triangles"]
            self.boundary_tags = r["boundary_tags"]
            self.interface_triangles = r["interface_triangles"]
            self.interface_tags = r["interface_tags"]
            self.cell_tags = r["tet_tags"]
            self.tag_names = r["tag_names"]
            self.shape_problem = r["shape_problem"]

    def __repr__(self) -> str:
        kind = "triangles" if self.dim == 2 else "tets"
        return f"<voroclip.Mesh: {len(self.points)} vertices, {len(self.cells)} {kind}>"

    def _named_tags(self):
        # [(dimension, tag, name)] of every tag the mesh uses, with the names its Gmsh files
        # carry: 3D tag_names (the input's names, else "patch <tag>" / "region <tag>"), 2D
        # those of the library's 2D writer ("boundary <tag>", "region <tag>").
        if self.dim == 3:
            return [(int(d), int(t), str(n)) for d, t, n in self.tag_names]
        return ([(1, t, f"boundary {t}") for t in np.unique(self.boundary_tags).tolist()] +
                [(2, t, f"region {t}") for t in np.unique(self.cell_tags).tolist()])

    def to_meshio(self, tags: str = "gmsh"):
        """A ``meshio.Mesh``: 2D triangles (z = 0 added, as meshio's writers expect) and
        boundary edges, or 3D tets and boundary (then interface) triangles, with the region /
        patch tags as cell data and the tags' names as ``field_data`` (``{name: array([tag,
        dimension])}``, as meshio's Gmsh reader gives them; the names of :meth:`write`'s
        Gmsh files: 3D ``tag_names``, 2D ``boundary <tag>`` and ``region <tag>``).

        ``tags="gmsh"``: ``gmsh:physical`` and ``gmsh:geometrical`` cell data, one cell block
        per element type and tag (cells in increasing tag order, in the mesh's order within a
        tag), and ``point_data["gmsh:dim_tags"]`` (each point's (dimension, tag) entity: a
        point of the boundary that of a boundary element, else that of a cell), which is
        what ``meshio.write(..., file_format="gmsh")`` (Gmsh 4.1) needs; ``"gmsh22"`` works
        too. ``"medit"``: one block per element type and ``medit:ref`` (Medit .mesh).
        Note: meshio reads and writes ``.msh`` as ANSYS unless told ``file_format="gmsh"``
        (or ``"gmsh22"``); :meth:`write` uses the library's Gmsh writer."""
        import meshio

        if tags not in ("gmsh", "medit"):
            raise Error(f"tags: expected 'gmsh' or 'medit', got {tags!r}")
        if self.dim == 2:
            points = np.column_stack([self.points, np.zeros(len(self.points))])
            parts = [("triangle", 2, self.cells, self.cell_tags),
                     ("line", 1, self.boundary_edges, self.boundary_tags)]
        else:
            points = self.points
            parts = [("tetra", 3, self.cells, self.cell_tags),
                     ("triangle", 2, np.vstack([self.boundary_triangles, self.interface_triangles]),
                      np.concatenate([self.boundary_tags, self.interface_tags]))]
        field_data = {name: np.array([tag, dim]) for dim, tag, name in self._named_tags()}
        if tags == "medit":
            return meshio.Mesh(points, [(kind, cells) for kind, _, cells, _ in parts],
                               cell_data={"medit:ref": [t for *_, t in parts]},
                               field_data=field_data)
        # Gmsh 4.1 keeps the physical tag per entity, not per element (meshio's writer takes
        # each block's first): one block, one entity, per (dimension, tag).
        blocks, physical = [], []
        dim_tags = np.full((len(points), 2), -1, dtype=np.int64)
        for kind, dim, cells, cell_tags in parts:  # cells first: the boundary's overwrite
            cell_tags = np.asarray(cell_tags)
            order = np.argsort(cell_tags, kind="stable")
            bounds = np.flatnonzero(np.diff(cell_tags[order])) + 1
            for run in np.split(order, bounds) if len(order) else []:
                tag = int(cell_tags[run[0]])
                blocks.append((kind, cells[run]))
                physical.append(np.full(len(run), tag, dtype=np.int64))
                dim_tags[cells[run].ravel()] = (dim, tag)
        if blocks:  # a point of no cell (none in the meshes made here): the first entity
            dim_tags[dim_tags[:, 0] < 0] = (parts[0][1], physical[0][0])
        return meshio.Mesh(points, blocks,
                           cell_data={"gmsh:physical": physical,
                                      "gmsh:geometrical": [p.copy() for p in physical]},
                           point_data={"gmsh:dim_tags": dim_tags}, field_data=field_data)

    def write(self, path, binary: bool = False, compress: bool = False,
              msh_version: str = "4.1", **kwargs) -> None:
        """Writes the mesh, the format from the extension.

        The library's own writers, the ones the CLI uses (the same mesh gives the same
        bytes as ``voroclip mesh3d -o`` / ``mesh2d -o``): 3D ``.msh`` (Gmsh 4.1 or 2.2;
        ``binary=True``: binary 4.1), ``.mesh`` (Medit), ``.node``/``.ele`` (TetGen:
        ``.node``, ``.ele`` and ``.face``), ``.vtk`` (legacy ASCII) and ``.vtu`` (base64
        binary; ``compress=True``: zlib; with the CLI's ``q1_min_dihedral_deg``): tets, the
        boundary triangles, region / patch tags and, in Gmsh files, the tag names. 2D
        ``.msh``, ``.mesh`` and ``.vtu`` (ASCII; ``binary=True``: base64, ``compress=True``:
        zlib, as mesh2d's ``--binary`` / ``--compress``): triangles, boundary edges, their
        tags and the vertex kinds. ``msh_version``: ``"4.1"`` (the default) or ``"2.2"``, as the
        CLI's ``--msh-version`` (2D and 3D; 2.2 is ASCII: not with ``binary=True``; another
        value, or ``"2.2"`` for another extension, raises :class:`Error`). Other
        extensions go through meshio (``kwargs`` go to ``meshio.write``, the tags as
        :meth:`to_meshio` names them)."""
        import os

        name = str(os.fspath(path)).lower()
        ext = os.path.splitext(name)[1]
        if msh_version not in ("4.1", "2.2"):
            raise Error(f"write: msh_version: expected '4.1' or '2.2', got {msh_version!r}")
        if msh_version != "4.1" and ext != ".msh":
            raise Error(f"write: msh_version={msh_version!r}: only a .msh file (Gmsh) has a "
                        f"format version, got {ext or 'no extension'}")
        if self.dim == 3 and ext in (".msh", ".mesh", ".node", ".ele", ".vtk", ".vtu"):
            if kwargs:
                raise Error(f"write: {sorted(kwargs)}: meshio options, not taken by {ext}")
            if binary and ext != ".msh":
                raise Error(f"write: binary=True: {ext} has no binary variant here (.msh has)")
            if compress and ext != ".vtu":
                raise Error(f"write: compress=True: {ext} has no compressed variant (.vtu has)")
            if binary and msh_version == "2.2":
                raise Error("write: binary=True: Gmsh 2.2 is written in ASCII here (binary is "
                            "4.1's)")
            msh = "msh22" if msh_version == "2.2" else "msh-binary" if binary else "msh"
            fmt = {".msh": msh, ".mesh": "mesh", ".node": "tetgen",
                   ".ele": "tetgen", ".vtk": "vtk", ".vtu": "vtu-zlib" if compress else "vtu"}[ext]
            _core.write_tet_mesh(os.fspath(path), self.points, self.cells,
                                 np.vstack([self.boundary_triangles, self.interface_triangles]),
                                 np.concatenate([self.boundary_tags, self.interface_tags]),
                                 self.cell_tags, list(self.tag_names), fmt)
            return
        if self.dim == 2 and ext in (".msh", ".mesh", ".vtu"):
            if kwargs or ((binary or compress) and ext != ".vtu"):
                raise Error(f"write: {ext} of a 2D mesh takes no options but msh_version "
                            "(binary and compress: .vtu only)")
            vtu = "vtu-zlib" if compress else "vtu-binary" if binary else "vtu"
            fmt = {".msh": "msh" if msh_version == "4.1" else "msh22", ".mesh": "mesh",
                   ".vtu": vtu}[ext]
            _core.write_mesh2(os.fspath(path), self.points, self.cells, self.vertex_kind,
                              self.boundary_edges, self.boundary_tags, self.cell_tags, fmt)
            return
        if binary or compress:
            raise Error("write: binary/compress: for the library's formats only")
        if name.endswith(".msh"):
            kwargs.setdefault("file_format", "gmsh22")
            kwargs.setdefault("binary", False)
        self.to_meshio("medit" if name.endswith(".mesh") else "gmsh").write(path, **kwargs)


def _given(**options) -> dict:
    return {k: v for k, v in options.items() if v is not None}


def mesh2d(domain, vertices: Optional[int] = None, edge_length: Optional[float] = None, *,
           density=None, sizing=None, callback: Optional[Callable[[dict], object]] = None,
           threads: Optional[int] = None, vectorized: bool = False, **options) -> Mesh:
    """A CVT triangle mesh of a polygonal domain (anything :func:`domain2` takes) of about
    ``vertices`` vertices, or with edge length ``edge_length`` (L) far from small features;
    give exactly one (both raise :class:`Error`, as the CLI), or neither with ``sizing``.
    Other options, by name, as mesh.h's Mesh2Options (an option not given keeps
    the library's default, so Python and the CLI agree): ``gradation``, ``corner_angle``,
    ``sharp_angle``, ``repair_angle`` (degrees), ``fix_input_vertices``, ``keep_gaps``,
    ``conforming`` (False: the paper's circumcentre rule instead of the conforming mesh),
    ``seed``, ``method`` ('lbfgs' | 'lloyd'), ``unconstrained_iterations``,
    ``constrained_iterations``, ``unconstrained_tolerance``, ``constrained_tolerance``,
    ``repair_rounds``, ``repair_iterations``, ``mean_angle_target`` (degrees, default 53;
    0: none), ``exact_vertices`` (keep the count when the mean smallest angle misses the
    target; by default the domain is meshed again with more vertices, at most
    ``max_mean_angle_runs`` (3) times:
    ``stats['mean_angle_raise']`` says why and by how much); an unknown name raises
    :class:`Error`.
    ``density`` and ``vectorized``: as :func:`clip2d`. ``sizing``: a target edge length h
    (L), as the CLI's ``--sizing``: a number or a callable ``h(x, y)`` (rho = h^-4; not with
    ``density`` or ``edge_length``); without ``vertices``, h is in model units and sets the
    count; with it, only h's shape counts. ``callback(info)`` gets phase, iteration, energy,
    gradient_norm, seconds (and ``retry_vertices`` before a run with more vertices); returning False stops early (a valid mesh of lower quality;
    ``stats['cancelled']``); Ctrl-C raises KeyboardInterrupt. The same mesh for any
    ``threads``."""
    r = _core.mesh2d(domain2(domain), _given(vertices=vertices, edge_length=edge_length,
                                             **options),
                     _vectorized(density, vectorized), _vectorized(sizing, vectorized), callback,
                     _threads(threads))
    return Mesh(2, r)


def mesh3d(domain, vertices: Optional[int] = None, *, density=None, sizing=None,
           callback: Optional[Callable[[dict], object]] = None, threads: Optional[int] = None,
           vectorized: bool = False, **options) -> Mesh:
    """A CVT tetrahedral mesh of a 3D domain (anything :func:`domain3` takes) of about
    ``vertices`` vertices (library default 10000): sharp features kept, the boundary's
    topology resolved, slivers perturbed away. The size, as the CLI's ``--density`` and
    ``--sizing``: ``density`` a number or a callable ``rho(x, y, z)`` (elements of size
    about rho^(-1/5), scaled to ``vertices``), or ``sizing`` a target edge length h, a number
    or a callable ``h(x, y, z)`` (rho = h^-5): without ``vertices``, h is in model units and
    sets the count; with it, only h's shape counts. Callables run on worker threads under
    the GIL, point by point: slow beyond a few thousand vertices, unless ``vectorized=True``
    (the callable takes float64 arrays ``x, y, z`` of shape (k,) and returns k values, or one
    number; the CVT's integrals call it with a few thousand points at a time). A value
    that is not finite and positive raises :class:`Error` naming the point. Other options, by name, as mesh.h's
    Mesh3Options (an option not given keeps the library's default): ``adaptive``,
    ``lfs_cap`` (the uniform spacing's cap in local feature sizes; 0, the default: none;
    both sized by each region's own boundary, its interfaces included, when the regions of a
    tet mesh are followed),
    ``facet_distance`` (a site fixed at each input vertex farther than this times the
    spacing from the mesh's boundary; 0, the default: none),
    ``features``, ``feature_angle`` (degrees), ``min_feature_length``, ``sampling``
    ('lattice' | 'random'), ``seed``, ``unconstrained_iterations``,
    ``constrained_iterations``, ``gradient_tolerance``, ``smooth_surface``,
    ``smooth_shape``, ``exact_vertices``, ``max_topology_rounds``, ``max_topology_sites``
    (the topology phase adds at most this many times the vertices, default 4; stats
    ``topology_capped`` and ``topology_capped_near``, the point near the first defect left,
    or None),
    ``max_boundary_distance`` (the mesh's boundary at most this many local edge lengths from
    the input's surface, default 1, else ``shape_problem`` says where; 0: not checked; stats
    ``hausdorff``, ``hausdorff_rel`` (of the bounding box's diagonal) and
    ``hausdorff_to_edge_length``), ``perturb``,
    ``sliver_angle`` (degrees), ``flip_angle`` (degrees: the last flips, moves and
    insertions against the tets below it; 0: none, the mesh stays Delaunay when
    ``mean_rounds`` is 0 too; stats ``flips``, ``flip_moves``, ``flip_sites``,
    ``boundary_flips``), ``mean_rounds`` (the
    rounds of flips and moves for the mean smallest dihedral angle after them, default 3; 0:
    none; stats ``mean_flips``, ``mean_moves``, ``mean_rounds``, ``mean_q1_before_deg``,
    ``mean_q1_after_deg``, ``mean_seconds``); an unknown name raises :class:`Error`.
    Tags: the input's (tet mesh files) or one patch per surface region between feature
    lines and one region per volume component. A tet mesh's regions that are volumes of their
    own have their interfaces followed (``interface_triangles``, ``interface_tags``; stats
    ``region_interfaces_followed``, ``region_interfaces_not_followed``: why not,
    ``tets_across_region_interfaces``). A domain of several bodies (outer shells, each
    with its cavities) has each meshed on its own, with its share of the vertices, patches
    numbered body after body. ``callback(info)`` gets phase, iteration, energy, ... (and,
    with several bodies, ``body``, ``nb_bodies``, and ``body_vertices`` once at the start of
    each; with ``sizing`` and no ``vertices``, ``implied_vertices`` once before anything
    else: the vertex count the size asks for); returning
    False stops (no tets, ``stats['cancelled']``); Ctrl-C raises KeyboardInterrupt. The
    same mesh for any ``threads`` and a given ``seed``."""
    r = _core.mesh3d(domain3(domain), _given(vertices=vertices, **options),
                     _vectorized(density, vectorized), _vectorized(sizing, vectorized),
                     callback, _threads(threads))
    return Mesh(3, r)


class Quality(NamedTuple):
    """Element quality. 3D: per tet ``q1`` (smallest dihedral angle, degrees), ``q2``
    (largest, degrees), ``q3`` (3 r_in / r_circ), ``q4`` (12 (9 V^2)^(1/3) / sum of squared
    edge lengths), ``volume`` (signed, L^3), ``dihedral`` (m, 6) degrees. 2D: per triangle
    ``q1`` smallest and ``q2`` largest angle (degrees), ``q3`` 2 r_in / r_circ, ``q4`` None,
    ``volume`` signed area. ``report``: the library's summary (the CLI's ``quality --stats
    json`` figures: min/mean/max, histograms, inverted and degenerate elements)."""

    q1: np.ndarray
    q2: np.ndarray
    q3: np.ndarray
    q4: Optional[np.ndarray]
    volume: np.ndarray
    dihedral: Optional[np.ndarray]
    report: dict


def _triangle_measures(points, triangles):
    p = points[triangles]  # (m, 3, 2)
    e = [p[:, (k + 2) % 3] - p[:, (k + 1) % 3] for k in range(3)]  # edge opposite k
    length = np.stack([np.hypot(v[:, 0], v[:, 1]) for v in e], axis=1)
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - \
            (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    angles = []
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        angles.append(np.degrees(np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]),
                                            (u * v).sum(axis=1))))
    angles = np.stack(angles, axis=1)
    a, b, c = length[:, 0], length[:, 1], length[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(cross != 0, 4 * cross ** 2 / (a * b * c * (a + b + c)), 0.0)
    return angles.min(axis=1), angles.max(axis=1), ratio, cross / 2


def quality(mesh, cells=None, *, threads: Optional[int] = None) -> Quality:
    """The quality of a tet mesh or a triangle mesh: a :class:`Mesh`, a meshio.Mesh, or
    ``(points, cells)`` with (m, 4) tets or (m, 3) triangles. Returns :class:`Quality`
    (the same for any ``threads``)."""
    if cells is not None:
        points = mesh
    elif isinstance(mesh, Mesh):
        points, cells = mesh.points, mesh.cells
    elif hasattr(mesh, "points") and hasattr(mesh, "cells"):
        points = mesh.points
        blocks = [b.data for b in mesh.cells if b.type == "tetra"] or \
                 [b.data for b in mesh.cells if b.type == "triangle"]
        if not blocks:
            raise Error("quality: the meshio.Mesh has neither tetra nor triangle cells")
        cells = np.concatenate(blocks)
    else:
        points, cells = mesh
    try:
        points = np.ascontiguousarray(points, dtype=np.float64)
        cells = np.ascontiguousarray(cells, dtype=np.int64)
    except (TypeError, ValueError) as e:
        raise Error(f"quality: expected arrays of points and vertex indices ({e})") from None
    if cells.ndim == 2 and cells.shape[1] == 4:
        r = _core.tet_quality(points, cells, _threads(threads))
        return Quality(r["q1"], r["q2"], r["q3"], r["q4"], r["volume"], r["dihedral"],
                       json.loads(r["report_json"]))
    if cells.ndim == 2 and cells.shape[1] == 3:
        if points.ndim == 2 and points.shape[1] == 3:
            points = np.ascontiguousarray(points[:, :2])
        r = _core.triangle_quality(points, cells)
        q1, q2, q3, area = _triangle_measures(points, cells)
        return Quality(q1, q2, q3, None, area, None, json.loads(r["report_json"]))
    raise Error(f"quality: expected (m, 4) tets or (m, 3) triangles, got shape {cells.shape}")
