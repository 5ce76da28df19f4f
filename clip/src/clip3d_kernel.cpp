// The convex-cell kernel of the 3D clipped Voronoi diagram (clip3d_kernel.h): exact
// clipping of a tet by a cell, and the tet-by-tet integration of a cell (Yan et al. 2011,
// sec. 4.2) built on it, for domains with a tet mesh: the path of a density linear per tet,
// and of tet_clipping, the reference the tests check the surface-only path
// (clip3d_cells.cpp) against.
//
// A convex polyhedron (or polygon) is kept as faces listing vertices, and every vertex as
// the three planes that define it, among the four facets of the current tet and the
// bisectors of the cell's site with its neighbours. The kind of a vertex follows from how
// many of its planes are tet facets: 3, a mesh vertex; 2, a mesh edge ∩ a bisector; 1, a
// mesh facet ∩ two bisectors; 0, a Voronoi vertex. "Which side of bisector(i, j)" is one
// exact predicate per kind (predicates.h, with the perturbation of insphere_sos), so
// clipping never meets a tie: sites on the boundary (the paper's Fig. 10) and bisectors
// through mesh edges (Fig. 11) need no special case. Coordinates are computed for
// integration only, each from the vertex's sorted global ids, so cells sharing a vertex
// compute the same bits.
#include "clip3d_kernel.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace voroclip {

namespace clip3 {

Plane other_common_plane(const PVertex& u, const PVertex& w, Plane face) {
  for (const Plane a : u.p) {
    if (a == face) continue;
    for (const Plane b : w.p) {
      if (a == b) return a;
    }
  }
  throw Error("clip3d: internal error: an edge whose ends share one plane");
}

Sign ConvexCell::side(const PVertex& v, std::uint32_t t, std::uint32_t i, std::uint32_t j) const {
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
  const double* pi = ctx_.site(i);
  const double* pj = ctx_.site(j);
  int others[4], no = 0;  // tet-local vertices not opposite a facet plane of v
  for (int k = 0; k < 4; ++k) {
    bool used = false;
    for (int q = 0; q < nf; ++q) used = used || facets[q] == k;
    if (!used) others[no++] = k;
  }
  const auto mv = [&](int local) { return ctx_.domain.vertex(ctx_.domain.tet_vertex(t, local)); };
  switch (nf) {
    case 3:
      return bisector_side_vertex3d(pi, pj, mv(others[0]), i, j);
    case 2:
      return bisector_side_edge3d(pi, ctx_.site(sites[0]), pj, mv(others[0]), mv(others[1]), i,
                                  sites[0], j);
    case 1:
      return bisector_side_facet3d(pi, ctx_.site(sites[0]), ctx_.site(sites[1]), pj, mv(others[0]),
                                   mv(others[1]), mv(others[2]), i, sites[0], sites[1], j);
    default:
      return bisector_side_voronoi3d(pi, ctx_.site(sites[0]), ctx_.site(sites[1]),
                                     ctx_.site(sites[2]), pj, i, sites[0], sites[1], sites[2], j);
  }
}

void ConvexCell::coords(const PVertex& v, std::uint32_t t, std::uint32_t i, double* x) const {
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
    if (!facet_used[k]) mesh[nm++] = ctx_.domain.tet_vertex(t, k);
  }
  sites[ns++] = i;
  small_sort(mesh, nm);
  small_sort(sites, ns);
  if (ns == 1) {  // a mesh vertex (nm == 1)
    const double* a = ctx_.domain.vertex(mesh[0]);
    x[0] = a[0];
    x[1] = a[1];
    x[2] = a[2];
    return;
  }
  if (ns == 2) {
    ctx_.edge_point(mesh[0], mesh[1], sites[0], sites[1], x);
    return;
  }
  if (ns == 3) {
    ctx_.facet_point(mesh, sites, x);
    return;
  }
  ctx_.voronoi_point(sites, x);
}

// The tet t (its four facets) as a polyhedron; with only_facet >= 0, that facet alone
// (a triangle: the boundary triangle of the restricted surface).
void ConvexCell::init_tet(Poly& p, int only_facet) {
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
bool ConvexCell::clip(const Poly& in, Poly& res, std::uint32_t t, std::uint32_t i,
                      std::uint32_t j) {
  const std::size_t nv = in.verts.size();
  buf_.sides.resize(nv);
  bool any_out = false, any_in = false;
  // Only vertices used by a face matter (a polygon clip keeps no others).
  for (std::size_t v = 0; v < nv; ++v) {
    const bool out_side = side(in.verts[v], t, i, j) == Sign::positive;
    buf_.sides[v] = out_side ? 1 : 0;
    any_out = any_out || out_side;
    any_in = any_in || !out_side;
  }
  if (!any_out) return false;
  res.clear();
  if (!any_in) return true;
  // Kept vertices keep their index in a compacted list; new ones are appended.
  std::vector<std::uint32_t>& remap = buf_.remap;  // old vertex -> new index
  remap.assign(nv, kNone);
  for (std::size_t v = 0; v < nv; ++v) {
    if (!buf_.sides[v]) {
      remap[v] = static_cast<std::uint32_t>(res.verts.size());
      res.verts.push_back(in.verts[v]);
    }
  }
  buf_.edge_keys.clear();
  buf_.edge_new.clear();
  const auto crossing = [&](std::uint32_t u, std::uint32_t w, Plane face) {
    const std::uint64_t key = (std::uint64_t{std::min(u, w)} << 32) | std::max(u, w);
    for (std::size_t k = 0; k < buf_.edge_keys.size(); ++k) {
      if (buf_.edge_keys[k] == key) return buf_.edge_new[k];
    }
    PVertex x{};
    x.p[0] = face;
    x.p[1] = other_common_plane(in.verts[u], in.verts[w], face);
    x.p[2] = static_cast<Plane>(j);
    const auto idx = static_cast<std::uint32_t>(res.verts.size());
    res.verts.push_back(x);
    buf_.edge_keys.push_back(key);
    buf_.edge_new.push_back(idx);
    return idx;
  };
  // New face: edges entry -> exit, chained (indices into res.verts).
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& cut_edges = buf_.cut_edges;
  cut_edges.clear();
  for (std::uint32_t f = 0; f < in.nb_faces(); ++f) {
    const std::uint32_t b = in.face_begin[f], e = in.face_begin[f + 1];
    const std::size_t start = res.face_verts.size();
    std::uint32_t exit_v = kNone, entry_v = kNone;
    for (std::uint32_t k = b; k < e; ++k) {
      const std::uint32_t u = in.face_verts[k];
      const std::uint32_t w = in.face_verts[k + 1 == e ? b : k + 1];
      if (!buf_.sides[u]) res.face_verts.push_back(remap[u]);
      if (buf_.sides[u] != buf_.sides[w]) {
        const std::uint32_t x = crossing(u, w, in.face_plane[f]);
        res.face_verts.push_back(x);
        (buf_.sides[u] ? entry_v : exit_v) = x;
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
    std::vector<std::uint32_t>& next = buf_.chain_next;
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

// A bisector with the tet's four vertices certainly on i's side (certainly_nearer) cannot
// cut it: skipped without a predicate.
const Poly& ConvexCell::clip_tet(std::uint32_t t, int only_facet, std::uint32_t i,
                                 const std::vector<std::uint32_t>& nbrs) {
  init_tet(a_, only_facet);
  const double* pi = ctx_.site(i);
  const double* v[4];
  for (int k = 0; k < 4; ++k) v[k] = ctx_.domain.vertex(ctx_.domain.tet_vertex(t, k));
  for (const std::uint32_t j : nbrs) {
    const double* pj = ctx_.site(j);
    if (certainly_nearer(v[0], pi, pj) && certainly_nearer(v[1], pi, pj) &&
        certainly_nearer(v[2], pi, pj) && certainly_nearer(v[3], pi, pj)) {
      continue;
    }
    if (clip(a_, b_, t, i, j)) std::swap(a_, b_);
    if (a_.empty()) break;
  }
  return a_;
}

// Cell c tet by tet (sec. 4.2): a FIFO of tets seeded by `seeds` (a boundary cell: the
// tets of its boundary triangles); each tet is clipped by the cell's bisectors, and a
// non-empty piece pushes the tets across the tet facets it still touches. Every connected
// piece of cell ∩ volume touches the boundary (a piece that did not would be the whole
// convex cell), so this reaches all of them. With `seeds_out`, every (neighbour, tet) where
// a piece has a face on their bisector is appended (the seeds of inner cells under a
// non-constant density). stamp_: per tet, the last cell (+ 1) that queued it, so that the
// visited test costs one load (each cell is clipped once per compute).
void ConvexCell::clip_cell(std::uint32_t c, const std::uint32_t* seeds, std::size_t nb_seeds,
                           CellOut& res,
                           std::vector<std::pair<std::uint32_t, std::uint32_t>>* seeds_out) {
  ctx_.dt.vertex_neighbors(c, nbrs_);
  const std::vector<std::uint32_t>& nbrs = nbrs_;  // untouched by the clipping
  std::vector<std::uint32_t>& stamp = stamp_;
  std::vector<std::uint32_t>& queue = queue_;
  if (stamp.size() != ctx_.domain.nb_tets()) stamp.assign(ctx_.domain.nb_tets(), 0);
  queue.clear();
  const auto push = [&](std::uint32_t t) {
    if (stamp[t] == c + 1) return;
    stamp[t] = c + 1;
    queue.push_back(t);
  };
  for (std::size_t q = 0; q < nb_seeds; ++q) push(seeds[q]);
  // The cones' apex: the site, or for a far one the domain's centre (Clip3Context::far).
  if (ctx_.far(c)) ctx_.check_far_site(c);
  const double* pc = ctx_.apex(c);
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const std::uint32_t t = queue[h];
    ++res.pairs;
    const Poly& p = clip_tet(t, -1, c, nbrs);
    if (p.empty()) continue;
    xyz_.resize(3 * p.verts.size());
    for (std::size_t v = 0; v < p.verts.size(); ++v) coords(p.verts[v], t, c, &xyz_[3 * v]);
    for (std::uint32_t f = 0; f < p.nb_faces(); ++f) {
      const Plane plane = p.face_plane[f];
      std::uint32_t across = ClippedVoronoi3::kSurface;
      if (is_facet(plane)) {
        const std::uint32_t t2 = ctx_.domain.tet_adjacent(t, facet_of(plane));
        if (t2 != Domain3::kNone) {
          push(t2);
          across = ClippedVoronoi3::kInterior;
        }
      } else {
        across = static_cast<std::uint32_t>(plane);
        if (seeds_out) seeds_out->emplace_back(across, t);
      }
      // Fan from the face's first vertex, apex the site: signed tets.
      const std::uint32_t fb = p.face_begin[f], fe = p.face_begin[f + 1];
      const double* a = &xyz_[3 * std::size_t{p.face_verts[fb]}];
      for (std::uint32_t k = fb + 1; k + 1 < fe; ++k) {
        const double* b = &xyz_[3 * std::size_t{p.face_verts[k]}];
        const double* d = &xyz_[3 * std::size_t{p.face_verts[k + 1]}];
        if (ctx_.linear_density) {
          add_tet_linear(t, pc, a, b, d, res);
        } else {
          add_tet(pc, a, b, d, res);
        }
      }
      if (ctx_.options.keep_geometry) {
        for (std::uint32_t k = fb; k < fe; ++k) {
          const double* x = &xyz_[3 * std::size_t{p.face_verts[k]}];
          res.face_xyz.insert(res.face_xyz.end(), x, x + 3);
        }
        res.face_begin.push_back(static_cast<std::uint32_t>(res.face_xyz.size() / 3));
        res.face_piece.push_back(static_cast<std::uint32_t>(h));
        res.face_across.push_back(across);
      }
    }
  }
}

// Signed tet (o, a, b, d), faces oriented as Domain3::kTetFacetVertex (inward-facing
// for orient3d > 0): volume = -det(a - o, b - o, d - o) / 6.
void ConvexCell::add_tet(const double* o, const double* a, const double* b, const double* d,
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
void ConvexCell::add_tet_linear(std::uint32_t t, const double* o, const double* a, const double* b,
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
double ConvexCell::density_at(std::uint32_t t, const double* x) const {
  const double* p0 = ctx_.domain.vertex(ctx_.domain.tet_vertex(t, 0));
  double m[3][3], rhs[3];
  for (int k = 0; k < 3; ++k) {
    const double* pk = ctx_.domain.vertex(ctx_.domain.tet_vertex(t, k + 1));
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
  const std::vector<double>& rho = ctx_.options.density.vertex_values;
  return rho[ctx_.domain.tet_vertex(t, 0)] * (1 - l[0] - l[1] - l[2]) +
         rho[ctx_.domain.tet_vertex(t, 1)] * l[0] + rho[ctx_.domain.tet_vertex(t, 2)] * l[1] +
         rho[ctx_.domain.tet_vertex(t, 3)] * l[2];
}

}  // namespace clip3

}  // namespace voroclip
