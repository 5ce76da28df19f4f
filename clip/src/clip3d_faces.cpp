// The faces of the cells of the 3D clipped Voronoi diagram, for export (keep_geometry;
// ClippedVoronoi3::cell_faces): DelaunayCells' voronoi_facets and boundary_faces
// (clip3d_cells.h). Yan et al. 2011 (sec. 4) integrate cells without their faces; these
// give them from the same data: an inner cell's Voronoi facets are rings of circumcentres
// of the Delaunay tets around its Delaunay edges, and a boundary cell's faces are its
// restricted surface polygons plus, per bisector, the loops chained from the pieces of its
// Voronoi edges inside the volume (boundary_cell) and the edges of its polygons on that
// bisector. Points are computed from their symbolic vertices wherever they are met (the
// same bits), so the loops are chained on coordinates.
#include "clip3d_cells.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace voroclip {

namespace clip3 {

namespace {

[[noreturn]] void internal_error(const std::string& what) {
  throw Error("clip3d: internal error: " + what);
}

}  // namespace

void DelaunayCells::voronoi_facets(std::uint32_t c, std::uint32_t piece, Stars& stars, Scratch& s,
                                   CellOut& res) const {
  // Per Delaunay edge (c, j), the circumcentres of the tets around it, taken from the first
  // star tet with that edge: crossing the facet f with kFaceOther[ic][f][0] == ij goes
  // counter-clockwise around p_j - p_c (kFaceOther), that is, outwards; the ring is then
  // reversed. edge_done marks every (tet, vertex) a ring has used.
  const Star& st = stars.star(ctx_, c);
  const std::size_t m = st.tets.size();
  s.edge_done.assign(4 * m, 0);
  const auto local = [&](std::uint32_t t, std::uint32_t v) {
    int k = 0;
    while (ctx_.dt.tet_vertex(t, k) != v) ++k;  // v is a vertex of t
    return k;
  };
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t t = st.tets[q];
    if (ctx_.dt.is_infinite(t)) internal_error("inner cell " + std::to_string(c) + " is unbounded");
    const int ic = local(t, c);
    for (int ij = 0; ij < 4; ++ij) {
      if (ij == ic || s.edge_done[4 * q + static_cast<std::size_t>(ij)] != 0) continue;
      const std::uint32_t j = ctx_.dt.tet_vertex(t, ij);
      const std::size_t first = res.face_xyz.size();
      std::uint32_t u = t;
      int uc = ic, uj = ij;
      do {  // (u is a star tet: finite)
        const std::uint32_t v[4] = {ctx_.dt.tet_vertex(u, 0), ctx_.dt.tet_vertex(u, 1),
                                    ctx_.dt.tet_vertex(u, 2), ctx_.dt.tet_vertex(u, 3)};
        s.edge_done[4 * std::size_t{st.pos(u)} + static_cast<std::size_t>(uj)] = 1;
        const double* x = circumcentre(u, v, s.circ);
        res.face_xyz.insert(res.face_xyz.end(), x, x + 3);
        int f = 0;
        while (f == uc || f == uj || kFaceOther[uc][f][0] != uj) ++f;
        u = ctx_.dt.tet_adjacent(u, f);
        uc = local(u, c);
        uj = local(u, j);
      } while (u != t);
      // Reversed, point by point: inwards.
      for (std::size_t a = first, b = res.face_xyz.size() - 3; a < b; a += 3, b -= 3) {
        for (std::size_t k = 0; k < 3; ++k) std::swap(res.face_xyz[a + k], res.face_xyz[b + k]);
      }
      res.face_begin.push_back(static_cast<std::uint32_t>(res.face_xyz.size() / 3));
      res.face_piece.push_back(piece);
      res.face_across.push_back(j);
    }
  }
}

void DelaunayCells::boundary_faces(std::uint32_t i, std::uint32_t piece, const std::int8_t* flag,
                                   const ClippedVoronoi3::Polygons& surface, Stars& stars,
                                   Scratch& s, std::vector<Segment>& segments, CellOut& res) const {
  segments.clear();
  Moments unused;
  boundary_cell(i, flag, stars, s, unused, &segments);
  const ClippedVoronoi3::Polygons& sp = surface;
  const auto emit_reversed = [&](const double* const* pts, std::size_t m, std::uint32_t across) {
    for (std::size_t k = m; k-- > 0;) res.face_xyz.insert(res.face_xyz.end(), pts[k], pts[k] + 3);
    res.face_begin.push_back(static_cast<std::uint32_t>(res.face_xyz.size() / 3));
    res.face_piece.push_back(piece);
    res.face_across.push_back(across);
  };
  std::vector<const double*> pts;
  // The restricted polygons, and their edges on bisectors (the face across runs through
  // such an edge the other way).
  for (std::uint32_t p = sp.site_begin[i]; p < sp.site_begin[i + 1]; ++p) {
    const std::uint32_t b = sp.polygon_begin[p], e = sp.polygon_begin[p + 1];
    pts.clear();
    for (std::uint32_t v = b; v < e; ++v) pts.push_back(&sp.xyz[3 * std::size_t{v}]);
    emit_reversed(pts.data(), pts.size(), ClippedVoronoi3::kSurface);
    for (std::uint32_t v = b; v < e; ++v) {
      const std::uint32_t j = rs_.surface_across[v];
      if (j == kNone) continue;
      const double* from = &sp.xyz[3 * std::size_t{v}];
      const double* to = &sp.xyz[3 * std::size_t{v + 1 == e ? b : v + 1}];
      Segment& g = segments.emplace_back();
      g.across = j;
      for (int c = 0; c < 3; ++c) {
        g.a[c] = to[c];
        g.b[c] = from[c];
      }
    }
  }
  // Per bisector, the segments chained into loops on their points' coordinates (a point is
  // computed from its symbolic vertex wherever it is met: the same bits), each loop emitted
  // reversed (inwards). Where several loops pass through one point, they are paired there in
  // segment order (the loops may differ, the face they bound does not).
  std::stable_sort(segments.begin(), segments.end(),
                   [](const Segment& x, const Segment& y) { return x.across < y.across; });
  using Key = std::array<std::uint64_t, 3>;
  const auto key = [](const double* x) {
    Key k;
    std::memcpy(k.data(), x, sizeof k);
    return k;
  };
  std::vector<std::pair<Key, std::uint32_t>> keys;
  std::vector<std::uint32_t> seg_from, seg_to, out_begin, out_list;
  std::vector<const double*> point_of;
  std::vector<std::uint8_t> used;
  for (std::size_t g0 = 0; g0 < segments.size();) {
    std::size_t g1 = g0;
    while (g1 < segments.size() && segments[g1].across == segments[g0].across) ++g1;
    const std::size_t m = g1 - g0;
    keys.clear();
    for (std::size_t k = g0; k < g1; ++k) {
      keys.emplace_back(key(segments[k].a), static_cast<std::uint32_t>(2 * (k - g0)));
      keys.emplace_back(key(segments[k].b), static_cast<std::uint32_t>(2 * (k - g0) + 1));
    }
    std::sort(keys.begin(), keys.end());
    seg_from.assign(m, 0);
    seg_to.assign(m, 0);
    point_of.clear();
    for (std::size_t r = 0; r < keys.size(); ++r) {
      if (r == 0 || keys[r].first != keys[r - 1].first) {
        const std::uint32_t e = keys[r].second;
        const Segment& sg = segments[g0 + e / 2];
        point_of.push_back(e % 2 == 0 ? sg.a : sg.b);
      }
      const auto id = static_cast<std::uint32_t>(point_of.size() - 1);
      (keys[r].second % 2 == 0 ? seg_from : seg_to)[keys[r].second / 2] = id;
    }
    // Outgoing segments per point, in segment order.
    const std::size_t nb_points = point_of.size();
    out_begin.assign(nb_points + 1, 0);
    for (std::size_t k = 0; k < m; ++k) ++out_begin[seg_from[k] + 1];
    for (std::size_t v = 0; v < nb_points; ++v) out_begin[v + 1] += out_begin[v];
    out_list.resize(m);
    {
      std::vector<std::uint32_t> fill(out_begin.begin(), out_begin.end() - 1);
      for (std::size_t k = 0; k < m; ++k)
        out_list[fill[seg_from[k]]++] = static_cast<std::uint32_t>(k);
    }
    used.assign(m, 0);
    // A segment of zero length (both ends equal) bounds nothing.
    for (std::size_t k = 0; k < m; ++k) used[k] = seg_from[k] == seg_to[k] ? 1 : 0;
    for (std::size_t k0 = 0; k0 < m; ++k0) {
      if (used[k0]) continue;
      pts.clear();
      std::size_t k = k0;
      bool closed = false;
      for (;;) {
        used[k] = 1;
        pts.push_back(point_of[seg_from[k]]);
        const std::uint32_t v = seg_to[k];
        if (v == seg_from[k0]) {
          closed = true;
          break;
        }
        std::size_t next = m;
        for (std::uint32_t e = out_begin[v]; e < out_begin[v + 1]; ++e) {
          if (!used[out_list[e]]) {
            next = out_list[e];
            break;
          }
        }
        if (next == m) break;
        k = next;
      }
      if (closed && pts.size() >= 3) emit_reversed(pts.data(), pts.size(), segments[g0].across);
    }
    g0 = g1;
  }
}

}  // namespace clip3

}  // namespace voroclip
