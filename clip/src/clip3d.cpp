// The 3D clipped Voronoi diagram: Yan, Wang, Lévy & Liu, "Efficient computation of
// clipped Voronoi diagram for mesh generation", CAD 2011, section 4.
//
// 1. Restricted surface (sec. 4.1). A FIFO of (boundary triangle, cell) pairs, seeded for
//    every triangle no pair has reached yet by the cell of one of its vertices (nearest
//    site, then a descent over Voronoi neighbours with the perturbed side test). A popped
//    pair clips the triangle by the cell's bisectors; an edge of the clipped polygon on a
//    triangle edge pushes the neighbouring triangle with the same cell, an edge on
//    bisector(c, k) pushes the triangle with cell k; each pair is pushed once. Cells with
//    a non-empty restricted polygon are the boundary cells.
// 2. Boundary cells (sec. 4.2), independently and in parallel: a FIFO of tets seeded by
//    the tets of the cell's boundary triangles; each tet is clipped by the cell's
//    bisectors, and a non-empty piece pushes the tets across the tet facets it still
//    touches. Every connected piece of cell ∩ volume touches the boundary (a piece that
//    did not would be the whole convex cell), so this reaches all of them.
// 3. Other cells are wholly inside or outside: a boundary cell marks a neighbour inside
//    when one of its pieces has a face on their bisector; union-find over Delaunay edges
//    spreads the marks when some are outside. Inner cells are integrated straight from
//    the Delaunay triangulation by the signed circumcentric decomposition: the Voronoi
//    cell of v is the signed sum over flags (v ∈ edge e ⊂ face f ⊂ tet t) of the
//    tetrahedra (v, c_e, c_f, c_t) (circumcentres), exact for a Delaunay triangulation
//    whatever the shape of its tets.
//
// Clipping kernel. A convex polyhedron (or polygon) is kept as faces listing vertices, and
// every vertex as the three planes that define it, among the four facets of the current
// tet and the bisectors of the cell's site with its neighbours. The kind of a vertex
// follows from how many of its planes are tet facets: 3, a mesh vertex; 2, a mesh edge ∩
// a bisector; 1, a mesh facet ∩ two bisectors; 0, a Voronoi vertex. "Which side of
// bisector(i, j)" is one exact predicate per kind (predicates.h, with the perturbation of
// insphere_sos), so clipping never meets a tie: sites on the boundary (the paper's
// Fig. 10) and bisectors through mesh edges (Fig. 11) need no special case. Coordinates
// are computed for integration only, each from the vertex's sorted global ids, so cells
// sharing a vertex compute the same bits.
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <string>
#include <unordered_set>
#include <vector>

#include "voroclip/clip.h"

namespace voroclip {

namespace clip3 {

constexpr std::uint32_t kNone = 0xffffffffu;

// A plane of a clip: facet f (0..3) of the current tet is -(f + 1); the bisector of the
// cell's site and site k is k.
using Plane = std::int32_t;
inline bool is_facet(Plane p) { return p < 0; }
inline int facet_of(Plane p) { return -p - 1; }
inline Plane facet_plane(int f) { return -(f + 1); }

struct PVertex {
  Plane p[3];
};

// A convex polyhedron (several faces) or polygon (one face). Face k lies on plane
// face_plane[k] and has the vertices face_verts[face_begin[k] .. face_begin[k + 1]).
// Faces are oriented consistently (adjacent faces run through a shared edge in opposite
// directions): the tet's facets as in Domain3::kTetFacetVertex.
struct Poly {
  std::vector<PVertex> verts;
  std::vector<Plane> face_plane;
  std::vector<std::uint32_t> face_begin{0};
  std::vector<std::uint32_t> face_verts;

  void clear() {
    verts.clear();
    face_plane.clear();
    face_begin.assign(1, 0);
    face_verts.clear();
  }
  std::uint32_t nb_faces() const { return static_cast<std::uint32_t>(face_plane.size()); }
  bool empty() const { return face_plane.empty(); }
};

// Insertion sort of a few ids (std::sort on tiny arrays trips -Warray-bounds in GCC 12).
inline void small_sort(std::uint32_t* a, int n) {
  for (int k = 1; k < n; ++k) {
    for (int q = k; q > 0 && a[q - 1] > a[q]; --q) std::swap(a[q - 1], a[q]);
  }
}

// The two planes shared by vertices u and w (adjacent along an edge) other than `face`.
Plane other_common_plane(const PVertex& u, const PVertex& w, Plane face) {
  for (const Plane a : u.p) {
    if (a == face) continue;
    for (const Plane b : w.p) {
      if (a == b) return a;
    }
  }
  throw Error("clip3d: internal error: an edge whose ends share one plane");
}

}  // namespace clip3

using namespace clip3;

struct Clip3Impl {
  const Domain3& domain;
  const Delaunay3& dt;
  const Clip3Options& options;
  ClippedVoronoi3& out;
  Clip3Impl(const Domain3& d, const Delaunay3& t, const Clip3Options& o, ClippedVoronoi3& r)
      : domain(d), dt(t), options(o), out(r) {}

  std::uint32_t n = 0;
  // Restricted surface: per boundary cell, the boundary triangles it meets (CSR).
  std::vector<std::uint32_t> cell_tri_begin, cell_tris;
  std::vector<double> surface_area;  // per site
  std::vector<std::uint32_t> boundary_cells;
  // Integrals relative to the site: volume, first moment, ∫|x - site|^2.
  struct Moments {
    double volume = 0, mass = 0, energy = 0, moment[3] = {0, 0, 0};
  };
  bool linear_density = false;
  struct CellOut : Moments {
    std::vector<std::uint32_t> walked;  // neighbours with a face of some piece
    std::uint64_t pairs = 0;
    std::vector<std::uint32_t> face_begin{0};
    std::vector<std::uint32_t> face_piece;
    std::vector<double> face_xyz;
  };
  std::vector<CellOut> cell_out;
  std::vector<std::int8_t> status;

  const double* site(std::uint32_t i) const { return dt.point(i); }

  // ---- Exact side of a vertex of a clip in tet t of cell i, with respect to
  // bisector(i, j): POSITIVE when on j's side (clipped away).
  Sign side(const PVertex& v, std::uint32_t t, std::uint32_t i, std::uint32_t j) const {
    int facets[3], nf = 0;
    std::uint32_t sites[3];
    int ns = 0;
    for (const Plane p : v.p) {
      if (is_facet(p)) {
        facets[nf++] = facet_of(p);
      } else {
        sites[ns++] = static_cast<std::uint32_t>(p);
      }
    }
    const double* pi = site(i);
    const double* pj = site(j);
    int others[4], no = 0;  // tet-local vertices not opposite a facet plane of v
    for (int k = 0; k < 4; ++k) {
      bool used = false;
      for (int q = 0; q < nf; ++q) used = used || facets[q] == k;
      if (!used) others[no++] = k;
    }
    const auto mv = [&](int local) { return domain.vertex(domain.tet_vertex(t, local)); };
    switch (nf) {
      case 3:
        return bisector_side_vertex3d(pi, pj, mv(others[0]), i, j);
      case 2:
        return bisector_side_edge3d(pi, site(sites[0]), pj, mv(others[0]), mv(others[1]), i,
                                    sites[0], j);
      case 1:
        return bisector_side_facet3d(pi, site(sites[0]), site(sites[1]), pj, mv(others[0]),
                                     mv(others[1]), mv(others[2]), i, sites[0], sites[1], j);
      default:
        return bisector_side_voronoi3d(pi, site(sites[0]), site(sites[1]), site(sites[2]), pj, i,
                                       sites[0], sites[1], sites[2], j);
    }
  }

  // ---- Coordinates of a vertex, from its sorted global ids (bit-identical in every cell).
  void coords(const PVertex& v, std::uint32_t t, std::uint32_t i, double* x) const {
    std::uint32_t mesh[4], sites[4];
    int nm = 0, ns = 0;
    bool facet_used[4] = {false, false, false, false};
    for (const Plane p : v.p) {
      if (is_facet(p)) {
        facet_used[facet_of(p)] = true;
      } else {
        sites[ns++] = static_cast<std::uint32_t>(p);
      }
    }
    for (int k = 0; k < 4; ++k) {
      if (!facet_used[k]) mesh[nm++] = domain.tet_vertex(t, k);
    }
    sites[ns++] = i;
    small_sort(mesh, nm);
    small_sort(sites, ns);
    // F(x) = |x - p|^2 - |x - q|^2 relative to the midpoint: 2 (x - m).(q - p).
    const auto F = [&](const double* a, std::uint32_t s0, std::uint32_t s1) {
      const double* p = site(s0);
      const double* q = site(s1);
      double f = 0;
      for (int c = 0; c < 3; ++c) f += (a[c] - 0.5 * (p[c] + q[c])) * (q[c] - p[c]);
      return f;
    };
    if (ns == 1) {  // a mesh vertex (nm == 1)
      const double* a = domain.vertex(mesh[0]);
      x[0] = a[0];
      x[1] = a[1];
      x[2] = a[2];
      return;
    }
    if (ns == 2) {  // mesh edge ∩ bisector(sites[0], sites[1])
      const double* a = domain.vertex(mesh[0]);
      const double* b = domain.vertex(mesh[1]);
      const double fa = F(a, sites[0], sites[1]), fb = F(b, sites[0], sites[1]);
      double s = fa / (fa - fb);
      if (!(s >= 0)) s = 0;
      if (s > 1) s = 1;
      for (int c = 0; c < 3; ++c) x[c] = a[c] + s * (b[c] - a[c]);
      return;
    }
    if (ns == 3) {  // mesh facet ∩ bisectors (s0, s1), (s0, s2)
      const double* a = domain.vertex(mesh[0]);
      const double* b = domain.vertex(mesh[1]);
      const double* c = domain.vertex(mesh[2]);
      const double k0 = F(a, sites[0], sites[1]), k1 = F(b, sites[0], sites[1]),
                   k2 = F(c, sites[0], sites[1]);
      const double l0 = F(a, sites[0], sites[2]), l1 = F(b, sites[0], sites[2]),
                   l2 = F(c, sites[0], sites[2]);
      // Barycentric coordinates: [1 1 1; k; l] lambda = (1, 0, 0).
      const double ca = k1 * l2 - k2 * l1, cb = k2 * l0 - k0 * l2, cc = k0 * l1 - k1 * l0;
      const double d = ca + cb + cc;
      double la = ca / d, lb = cb / d, lc = cc / d;
      if (!std::isfinite(la) || !std::isfinite(lb) || !std::isfinite(lc)) la = lb = lc = 1.0 / 3;
      for (int q = 0; q < 3; ++q) x[q] = la * a[q] + lb * b[q] + lc * c[q];
      return;
    }
    // The circumcentre of the four sites.
    const double* p0 = site(sites[0]);
    double r[3][3], w[3];
    for (int k = 0; k < 3; ++k) {
      const double* pk = site(sites[k + 1]);
      for (int c = 0; c < 3; ++c) r[k][c] = pk[c] - p0[c];
      w[k] = 0.5 * (r[k][0] * r[k][0] + r[k][1] * r[k][1] + r[k][2] * r[k][2]);
    }
    const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                       r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                       r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    const double ux = w[0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                      r[0][1] * (w[1] * r[2][2] - r[1][2] * w[2]) +
                      r[0][2] * (w[1] * r[2][1] - r[1][1] * w[2]);
    const double uy = r[0][0] * (w[1] * r[2][2] - r[1][2] * w[2]) -
                      w[0] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                      r[0][2] * (r[1][0] * w[2] - w[1] * r[2][0]);
    const double uz = r[0][0] * (r[1][1] * w[2] - w[1] * r[2][1]) -
                      r[0][1] * (r[1][0] * w[2] - w[1] * r[2][0]) +
                      w[0] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    x[0] = p0[0] + ux / det;
    x[1] = p0[1] + uy / det;
    x[2] = p0[2] + uz / det;
  }

  // ---- The clipping kernel.
  struct Scratch {
    Poly a, b;
    std::vector<std::int8_t> sides;
    std::vector<std::uint64_t> edge_keys;
    std::vector<std::uint32_t> edge_new;
    std::vector<std::uint32_t> chain_next;
    std::vector<std::uint32_t> remap;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> cut_edges;
    std::vector<std::uint32_t> nbrs;
    std::vector<double> xyz;
  };

  // The tet t (its four facets) as a polyhedron; with only_facet >= 0, that facet alone
  // (a triangle: the boundary triangle of the restricted surface).
  static void init_tet(Poly& p, int only_facet) {
    p.clear();
    for (int k = 0; k < 4; ++k) {
      PVertex v{};
      int q = 0;
      for (int f = 0; f < 4; ++f) {
        if (f != k) v.p[q++] = facet_plane(f);
      }
      p.verts.push_back(v);
    }
    for (int f = 0; f < 4; ++f) {
      if (only_facet >= 0 && f != only_facet) continue;
      p.face_plane.push_back(facet_plane(f));
      for (int q = 0; q < 3; ++q) {
        p.face_verts.push_back(static_cast<std::uint32_t>(Domain3::kTetFacetVertex[f][q]));
      }
      p.face_begin.push_back(static_cast<std::uint32_t>(p.face_verts.size()));
    }
    if (only_facet >= 0) p.verts.erase(p.verts.begin() + only_facet);
    if (only_facet >= 0) {
      for (std::uint32_t& v : p.face_verts) {
        if (v > static_cast<std::uint32_t>(only_facet)) --v;
      }
    }
  }

  // Clips `in` by bisector(i, j) into `res` (keeps site i's side). Returns false when
  // nothing was cut (res untouched: use `in`).
  bool clip(const Poly& in, Poly& res, std::uint32_t t, std::uint32_t i, std::uint32_t j,
            Scratch& s) const {
    const std::size_t nv = in.verts.size();
    s.sides.resize(nv);
    bool any_out = false, any_in = false;
    // Only vertices used by a face matter (a polygon clip keeps no others).
    for (std::size_t v = 0; v < nv; ++v) {
      const bool out_side = side(in.verts[v], t, i, j) == Sign::positive;
      s.sides[v] = out_side ? 1 : 0;
      any_out = any_out || out_side;
      any_in = any_in || !out_side;
    }
    if (!any_out) return false;
    res.clear();
    if (!any_in) return true;
    // Kept vertices keep their index in a compacted list; new ones are appended.
    std::vector<std::uint32_t>& remap = s.remap;  // old vertex -> new index
    remap.assign(nv, kNone);
    for (std::size_t v = 0; v < nv; ++v) {
      if (!s.sides[v]) {
        remap[v] = static_cast<std::uint32_t>(res.verts.size());
        res.verts.push_back(in.verts[v]);
      }
    }
    s.edge_keys.clear();
    s.edge_new.clear();
    const auto crossing = [&](std::uint32_t u, std::uint32_t w, Plane face) {
      const std::uint64_t key = (std::uint64_t{std::min(u, w)} << 32) | std::max(u, w);
      for (std::size_t k = 0; k < s.edge_keys.size(); ++k) {
        if (s.edge_keys[k] == key) return s.edge_new[k];
      }
      PVertex x{};
      x.p[0] = face;
      x.p[1] = other_common_plane(in.verts[u], in.verts[w], face);
      x.p[2] = static_cast<Plane>(j);
      const auto idx = static_cast<std::uint32_t>(res.verts.size());
      res.verts.push_back(x);
      s.edge_keys.push_back(key);
      s.edge_new.push_back(idx);
      return idx;
    };
    // New face: edges entry -> exit, chained (indices into res.verts).
    std::vector<std::pair<std::uint32_t, std::uint32_t>>& cut_edges = s.cut_edges;
    cut_edges.clear();
    for (std::uint32_t f = 0; f < in.nb_faces(); ++f) {
      const std::uint32_t b = in.face_begin[f], e = in.face_begin[f + 1];
      const std::size_t start = res.face_verts.size();
      std::uint32_t exit_v = kNone, entry_v = kNone;
      for (std::uint32_t k = b; k < e; ++k) {
        const std::uint32_t u = in.face_verts[k];
        const std::uint32_t w = in.face_verts[k + 1 == e ? b : k + 1];
        if (!s.sides[u]) res.face_verts.push_back(remap[u]);
        if (s.sides[u] != s.sides[w]) {
          const std::uint32_t x = crossing(u, w, in.face_plane[f]);
          res.face_verts.push_back(x);
          (s.sides[u] ? entry_v : exit_v) = x;
        }
      }
      if (res.face_verts.size() - start >= 3) {
        res.face_plane.push_back(in.face_plane[f]);
        res.face_begin.push_back(static_cast<std::uint32_t>(res.face_verts.size()));
        if (exit_v != kNone) cut_edges.emplace_back(entry_v, exit_v);
      } else {
        res.face_verts.resize(start);
      }
    }
    if (in.nb_faces() > 1 && cut_edges.size() >= 3) {
      // The face on the bisector: follow entry -> exit edges around.
      std::vector<std::uint32_t>& next = s.chain_next;
      next.assign(res.verts.size(), kNone);
      for (const auto& [a, b2] : cut_edges) next[a] = b2;
      const std::uint32_t first = cut_edges[0].first;
      std::uint32_t v = first;
      for (std::size_t guard = 0; guard <= cut_edges.size(); ++guard) {
        res.face_verts.push_back(v);
        v = next[v];
        if (v == first || v == kNone) break;
      }
      if (v != first) throw Error("clip3d: internal error: the cut face does not close");
      res.face_plane.push_back(static_cast<Plane>(j));
      res.face_begin.push_back(static_cast<std::uint32_t>(res.face_verts.size()));
    }
    return true;
  }

  // Clips tet t (or its facet `only_facet`) by every bisector of cell i. The result is in
  // s.a (possibly empty).
  void clip_by_cell(std::uint32_t t, int only_facet, std::uint32_t i,
                    const std::vector<std::uint32_t>& nbrs, Scratch& s) const {
    init_tet(s.a, only_facet);
    for (const std::uint32_t j : nbrs) {
      if (clip(s.a, s.b, t, i, j, s)) std::swap(s.a, s.b);
      if (s.a.empty()) return;
    }
  }

  // ---- Step 1: restricted surface.
  std::uint32_t cell_of_point(const double* a, std::vector<std::uint32_t>& scratch) const {
    std::uint32_t c = dt.nearest_vertex(a);
    for (bool moved = true; moved;) {
      moved = false;
      dt.vertex_neighbors(c, scratch);
      for (const std::uint32_t k : scratch) {
        if (bisector_side_vertex3d(site(c), site(k), a, c, k) == Sign::positive) {
          c = k;
          moved = true;
          break;
        }
      }
    }
    return c;
  }

  void surface_pass(Scratch& s) {
    const std::uint32_t nb = domain.nb_boundary_triangles();
    std::vector<std::uint8_t> reached(nb, 0);
    std::unordered_set<std::uint64_t> pushed;
    std::deque<std::pair<std::uint32_t, std::uint32_t>> queue;  // (triangle, cell)
    std::vector<std::pair<std::uint32_t, std::uint32_t>> hits;  // (cell, triangle)
    surface_area.assign(n, 0);
    const auto push = [&](std::uint32_t b, std::uint32_t c) {
      if (pushed.insert((std::uint64_t{c} << 32) | b).second) queue.emplace_back(b, c);
    };
    std::vector<std::uint32_t> nbrs;
    for (std::uint32_t b0 = 0; b0 < nb; ++b0) {
      if (reached[b0]) continue;
      push(b0, cell_of_point(domain.vertex(domain.boundary_vertex(b0, 0)), nbrs));
      while (!queue.empty()) {
        const auto [b, c] = queue.front();
        queue.pop_front();
        reached[b] = 1;
        const std::uint32_t t = domain.boundary_tet(b);
        const int f = domain.boundary_facet(b);
        dt.vertex_neighbors(c, nbrs);
        clip_by_cell(t, f, c, nbrs, s);
        if (s.a.empty()) continue;
        hits.emplace_back(c, b);
        // Area and geometry.
        const Poly& p = s.a;
        s.xyz.resize(3 * p.verts.size());
        for (std::size_t v = 0; v < p.verts.size(); ++v) coords(p.verts[v], t, c, &s.xyz[3 * v]);
        double area[3] = {0, 0, 0};
        const std::uint32_t fb = p.face_begin[0], fe = p.face_begin[1];
        const double* o = &s.xyz[3 * std::size_t{p.face_verts[fb]}];
        for (std::uint32_t k = fb + 1; k + 1 < fe; ++k) {
          const double* u = &s.xyz[3 * std::size_t{p.face_verts[k]}];
          const double* w = &s.xyz[3 * std::size_t{p.face_verts[k + 1]}];
          const double a[3] = {u[0] - o[0], u[1] - o[1], u[2] - o[2]};
          const double d[3] = {w[0] - o[0], w[1] - o[1], w[2] - o[2]};
          area[0] += a[1] * d[2] - a[2] * d[1];
          area[1] += a[2] * d[0] - a[0] * d[2];
          area[2] += a[0] * d[1] - a[1] * d[0];
        }
        surface_area[c] +=
            0.5 * std::sqrt(area[0] * area[0] + area[1] * area[1] + area[2] * area[2]);
        if (options.keep_geometry) {
          out.surface_.site.push_back(c);
          for (std::uint32_t k = fb; k < fe; ++k) {
            const double* x = &s.xyz[3 * std::size_t{p.face_verts[k]}];
            out.surface_.xyz.insert(out.surface_.xyz.end(), x, x + 3);
          }
          out.surface_.polygon_begin.push_back(
              static_cast<std::uint32_t>(out.surface_.xyz.size() / 3));
        }
        // New pairs from the polygon's edges.
        for (std::uint32_t k = fb; k < fe; ++k) {
          const PVertex& u = p.verts[p.face_verts[k]];
          const PVertex& w = p.verts[p.face_verts[k + 1 == fe ? fb : k + 1]];
          const Plane g = other_common_plane(u, w, facet_plane(f));
          if (is_facet(g)) {
            // The triangle edge between facets f and g: opposite, in the triangle, its
            // vertex that is tet vertex g.
            int e = 0;
            while (Domain3::kTetFacetVertex[f][e] != facet_of(g)) ++e;
            const std::uint32_t b2 = domain.boundary_adjacent(b, e);
            if (b2 != Domain3::kNone) push(b2, c);
          } else {
            push(b, static_cast<std::uint32_t>(g));
          }
        }
      }
    }
    // Boundary cells and their triangles (sorted: deterministic).
    std::sort(hits.begin(), hits.end());
    cell_tri_begin.assign(n + 1, 0);
    for (const auto& h : hits) ++cell_tri_begin[h.first + 1];
    for (std::uint32_t i = 0; i < n; ++i) cell_tri_begin[i + 1] += cell_tri_begin[i];
    cell_tris.resize(hits.size());
    for (std::size_t k = 0; k < hits.size(); ++k) cell_tris[k] = hits[k].second;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (cell_tri_begin[i + 1] > cell_tri_begin[i]) boundary_cells.push_back(i);
    }
  }

  // ---- Step 2: a boundary cell, tet by tet.
  // `stamp`: per tet, the last cell (+1) that queued it (a per-thread array, so that
  // the visited test costs one load).
  // Cell c tet by tet from the seed tets (a boundary cell: the tets of its boundary
  // triangles). With `seeds_out`, every (neighbour, tet) where a piece has a face on
  // their bisector is appended (the seeds of inner cells under a non-constant density).
  void clip_cell(std::uint32_t c, const std::uint32_t* seeds, std::size_t nb_seeds, Scratch& s,
                 std::vector<std::uint32_t>& stamp, std::vector<std::uint32_t>& queue, CellOut& res,
                 std::vector<std::pair<std::uint32_t, std::uint32_t>>* seeds_out) const {
    dt.vertex_neighbors(c, s.nbrs);
    const std::vector<std::uint32_t>& nbrs = s.nbrs;  // untouched by the clipping
    if (stamp.size() != domain.nb_tets()) stamp.assign(domain.nb_tets(), 0);
    queue.clear();
    const auto push = [&](std::uint32_t t) {
      if (stamp[t] == c + 1) return;
      stamp[t] = c + 1;
      queue.push_back(t);
    };
    for (std::size_t q = 0; q < nb_seeds; ++q) push(seeds[q]);
    std::vector<std::uint8_t> walked(nbrs.size(), 0);
    const double* pc = site(c);
    for (std::size_t h = 0; h < queue.size(); ++h) {
      const std::uint32_t t = queue[h];
      ++res.pairs;
      clip_by_cell(t, -1, c, nbrs, s);
      const Poly& p = s.a;
      if (p.empty()) continue;
      s.xyz.resize(3 * p.verts.size());
      for (std::size_t v = 0; v < p.verts.size(); ++v) coords(p.verts[v], t, c, &s.xyz[3 * v]);
      for (std::uint32_t f = 0; f < p.nb_faces(); ++f) {
        const Plane plane = p.face_plane[f];
        if (is_facet(plane)) {
          const std::uint32_t t2 = domain.tet_adjacent(t, facet_of(plane));
          if (t2 != Domain3::kNone) push(t2);
        } else {
          const auto k = static_cast<std::uint32_t>(plane);
          for (std::size_t q = 0; q < nbrs.size(); ++q) {
            if (nbrs[q] == k) walked[q] = 1;
          }
          if (seeds_out) seeds_out->emplace_back(k, t);
        }
        // Fan from the face's first vertex, apex the site: signed tets.
        const std::uint32_t fb = p.face_begin[f], fe = p.face_begin[f + 1];
        const double* a = &s.xyz[3 * std::size_t{p.face_verts[fb]}];
        for (std::uint32_t k = fb + 1; k + 1 < fe; ++k) {
          const double* b = &s.xyz[3 * std::size_t{p.face_verts[k]}];
          const double* d = &s.xyz[3 * std::size_t{p.face_verts[k + 1]}];
          if (linear_density) {
            add_tet_linear(t, pc, a, b, d, res);
          } else {
            add_tet(pc, a, b, d, res);
          }
        }
        if (options.keep_geometry) {
          for (std::uint32_t k = fb; k < fe; ++k) {
            const double* x = &s.xyz[3 * std::size_t{p.face_verts[k]}];
            res.face_xyz.insert(res.face_xyz.end(), x, x + 3);
          }
          res.face_begin.push_back(static_cast<std::uint32_t>(res.face_xyz.size() / 3));
          res.face_piece.push_back(static_cast<std::uint32_t>(h));
        }
      }
    }
    for (std::size_t q = 0; q < nbrs.size(); ++q) {
      if (walked[q]) res.walked.push_back(nbrs[q]);
    }
  }

  // Signed tet (o, a, b, d), faces oriented as Domain3::kTetFacetVertex (inward-facing
  // for orient3d > 0): volume = -det(a - o, b - o, d - o) / 6.
  static void add_tet(const double* o, const double* a, const double* b, const double* d,
                      Moments& res) {
    const double u[3] = {a[0] - o[0], a[1] - o[1], a[2] - o[2]};
    const double v[3] = {b[0] - o[0], b[1] - o[1], b[2] - o[2]};
    const double w[3] = {d[0] - o[0], d[1] - o[1], d[2] - o[2]};
    const double det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                       u[2] * (v[0] * w[1] - v[1] * w[0]);
    const double vol = -det / 6;
    res.volume += vol;
    for (int c = 0; c < 3; ++c) res.moment[c] += vol * (u[c] + v[c] + w[c]) / 4;
    res.energy +=
        vol / 10 *
        (u[0] * u[0] + u[1] * u[1] + u[2] * u[2] + v[0] * v[0] + v[1] * v[1] + v[2] * v[2] +
         w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) +
         (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) + (v[0] * w[0] + v[1] * w[1] + v[2] * w[2]));
  }

  // Signed tet (o, a, b, d) as add_tet, with rho linear: the linear function of tet t of
  // the domain (exact: the integrands are polynomials of degree <= 3 and the signed fan
  // is exact for polynomials). ∫ λ_i λ_j λ_k over a tet of volume V is V/20, V/60 or
  // V/120 for three, two or no equal indices; ∫ λ_i λ_j is V/10 or V/20.
  void add_tet_linear(std::uint32_t t, const double* o, const double* a, const double* b,
                      const double* d, Moments& res) const {
    const double* pts[4] = {o, a, b, d};
    double r[4];
    for (int k = 0; k < 4; ++k) r[k] = density_at(t, pts[k]);
    double u[4][3];
    for (int k = 0; k < 4; ++k) {
      for (int c = 0; c < 3; ++c) u[k][c] = pts[k][c] - o[c];
    }
    const double det = u[1][0] * (u[2][1] * u[3][2] - u[2][2] * u[3][1]) -
                       u[1][1] * (u[2][0] * u[3][2] - u[2][2] * u[3][0]) +
                       u[1][2] * (u[2][0] * u[3][1] - u[2][1] * u[3][0]);
    const double vol = -det / 6;
    double mass = 0, mom[3] = {0, 0, 0}, energy = 0;
    for (int i = 0; i < 4; ++i) {
      mass += r[i] / 4;
      for (int j = 0; j < 4; ++j) {
        const double w2 = (i == j ? 1.0 / 10 : 1.0 / 20);
        for (int c = 0; c < 3; ++c) mom[c] += w2 * r[i] * u[j][c];
        for (int k = 0; k < 4; ++k) {
          const double dot = u[j][0] * u[k][0] + u[j][1] * u[k][1] + u[j][2] * u[k][2];
          const int equal = (i == j) + (j == k) + (i == k);
          const double w3 = equal == 3 ? 1.0 / 20 : equal == 1 ? 1.0 / 60 : 1.0 / 120;
          energy += w3 * r[i] * dot;
        }
      }
    }
    res.volume += vol;
    res.mass += vol * mass;
    for (int c = 0; c < 3; ++c) res.moment[c] += vol * mom[c];
    res.energy += vol * energy;
  }

  // rho at x by the linear function of domain tet t (barycentric coordinates of x).
  double density_at(std::uint32_t t, const double* x) const {
    const double* p0 = domain.vertex(domain.tet_vertex(t, 0));
    double m[3][3], rhs[3];
    for (int k = 0; k < 3; ++k) {
      const double* pk = domain.vertex(domain.tet_vertex(t, k + 1));
      for (int c = 0; c < 3; ++c) m[c][k] = pk[c] - p0[c];
    }
    for (int c = 0; c < 3; ++c) rhs[c] = x[c] - p0[c];
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double l[3];
    for (int k = 0; k < 3; ++k) {
      double mk[3][3];
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) mk[r][c] = c == k ? rhs[r] : m[r][c];
      }
      l[k] = (mk[0][0] * (mk[1][1] * mk[2][2] - mk[1][2] * mk[2][1]) -
              mk[0][1] * (mk[1][0] * mk[2][2] - mk[1][2] * mk[2][0]) +
              mk[0][2] * (mk[1][0] * mk[2][1] - mk[1][1] * mk[2][0])) /
             det;
    }
    const std::vector<double>& rho = options.vertex_density;
    return rho[domain.tet_vertex(t, 0)] * (1 - l[0] - l[1] - l[2]) +
           rho[domain.tet_vertex(t, 1)] * l[0] + rho[domain.tet_vertex(t, 2)] * l[1] +
           rho[domain.tet_vertex(t, 3)] * l[2];
  }

  // ---- Step 3: the other cells.
  void classify() {
    status.assign(n, -1);
    std::vector<std::uint8_t> is_b(n, 0);
    for (const std::uint32_t c : boundary_cells) is_b[c] = 1;
    std::vector<std::uint32_t> nbrs;
    bool any_outside = false;
    for (std::size_t q = 0; q < boundary_cells.size(); ++q) {
      dt.vertex_neighbors(boundary_cells[q], nbrs);
      const auto& w = cell_out[q].walked;
      for (const std::uint32_t k : nbrs) {
        if (is_b[k]) continue;
        const std::int8_t st = std::find(w.begin(), w.end(), k) != w.end() ? 1 : 0;
        if (status[k] != -1 && status[k] != st) {
          throw Error("clip3d: internal error: inconsistent inside/outside seeds at site " +
                      std::to_string(k));
        }
        status[k] = st;
        any_outside = any_outside || st == 0;
      }
    }
    if (!any_outside) {
      for (std::uint32_t i = 0; i < n; ++i) {
        if (!is_b[i] && dt.duplicate_of(i) == i) status[i] = 1;
      }
      return;
    }
    std::vector<std::uint32_t> parent(n);
    for (std::uint32_t i = 0; i < n; ++i) parent[i] = i;
    const auto find = [&](std::uint32_t x) {
      while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
      }
      return x;
    };
    for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
      if (dt.is_free(t) || dt.is_infinite(t)) continue;
      for (int a = 0; a < 4; ++a) {
        for (int b = a + 1; b < 4; ++b) {
          const std::uint32_t u = dt.tet_vertex(t, a), w = dt.tet_vertex(t, b);
          if (is_b[u] || is_b[w]) continue;
          const std::uint32_t ru = find(u), rw = find(w);
          if (ru != rw) parent[std::max(ru, rw)] = std::min(ru, rw);
        }
      }
    }
    std::vector<std::int8_t> root_status(n, -1);
    for (std::uint32_t i = 0; i < n; ++i) {
      if (status[i] != -1) root_status[find(i)] = status[i];
    }
    for (std::uint32_t i = 0; i < n; ++i) {
      if (!is_b[i] && dt.duplicate_of(i) == i) status[i] = root_status[find(i)];
    }
  }

  // The inner cell of v from the triangulation: a pyramid from the site over each Voronoi
  // face, the face dual to Delaunay edge (v, x) being the polygon of the circumcentres of
  // the tets around that edge, in cyclic order (a walk through the tets sharing the edge).
  // The site lies strictly on its side of the face's plane (the bisector), so the
  // pyramid's volume is positive: a face whose fan comes out negative is reversed.
  // `tets`, `done`, `ring`: scratch. (Inner cells are bounded: no infinite tet on the way.)
  void inner_cell(std::uint32_t v, const std::vector<double>& circ,
                  std::vector<std::uint32_t>& tets, std::vector<std::uint32_t>& done,
                  std::vector<std::uint32_t>& ring, Moments& res) const {
    dt.vertex_tets(v, tets);
    const double* pv = site(v);
    done.clear();
    for (const std::uint32_t t0 : tets) {
      for (int kx = 0; kx < 4; ++kx) {
        const std::uint32_t x = dt.tet_vertex(t0, kx);
        if (x == v || std::find(done.begin(), done.end(), x) != done.end()) continue;
        done.push_back(x);
        // Walk around edge (v, x): in tet `cur` with the two other vertices (a, b), step
        // through the facet opposite a (it holds v, x, b) to the next tet.
        ring.clear();
        std::uint32_t cur = t0, a = kNone;
        for (int k = 0; k < 4; ++k) {
          const std::uint32_t w = dt.tet_vertex(t0, k);
          if (w != v && w != x) {
            a = w;
            break;
          }
        }
        for (std::size_t guard = 0; guard < 1000; ++guard) {
          ring.push_back(cur);
          int la = 0;
          while (dt.tet_vertex(cur, la) != a) ++la;
          std::uint32_t b = kNone;
          for (int k = 0; k < 4; ++k) {
            const std::uint32_t w = dt.tet_vertex(cur, k);
            if (w != v && w != x && w != a) b = w;
          }
          cur = dt.tet_adjacent(cur, la);
          a = b;
          if (cur == t0) break;
        }
        // Fan of the face from its first vertex, apex the site.
        Moments face;
        const double* c0 = &circ[3 * std::size_t{ring[0]}];
        for (std::size_t j = 1; j + 1 < ring.size(); ++j) {
          add_tet(pv, c0, &circ[3 * std::size_t{ring[j]}], &circ[3 * std::size_t{ring[j + 1]}],
                  face);
        }
        const double sgn = face.volume < 0 ? -1.0 : 1.0;
        res.volume += sgn * face.volume;
        res.energy += sgn * face.energy;
        for (int c = 0; c < 3; ++c) res.moment[c] += sgn * face.moment[c];
      }
    }
  }

  void run() {
    using Clock = std::chrono::steady_clock;
    n = dt.nb_points();
    out.surface_ = {};
    out.faces_ = {};
    out.surface_.polygon_begin.push_back(0);
    out.faces_.polygon_begin.push_back(0);
    auto t0 = Clock::now();
    Scratch s;
    surface_pass(s);
    auto t1 = Clock::now();
    out.seconds_[0] = std::chrono::duration<double>(t1 - t0).count();

    linear_density = !options.vertex_density.empty();
    cell_out.assign(boundary_cells.size(), CellOut{});
    tbb::enumerable_thread_specific<Scratch> scratch;
    tbb::enumerable_thread_specific<
        std::pair<std::vector<std::uint32_t>, std::vector<std::uint32_t>>>
        lists;
    // Per boundary cell, its seeds: the tets of its boundary triangles.
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> seeds_out(
        linear_density ? boundary_cells.size() : 0);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, boundary_cells.size(), 4), [&](const auto& range) {
          Scratch& sc = scratch.local();
          auto& l = lists.local();
          std::vector<std::uint32_t> seeds;
          for (std::size_t q = range.begin(); q != range.end(); ++q) {
            const std::uint32_t c = boundary_cells[q];
            seeds.clear();
            for (std::uint32_t k = cell_tri_begin[c]; k < cell_tri_begin[c + 1]; ++k) {
              seeds.push_back(domain.boundary_tet(cell_tris[k]));
            }
            clip_cell(c, seeds.data(), seeds.size(), sc, l.first, l.second, cell_out[q],
                      linear_density ? &seeds_out[q] : nullptr);
          }
        });
    auto t2 = Clock::now();
    out.seconds_[1] = std::chrono::duration<double>(t2 - t1).count();

    classify();
    // A non-constant density: inner cells are clipped too, layer after layer from the
    // boundary cells (each layer seeded by the faces the previous one has on their
    // bisectors; seeds sorted, so the order of everything is a function of the input).
    std::vector<std::uint32_t> inner_slot(linear_density ? n : 0, kNone);
    std::vector<CellOut> inner_out;
    if (linear_density) {
      std::vector<std::pair<std::uint32_t, std::uint32_t>> pending;
      for (const auto& v : seeds_out) pending.insert(pending.end(), v.begin(), v.end());
      std::vector<std::uint8_t> done(n, 0);
      for (const std::uint32_t c : boundary_cells) done[c] = 1;
      for (;;) {
        std::sort(pending.begin(), pending.end());
        pending.erase(std::unique(pending.begin(), pending.end()), pending.end());
        std::vector<std::uint32_t> layer, begin;
        std::vector<std::uint32_t> seed_tets;
        for (std::size_t k = 0; k < pending.size();) {
          const std::uint32_t c = pending[k].first;
          std::size_t e = k;
          while (e < pending.size() && pending[e].first == c) ++e;
          if (!done[c] && status[c] == 1) {
            done[c] = 1;
            layer.push_back(c);
            begin.push_back(static_cast<std::uint32_t>(seed_tets.size()));
            for (std::size_t q = k; q < e; ++q) seed_tets.push_back(pending[q].second);
          }
          k = e;
        }
        if (layer.empty()) break;
        begin.push_back(static_cast<std::uint32_t>(seed_tets.size()));
        const std::size_t base = inner_out.size();
        inner_out.resize(base + layer.size());
        std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> next(layer.size());
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, layer.size(), 4), [&](const auto& range) {
              Scratch& sc = scratch.local();
              auto& l = lists.local();
              for (std::size_t q = range.begin(); q != range.end(); ++q) {
                clip_cell(layer[q], seed_tets.data() + begin[q], begin[q + 1] - begin[q], sc,
                          l.first, l.second, inner_out[base + q], &next[q]);
              }
            });
        for (std::size_t q = 0; q < layer.size(); ++q) {
          inner_slot[layer[q]] = static_cast<std::uint32_t>(base + q);
        }
        pending.clear();
        for (const auto& v : next) pending.insert(pending.end(), v.begin(), v.end());
      }
    }
    // Circumcentres of the Delaunay tets.
    std::vector<double> circ(3 * std::size_t{dt.nb_tet_slots()}, 0);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, dt.nb_tet_slots(), 4096),
                      [&](const auto& range) {
                        for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
                          if (!dt.is_free(t) && !dt.is_infinite(t)) {
                            dt.circumcenter(t, &circ[3 * std::size_t{t}]);
                          }
                        }
                      });
    std::vector<std::uint32_t> slot(n, kNone);
    for (std::uint32_t q = 0; q < boundary_cells.size(); ++q) slot[boundary_cells[q]] = q;
    out.cells_.assign(n, ClippedVoronoi3::Cell{});
    struct InnerScratch {
      std::vector<std::uint32_t> tets, done, ring;
    };
    tbb::enumerable_thread_specific<InnerScratch> tet_lists;
    // Inner cells of the constant density first, in the order of a tet of theirs (tets
    // are numbered roughly along the insertion curve: neighbouring cells then walk
    // neighbouring memory), into a buffer; then every cell in index order.
    std::vector<Moments> inner_moments;
    std::vector<std::uint32_t> inner_pos;
    if (!linear_density) {
      const std::uint32_t slots = dt.nb_tet_slots();
      std::vector<std::uint32_t> bucket(std::size_t{slots} + 1, 0), order;
      for (std::uint32_t i = 0; i < n; ++i) {
        if (slot[i] == kNone && status[i] == 1) ++bucket[dt.vertex_tet(i) + std::size_t{1}];
      }
      for (std::size_t t = 0; t < slots; ++t) bucket[t + 1] += bucket[t];
      order.resize(bucket[slots]);
      inner_pos.assign(n, kNone);
      for (std::uint32_t i = 0; i < n; ++i) {
        if (slot[i] == kNone && status[i] == 1) {
          const std::uint32_t q = bucket[dt.vertex_tet(i)]++;
          order[q] = i;
          inner_pos[i] = q;
        }
      }
      inner_moments.resize(order.size());
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 256),
                        [&](const auto& range) {
                          InnerScratch& is = tet_lists.local();
                          for (std::size_t q = range.begin(); q != range.end(); ++q) {
                            inner_moments[q] = Moments{};
                            inner_cell(order[q], circ, is.tets, is.done, is.ring, inner_moments[q]);
                          }
                        });
    }
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 1024), [&](const auto& range) {
      for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
        const Moments* r = nullptr;
        if (slot[i] != kNone) {
          r = &cell_out[slot[i]];
        } else if (linear_density) {
          if (inner_slot[i] != kNone) r = &inner_out[inner_slot[i]];
        } else if (status[i] == 1) {
          r = &inner_moments[inner_pos[i]];
        }
        ClippedVoronoi3::Cell& cell = out.cells_[i];
        const double* p = site(i);
        cell.volume = r ? r->volume : 0;
        if (linear_density) {
          cell.mass = r ? r->mass : 0;
          cell.energy = r ? r->energy : 0;
        } else {
          cell.mass = options.density * cell.volume;
          cell.energy = r ? options.density * r->energy : 0;
        }
        const double m = linear_density ? cell.mass : cell.volume;
        for (int c = 0; c < 3; ++c) {
          cell.centroid[c] = r && m > 0 ? p[c] + r->moment[c] / m : p[c];
        }
        cell.surface_area = surface_area[i];
        cell.boundary = slot[i] != kNone ? 1 : 0;
      }
    });
    auto t3 = Clock::now();
    out.seconds_[2] = std::chrono::duration<double>(t3 - t2).count();

    out.nb_boundary_ = static_cast<std::uint32_t>(boundary_cells.size());
    out.total_volume_ = out.total_mass_ = out.total_energy_ = out.total_surface_area_ = 0;
    out.nb_pairs_ = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      out.total_volume_ += out.cells_[i].volume;
      out.total_mass_ += out.cells_[i].mass;
      out.total_energy_ += out.cells_[i].energy;
      out.total_surface_area_ += out.cells_[i].surface_area;
    }
    for (const CellOut& c : cell_out) out.nb_pairs_ += c.pairs;
    for (const CellOut& c : inner_out) out.nb_pairs_ += c.pairs;
    if (options.keep_geometry) {
      std::uint32_t pieces = 0;
      for (std::size_t q = 0; q < boundary_cells.size(); ++q) {
        const CellOut& c = cell_out[q];
        const auto base = static_cast<std::uint32_t>(out.faces_.xyz.size() / 3);
        out.faces_.xyz.insert(out.faces_.xyz.end(), c.face_xyz.begin(), c.face_xyz.end());
        std::uint32_t last = kNone;
        for (std::size_t f = 1; f < c.face_begin.size(); ++f) {
          if (c.face_piece[f - 1] != last) {
            last = c.face_piece[f - 1];
            ++pieces;
          }
          out.faces_.site.push_back(boundary_cells[q]);
          out.faces_.piece.push_back(pieces - 1);
          out.faces_.polygon_begin.push_back(base + c.face_begin[f]);
        }
      }
    }
  }
};

void ClippedVoronoi3::compute(const Domain3& domain, const Delaunay3& dt,
                              const Clip3Options& options) {
  if (domain.nb_tets() == 0) throw Error("clip3d: the domain has no tetrahedra");
  if (dt.nb_points() == 0) throw Error("clip3d: no sites");
  if (!(options.density > 0) || !std::isfinite(options.density)) {
    throw Error("clip3d: the density must be finite and positive");
  }
  if (!options.vertex_density.empty()) {
    if (options.vertex_density.size() != domain.nb_vertices()) {
      throw Error("clip3d: vertex_density has " + std::to_string(options.vertex_density.size()) +
                  " values for " + std::to_string(domain.nb_vertices()) + " domain vertices");
    }
    for (std::size_t v = 0; v < options.vertex_density.size(); ++v) {
      if (!(options.vertex_density[v] >= 0) || !std::isfinite(options.vertex_density[v])) {
        throw Error("clip3d: vertex_density[" + std::to_string(v) + "] is negative or not finite");
      }
    }
  }
  Clip3Impl impl(domain, dt, options, *this);
  impl.run();
}

}  // namespace voroclip
