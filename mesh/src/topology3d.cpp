// The topology of the boundary of a 3D CVT mesh (mesh.h, "the topology of the boundary").
//
// Closed-ball property (Edelsbrunner & Shah, "Triangulating topological spaces", IJCGA
// 1997): the restricted Voronoi diagram of a set of sites on a surface S has it when every
// restricted Voronoi cell V_i ∩ S is a closed disk, every restricted facet V_i ∩ V_j ∩ S is
// empty or a single arc, and every restricted edge V_i ∩ V_j ∩ V_k ∩ S is empty or a single
// point; the restricted Delaunay triangulation, dual to it, is then homeomorphic to S. The
// extracted mesh's boundary is made of the Delaunay triangles dual to the Voronoi edges
// that cross S (their tets' circumcentres lie on both sides), so this is the condition the
// mesher refines for (Boissonnat & Oudot, "Provably good sampling and meshing of surfaces",
// 2005, and Cheng, Dey & Ramos, 2007, insert the point of a bad restricted cell farthest
// from its site).
//
// The check reads the restricted polygons of ClippedVoronoi3 (keep_surface), whose vertices
// are symbolic (ClipVertex3): the same vertex has the same key in every polygon. Per cell:
//   - its polygons glued along their common edges (an edge on a mesh edge is shared by the
//     polygons of the two triangles; one on a bisector bounds the region): one connected
//     piece with Euler characteristic V - E + F = 1, and no edge in more than two polygons,
//     is a disk;
//   - per neighbour j, its boundary edges on bisector(i, j) (both ends on it: their site
//     lists hold j) form one path: connected, V = E + 1;
//   - a Voronoi edge (three sites) crosses S once: one facet-bisectors vertex per triple.
// A cell at a knife edge is passed over (closed_ball_defects in mesh.h) unless a piece of its
// region has no border (a whole shell of S inside the cell); and, given the surface, the
// cells of a shell that fewer than four cells meet always count (no closed restricted
// Delaunay surface has fewer than four vertices).
// All integer work on the symbolic keys: no floating-point decision; only the farthest
// point's choice compares distances.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "union_find.h"
#include "voroclip/mesh.h"

namespace voroclip {

namespace {

using mesh3::UnionFind;
using Key = std::array<std::uint32_t, 7>;

Key key_of(const ClipVertex3& v) {
  return {static_cast<std::uint32_t>(v.kind),
          v.mesh[0],
          v.mesh[1],
          v.mesh[2],
          v.site[0],
          v.site[1],
          v.site[2]};
}

bool has_site(const ClipVertex3& v, std::uint32_t s) {
  return v.site[0] == s || v.site[1] == s || v.site[2] == s;
}

// What is wrong with one cell: bit 0 not a disk, bit 1 a facet not an arc, bit 2 a Voronoi
// edge crossing S twice or more, bit 3 a closed piece (with bit 0): a connected part of the
// region with no edge on a bisector, so a whole shell of S inside the one cell.
constexpr int kNotDisk = 1, kNotArc = 2, kEdgeTwice = 4, kClosedPiece = 8;
struct CellScratch {
  std::vector<std::pair<Key, std::uint32_t>> keys;             // (key, corner index)
  std::vector<std::uint32_t> id;                               // per corner: its vertex id
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;  // (vertex pair, polygon)
  std::vector<std::pair<std::uint32_t, std::uint64_t>> arcs;   // (site across, vertex pair)
  UnionFind uf;
  std::vector<std::uint32_t> arc_vertices;
  // Per polygon: an edge of it borders the region (no other polygon has it); then per piece
  // (its root polygon): one of its polygons does.
  std::vector<std::uint8_t> open;
};

// Whether a restricted vertex lies on a knife edge (on it, or at one of its ends).
bool on_knife_edge(const ClipVertex3& v, const std::vector<std::uint64_t>& knife_edges,
                   const std::vector<std::uint32_t>& knife_vertices) {
  if (v.kind == ClipVertex3::Kind::kMeshVertex) {
    return std::binary_search(knife_vertices.begin(), knife_vertices.end(), v.mesh[0]);
  }
  if (v.kind == ClipVertex3::Kind::kEdgeBisector) {
    const std::uint64_t key =
        std::uint64_t{std::min(v.mesh[0], v.mesh[1])} << 32 | std::max(v.mesh[0], v.mesh[1]);
    return std::binary_search(knife_edges.begin(), knife_edges.end(), key);
  }
  return false;
}

int cell_defects(const ClippedVoronoi3::Polygons& sp, std::uint32_t i, CellScratch& s,
                 const std::vector<std::uint64_t>& knife_edges,
                 const std::vector<std::uint32_t>& knife_vertices) {
  const std::uint32_t p0 = sp.site_begin[i], p1 = sp.site_begin[i + 1];
  if (p0 == p1) return 0;
  const std::uint32_t c0 = sp.polygon_begin[p0], c1 = sp.polygon_begin[p1];
  // A cell at a knife edge counts only for a closed piece (no sampling gives it the rest).
  bool on_knife = false;
  for (std::uint32_t c = c0; c < c1 && !knife_edges.empty() && !on_knife; ++c) {
    on_knife = on_knife_edge(sp.vertices[c], knife_edges, knife_vertices);
  }
  // Vertex ids by key.
  s.keys.clear();
  for (std::uint32_t c = c0; c < c1; ++c) s.keys.emplace_back(key_of(sp.vertices[c]), c - c0);
  std::sort(s.keys.begin(), s.keys.end());
  s.id.assign(c1 - c0, 0);
  std::uint32_t nv = 0;
  int defects = 0;
  for (std::size_t r = 0; r < s.keys.size(); ++r) {
    if (r > 0 && s.keys[r].first != s.keys[r - 1].first) ++nv;
    s.id[s.keys[r].second] = nv;
    // Two crossings of one Voronoi edge: facet-bisectors vertices with the same sites in
    // two triangles (their keys differ by the mesh triangle).
    if (r > 0 &&
        s.keys[r].first[0] == static_cast<std::uint32_t>(ClipVertex3::Kind::kFacetBisectors) &&
        s.keys[r - 1].first[0] == s.keys[r].first[0] &&
        s.keys[r - 1].first[4] == s.keys[r].first[4] &&
        s.keys[r - 1].first[5] == s.keys[r].first[5] &&
        s.keys[r - 1].first[6] == s.keys[r].first[6] && s.keys[r - 1].first != s.keys[r].first) {
      defects |= kEdgeTwice;
    }
  }
  ++nv;
  // Edges, glued.
  s.edges.clear();
  s.arcs.clear();
  for (std::uint32_t p = p0; p < p1; ++p) {
    const std::uint32_t b = sp.polygon_begin[p], e = sp.polygon_begin[p + 1];
    for (std::uint32_t c = b; c < e; ++c) {
      const std::uint32_t d = c + 1 == e ? b : c + 1;
      const std::uint32_t u = s.id[c - c0], w = s.id[d - c0];
      if (u == w) continue;
      const std::uint64_t key = std::uint64_t{std::min(u, w)} << 32 | std::max(u, w);
      s.edges.emplace_back(key, p - p0);
      // On a bisector with site j: both ends' site lists hold i and j.
      const ClipVertex3& a = sp.vertices[c];
      const ClipVertex3& z = sp.vertices[d];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t j = a.site[k];
        if (j == ClipVertex3::kNone || j == i) continue;
        if (has_site(z, j)) s.arcs.emplace_back(j, key);
      }
    }
  }
  std::sort(s.edges.begin(), s.edges.end());
  const auto nf = p1 - p0;
  s.uf.reset(nf);
  s.open.assign(nf, 0);
  std::uint32_t ne = 0;
  for (std::size_t r = 0; r < s.edges.size();) {
    std::size_t q = r + 1;
    while (q < s.edges.size() && s.edges[q].first == s.edges[r].first) ++q;
    if (q - r > 2) defects |= kNotDisk;
    if (q - r == 1) s.open[s.edges[r].second] = 1;  // on the region's border
    for (std::size_t t = r + 1; t < q; ++t) s.uf.unite(s.edges[r].second, s.edges[t].second);
    ++ne;
    r = q;
  }
  const long chi = static_cast<long>(nv) - static_cast<long>(ne) + static_cast<long>(nf);
  if (s.uf.count() != 1 || chi != 1) defects |= kNotDisk;
  // A piece none of whose edges borders it is closed: a shell of S (each of whose edges is
  // in two triangles) wholly inside the cell, where the restricted Delaunay triangulation
  // has no triangle. A part far smaller than the spacing (a small body beside a large one)
  // lies so, whatever its edges.
  for (std::uint32_t p = 0; p < nf; ++p) {
    if (s.open[p] != 0) s.open[s.uf.find(p)] = 1;
  }
  for (std::uint32_t p = 0; p < nf; ++p) {
    if (s.uf.find(p) == p && s.open[p] == 0) defects |= kNotDisk | kClosedPiece;
  }
  if (on_knife) return defects & kClosedPiece ? defects : 0;
  // Arcs: per site across, the region's boundary edges on that bisector form one path.
  std::sort(s.arcs.begin(), s.arcs.end());
  s.arcs.erase(std::unique(s.arcs.begin(), s.arcs.end()), s.arcs.end());
  for (std::size_t r = 0; r < s.arcs.size();) {
    std::size_t q = r + 1;
    while (q < s.arcs.size() && s.arcs[q].first == s.arcs[r].first) ++q;
    s.arc_vertices.clear();
    for (std::size_t t = r; t < q; ++t) {
      s.arc_vertices.push_back(static_cast<std::uint32_t>(s.arcs[t].second >> 32));
      s.arc_vertices.push_back(static_cast<std::uint32_t>(s.arcs[t].second & 0xffffffffu));
    }
    std::sort(s.arc_vertices.begin(), s.arc_vertices.end());
    s.arc_vertices.erase(std::unique(s.arc_vertices.begin(), s.arc_vertices.end()),
                         s.arc_vertices.end());
    const auto na = static_cast<std::uint32_t>(q - r);
    if (s.arc_vertices.size() != std::size_t{na} + 1) {
      defects |= kNotArc;
    } else {
      s.uf.reset(s.arc_vertices.size());
      const auto local = [&](std::uint32_t v) {
        return static_cast<std::uint32_t>(
            std::lower_bound(s.arc_vertices.begin(), s.arc_vertices.end(), v) -
            s.arc_vertices.begin());
      };
      for (std::size_t t = r; t < q; ++t) {
        s.uf.unite(local(static_cast<std::uint32_t>(s.arcs[t].second >> 32)),
                   local(static_cast<std::uint32_t>(s.arcs[t].second & 0xffffffffu)));
      }
      if (s.uf.count() != 1) defects |= kNotArc;
    }
    r = q;
  }
  return defects;
}

}  // namespace

ClosedBallDefects closed_ball_defects(const ClippedVoronoi3& cv, const double* sites,
                                      const std::vector<std::uint64_t>& knife_edges,
                                      const Surface3* surface) {
  if (!std::is_sorted(knife_edges.begin(), knife_edges.end())) {
    throw Error("closed_ball_defects: the knife edges are not sorted");
  }
  std::vector<std::uint32_t> knife_vertices;
  for (const std::uint64_t e : knife_edges) {
    knife_vertices.push_back(static_cast<std::uint32_t>(e >> 32));
    knife_vertices.push_back(static_cast<std::uint32_t>(e & 0xffffffffu));
  }
  std::sort(knife_vertices.begin(), knife_vertices.end());
  knife_vertices.erase(std::unique(knife_vertices.begin(), knife_vertices.end()),
                       knife_vertices.end());
  const ClippedVoronoi3::Polygons& sp = cv.surface_polygons();
  if (sp.site_begin.size() != std::size_t{cv.nb_sites()} + 1) {
    throw Error("closed_ball_defects: the diagram was computed without keep_surface");
  }
  const std::uint32_t n = cv.nb_sites();
  std::vector<std::int8_t> defect(n, 0);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 256), [&](const auto& range) {
    CellScratch s;
    for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
      defect[i] = static_cast<std::int8_t>(cell_defects(sp, i, s, knife_edges, knife_vertices));
    }
  });
  if (surface != nullptr) {
    // A shell that fewer than four cells meet has no closed restricted Delaunay surface (it
    // needs four vertices at least), knife edges or not: its cells count (as not disks).
    std::vector<std::uint64_t> met;  // shell << 32 | cell, per polygon
    for (std::uint32_t i = 0; i < n; ++i) {
      for (std::uint32_t p = sp.site_begin[i]; p < sp.site_begin[i + 1]; ++p) {
        met.push_back(std::uint64_t{surface->shell_of(sp.triangle[p])} << 32 | i);
      }
    }
    std::sort(met.begin(), met.end());
    met.erase(std::unique(met.begin(), met.end()), met.end());
    for (std::size_t r = 0; r < met.size();) {
      std::size_t q = r + 1;
      while (q < met.size() && met[q] >> 32 == met[r] >> 32) ++q;
      if (q - r < 4) {
        for (std::size_t t = r; t < q; ++t) {
          defect[met[t] & 0xffffffffu] |= static_cast<std::int8_t>(kNotDisk);
        }
      }
      r = q;
    }
  }
  ClosedBallDefects d;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (defect[i] == 0) continue;
    d.nb_not_disk += defect[i] & kNotDisk ? 1 : 0;
    d.nb_facets += defect[i] & kNotArc ? 1 : 0;
    d.nb_edges += defect[i] & kEdgeTwice ? 1 : 0;
    d.cells.push_back(i);
    // The region's vertex farthest from the site.
    const double* p = sites + 3 * std::size_t{i};
    double best = -1;
    std::uint32_t arg = 0;
    for (std::uint32_t c = sp.polygon_begin[sp.site_begin[i]];
         c < sp.polygon_begin[sp.site_begin[i + 1]]; ++c) {
      const double* x = &sp.xyz[3 * std::size_t{c}];
      const double d2 = (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) +
                        (x[2] - p[2]) * (x[2] - p[2]);
      if (d2 > best) {
        best = d2;
        arg = c;
      }
    }
    d.points.insert(d.points.end(), &sp.xyz[3 * std::size_t{arg}],
                    &sp.xyz[3 * std::size_t{arg}] + 3);
  }
  return d;
}

}  // namespace voroclip

namespace voroclip {

std::string check_mesh3_shape(const Domain3& domain, const std::vector<double>& xyz,
                              const std::vector<std::uint32_t>& tets) {
  if (tets.empty()) return "the mesh has no tets";
  TetMeshInput m;
  m.source = "the mesh";
  m.xyz = xyz;
  m.tets = tets;
  Domain3 out;
  try {
    out = Domain3(m);
  } catch (const Error& e) {
    return std::string("its tets do not make a valid volume: ") + e.what();
  }
  struct Shape {
    std::uint32_t depth, genus;
    double volume;
    std::uint32_t shell;
    bool operator<(const Shape& o) const {
      if (depth != o.depth) return depth < o.depth;
      if (genus != o.genus) return genus < o.genus;
      return std::abs(volume) > std::abs(o.volume);
    }
  };
  const auto shapes = [](const Surface3& s) {
    std::vector<Shape> v;
    for (std::uint32_t k = 0; k < s.shells().size(); ++k) {
      const Surface3::Shell& sh = s.shells()[k];
      v.push_back({sh.depth, sh.genus, sh.volume, k});
    }
    std::sort(v.begin(), v.end());
    return v;
  };
  const std::vector<Shape> want = shapes(domain.surface()), got = shapes(out.surface());
  const auto where = [&](const Surface3& s, std::uint32_t shell) {
    const double* p = s.vertex(s.triangle_vertex(s.shells()[shell].first_triangle, 0));
    return "(" + std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " + std::to_string(p[2]) +
           ")";
  };
  if (got.size() != want.size()) {
    std::string what = "its boundary has " + std::to_string(got.size()) +
                       (got.size() == 1 ? " shell" : " shells") + " where the domain has " +
                       std::to_string(want.size());
    if (got.size() < want.size()) {
      // Name the smallest shell of the domain that no vertex of the mesh's boundary is
      // nearest to: a part smaller than the edges, usually, that got no vertices.
      const Surface3& in = domain.surface();
      const SurfaceTree tree(boundary_surface(domain));
      std::vector<std::uint8_t> reached(in.shells().size(), 0);
      const Surface3& mine = out.surface();
      std::vector<std::uint8_t> asked(mine.nb_vertices(), 0);  // each boundary vertex once
      for (const std::uint32_t v : mine.triangles()) {
        if (asked[v] != 0) continue;
        asked[v] = 1;
        const SurfaceTree::Closest c = tree.closest(mine.vertex(v));
        if (c.triangle != SurfaceTree::kNone) reached[in.shell_of(c.triangle)] = 1;
      }
      std::uint32_t missing = SurfaceTree::kNone;
      for (std::uint32_t k = 0; k < in.shells().size(); ++k) {
        if (reached[k] == 0 &&
            (missing == SurfaceTree::kNone ||
             std::abs(in.shells()[k].volume) < std::abs(in.shells()[missing].volume))) {
          missing = k;
        }
      }
      if (missing != SurfaceTree::kNone) {
        double lo[3], hi[3];
        for (int c = 0; c < 3; ++c) {
          lo[c] = std::numeric_limits<double>::infinity();
          hi[c] = -lo[c];
        }
        for (std::uint32_t t = 0; t < in.nb_triangles(); ++t) {
          if (in.shell_of(t) != missing) continue;
          for (int k = 0; k < 3; ++k) {
            const double* p = in.vertex(in.triangle_vertex(t, k));
            for (int c = 0; c < 3; ++c) {
              lo[c] = std::min(lo[c], p[c]);
              hi[c] = std::max(hi[c], p[c]);
            }
          }
        }
        const double across =
            std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
        what += " (none of its vertices is nearest to the domain's shell at " + where(in, missing) +
                ", " + std::to_string(in.shells()[missing].nb_triangles) + " triangles, " +
                std::to_string(across) + " across: a part smaller than the edges gets no vertices)";
      }
    }
    if (got.size() > want.size()) {
      // The smallest ones are likely the strays: name the smallest.
      std::uint32_t smallest = 0;
      for (std::uint32_t k = 1; k < out.surface().shells().size(); ++k) {
        if (std::abs(out.surface().shells()[k].volume) <
            std::abs(out.surface().shells()[smallest].volume)) {
          smallest = k;
        }
      }
      what += " (the smallest, " + std::to_string(out.surface().shells()[smallest].nb_triangles) +
              " triangles, at " + where(out.surface(), smallest) + ")";
    }
    return what;
  }
  for (std::size_t k = 0; k < want.size(); ++k) {
    if (got[k].genus != want[k].genus || got[k].depth != want[k].depth) {
      return "a boundary shell of genus " + std::to_string(got[k].genus) + " at " +
             where(out.surface(), got[k].shell) + " where the domain's has genus " +
             std::to_string(want[k].genus);
    }
  }
  return "";
}

}  // namespace voroclip
