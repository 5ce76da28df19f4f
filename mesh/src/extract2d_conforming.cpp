// Conforming extraction of a 2D mesh (mesh.h, step 6): the constrained Delaunay
// triangulation of the sites with the boundary chains as segments, restricted to the
// inside of the chains; and the exact check that a mesh conforms to its domain.
//
// The boundary sites of each ring (sites at its vertices and sites on its edges) are put
// in ring order: by edge, then along the edge. The order along an edge is exact: by the
// coordinate along which the edge extends most (ascending when the edge goes that way),
// ties by the other coordinate; sites a few ulps off their edge (mesh.h, "Coordinates")
// keep the order of their exact projections whenever those are farther apart than the
// rounding. Consecutive sites make the ring's chain. Each chain segment is inserted into
// the Delaunay triangulation of all sites (cdt2.h); then a flood fill across the
// unconstrained edges, seeded on both sides of every chain segment (the domain is on the
// left of a ring), labels each triangle inside or outside; a region reached from both
// sides would mean crossing chains and is an error (never seen: chains follow disjoint
// rings within a few ulps).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "boundary_edge2d.h"
#include "cdt2.h"
#include "edge_grid2.h"
#include "voroclip/mesh.h"

namespace voroclip {

namespace {

constexpr std::uint32_t kNone = Mesh2::kNone;

// Orders points near the edge a -> b along it (see above).
struct AlongEdge {
  int axis = 0;     // 0: x, 1: y
  bool up[2] = {};  // coordinate increasing from a to b (per axis)
  AlongEdge(const double* a, const double* b) {
    axis = std::fabs(b[0] - a[0]) >= std::fabs(b[1] - a[1]) ? 0 : 1;
    up[0] = b[0] >= a[0];
    up[1] = b[1] >= a[1];
  }
  bool less(const double* p, const double* q) const {
    const int o = 1 - axis;
    if (p[axis] != q[axis]) return up[axis] ? p[axis] < q[axis] : p[axis] > q[axis];
    return up[o] ? p[o] < q[o] : p[o] > q[o];
  }
};

}  // namespace

Mesh2 extract_conforming_mesh2(const Domain2& domain, const std::vector<double>& sites,
                               const std::vector<Mesh2::VertexKind>& kinds,
                               const std::vector<std::uint32_t>& site_domain,
                               const std::vector<std::uint32_t>& site_edge, Extract2Stats* stats) {
  if (sites.size() % 2 != 0) throw Error("extract_conforming_mesh2: odd site array length");
  const auto n = static_cast<std::uint32_t>(sites.size() / 2);
  if (kinds.size() != n || site_domain.size() != n || site_edge.size() != n) {
    throw Error(
        "extract_conforming_mesh2: kinds, site_domain and site_edge must have one "
        "entry per site (" +
        std::to_string(n) + ")");
  }
  const Delaunay2 dt(sites.data(), n);
  mesh2d::Cdt2 cdt(dt);

  // Per site: its canonical vertex, and the site whose data the vertex takes (a fixed site
  // wins over a sliding one at the same point).
  std::vector<std::uint32_t> data_site(n, kNone);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t c = dt.duplicate_of(i);
    if (data_site[c] == kNone || (kinds[i] == Mesh2::VertexKind::kFixed &&
                                  kinds[data_site[c]] != Mesh2::VertexKind::kFixed)) {
      data_site[c] = i;
    }
  }

  // Boundary chains, ring by ring.
  struct Entry {
    std::uint32_t edge;  // position of the edge in its ring
    std::uint32_t site;
  };
  std::vector<std::vector<Entry>> rings(domain.nb_rings());
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t e = kNone;
    if (site_domain[i] != kNone) {
      if (site_domain[i] >= domain.nb_vertices()) {
        throw Error("extract_conforming_mesh2: site " + std::to_string(i) +
                    " names domain vertex " + std::to_string(site_domain[i]) + " of " +
                    std::to_string(domain.nb_vertices()));
      }
      e = site_domain[i];
    } else if (site_edge[i] != kNone) {
      if (site_edge[i] >= domain.nb_edges()) {
        throw Error("extract_conforming_mesh2: site " + std::to_string(i) + " names domain edge " +
                    std::to_string(site_edge[i]) + " of " + std::to_string(domain.nb_edges()));
      }
      e = site_edge[i];
    } else {
      continue;
    }
    const std::uint32_t r = domain.ring_of(e);
    rings[r].push_back({e - domain.ring_begin(r), dt.duplicate_of(i)});
  }
  std::vector<std::uint32_t> chain_edges;  // directed sub-edges, domain on the left
  std::uint32_t nb_segments = 0;
  for (std::uint32_t r = 0; r < domain.nb_rings(); ++r) {
    std::vector<Entry>& list = rings[r];
    std::sort(list.begin(), list.end(), [&](const Entry& p, const Entry& q) {
      if (p.edge != q.edge) return p.edge < q.edge;
      if (p.site == q.site) return false;
      const std::uint32_t e = domain.ring_begin(r) + p.edge;
      const AlongEdge along(domain.vertex(e), domain.vertex(domain.next(e)));
      const double* a = dt.point(p.site);
      const double* b = dt.point(q.site);
      // A site at the edge's start vertex comes first.
      const bool pa = site_domain[data_site[p.site]] == e;
      const bool qa = site_domain[data_site[q.site]] == e;
      if (pa != qa) return pa;
      return along.less(a, b);
    });
    list.erase(std::unique(list.begin(), list.end(),
                           [](const Entry& p, const Entry& q) { return p.site == q.site; }),
               list.end());
    while (list.size() > 1 && list.back().site == list.front().site) list.pop_back();
    if (list.size() < 3) {
      throw Error("mesh2d: ring " + std::to_string(domain.source_ring(r)) + " has only " +
                  std::to_string(list.size()) + " boundary sites; a ring needs 3 or more");
    }
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::uint32_t a = list[k].site, b = list[(k + 1) % list.size()].site;
      std::vector<std::uint32_t> pieces;
      cdt.insert_segment(a, b, &pieces);
      chain_edges.insert(chain_edges.end(), pieces.begin(), pieces.end());
      ++nb_segments;
    }
  }
  const std::uint32_t recovery_flips = cdt.nb_flips();
  const std::uint32_t delaunay_flips = cdt.make_delaunay();

  // Inside / outside: flood fill from both sides of every chain edge.
  const std::uint32_t nt = cdt.nb_triangles();
  std::vector<std::uint8_t> label(nt, 0);  // 0 unknown, 1 inside, 2 outside
  std::vector<std::uint32_t> stack;
  const auto fill = [&](std::uint32_t seed, std::uint8_t value) {
    if (seed == kNone) return;
    if (label[seed] == value) return;
    if (label[seed] != 0) {
      throw Error("mesh2d: the boundary chains cross (a region is both inside and outside)");
    }
    label[seed] = value;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::uint32_t t = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        if (cdt.constrained(t, k)) continue;
        const std::uint32_t code = cdt.across(t, k);
        if (code == kNone) continue;
        const std::uint32_t u = code / 3;
        if (label[u] == value) continue;
        if (label[u] != 0) {
          throw Error("mesh2d: the boundary chains cross (a region is both inside and outside)");
        }
        label[u] = value;
        stack.push_back(u);
      }
    }
  };
  for (std::size_t k = 0; k + 1 < chain_edges.size(); k += 2) {
    int local = 0;
    fill(cdt.find_edge(chain_edges[k], chain_edges[k + 1], &local), 1);
    fill(cdt.find_edge(chain_edges[k + 1], chain_edges[k], &local), 2);
  }

  Mesh2 mesh;
  Extract2Stats st;
  st.nb_delaunay = dt.nb_triangles();
  st.nb_boundary_segments = nb_segments;
  st.nb_recovery_flips = recovery_flips;
  st.nb_delaunay_flips = delaunay_flips;
  std::vector<std::uint32_t> index(n, kNone);
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (label[t] != 1) continue;
    for (int k = 0; k < 3; ++k) index[cdt.vertex(t, k)] = 0;
  }
  std::uint32_t used = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (index[v] == kNone) continue;
    index[v] = used++;
    const std::uint32_t s = data_site[v];
    mesh.xy.push_back(sites[2 * std::size_t{v}]);
    mesh.xy.push_back(sites[2 * std::size_t{v} + 1]);
    mesh.vertex_kind.push_back(kinds[s]);
    mesh.vertex_domain.push_back(site_domain[s]);
    mesh.vertex_edge.push_back(site_edge[s]);
    mesh.vertex_site.push_back(s);
  }
  for (std::uint32_t t = 0; t < nt; ++t) {
    if (label[t] != 1) continue;
    for (int k = 0; k < 3; ++k) mesh.triangles.push_back(index[cdt.vertex(t, k)]);
  }
  st.removed_vertices = dt.nb_vertices() - used;
  if (stats) *stats = std::move(st);
  return mesh;
}

}  // namespace voroclip

namespace voroclip {

namespace {

// The box of the doubles within `ulps` steps of p, per coordinate.
void ulp_box(const double* p, int ulps, double* lo, double* hi) {
  for (int c = 0; c < 2; ++c) {
    lo[c] = hi[c] = p[c];
    for (int k = 0; k < ulps; ++k) {
      lo[c] = std::nextafter(lo[c], -std::numeric_limits<double>::infinity());
      hi[c] = std::nextafter(hi[c], std::numeric_limits<double>::infinity());
    }
  }
}

}  // namespace

std::string check_mesh2_conforming(const Domain2& domain, const Mesh2& mesh, bool corners) {
  constexpr int kUlps = 16;
  const std::uint32_t nv = mesh.nb_vertices(), nt = mesh.nb_triangles();
  // Straight runs of the boundary: edges joined at vertices that are not corners.
  std::vector<std::uint32_t> run(domain.nb_edges(), kNone);
  std::uint32_t nb_runs = 0;
  for (std::uint32_t r = 0; r < domain.nb_rings(); ++r) {
    std::uint32_t start = domain.ring_begin(r);
    while (start < domain.ring_end(r) && !domain.is_corner(start)) ++start;
    // A ring has corners (it is not all collinear); walk from one.
    std::uint32_t e = start;
    do {
      if (domain.is_corner(e)) ++nb_runs;
      run[e] = nb_runs - 1;
      e = domain.next(e);
    } while (e != start);
  }
  // Per mesh vertex, the runs whose edges pass within kUlps of it.
  const mesh2d::EdgeGrid2 grid(domain);
  std::vector<std::vector<std::uint32_t>> near(nv);
  const auto runs_near = [&](std::uint32_t v) -> const std::vector<std::uint32_t>& {
    std::vector<std::uint32_t>& out = near[v];
    if (!out.empty()) return out;
    double lo[2], hi[2];
    ulp_box(&mesh.xy[2 * std::size_t{v}], kUlps, lo, hi);
    grid.for_each_in_box(lo, hi, [&](std::uint32_t e) {
      if (mesh2d::box_meets_segment(lo, hi, domain.vertex(e), domain.vertex(domain.next(e)))) {
        out.push_back(run[e]);
      }
    });
    if (out.empty()) out.push_back(kNone);
    return out;
  };
  std::unordered_map<std::uint64_t, std::uint32_t> directed;
  directed.reserve(3 * std::size_t{nt});
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = mesh.triangles[3 * std::size_t{t} + k];
      const std::uint64_t b = mesh.triangles[3 * std::size_t{t} + (k + 1) % 3];
      directed.emplace(a << 32 | b, t);
    }
  }
  long double boundary_length = 0;
  for (const auto& [key, t] : directed) {
    const auto a = static_cast<std::uint32_t>(key >> 32);
    const auto b = static_cast<std::uint32_t>(key & 0xffffffffu);
    if (directed.count(std::uint64_t{b} << 32 | a)) continue;
    boundary_length +=
        std::hypot(mesh.xy[2 * std::size_t{b}] - mesh.xy[2 * std::size_t{a}],
                   mesh.xy[2 * std::size_t{b} + 1] - mesh.xy[2 * std::size_t{a} + 1]);
    const std::vector<std::uint32_t>& ra = runs_near(a);
    const std::vector<std::uint32_t>& rb = runs_near(b);
    bool shared = false;
    for (const std::uint32_t x : ra) {
      shared = shared || (x != kNone && std::find(rb.begin(), rb.end(), x) != rb.end());
    }
    if (!shared) {
      return "the boundary edge " + std::to_string(a) + "-" + std::to_string(b) + " of triangle " +
             std::to_string(t) +
             " does not lie along one straight part of "
             "the domain's boundary";
    }
  }
  if (corners) {
    const auto key = [](const double* p) {
      std::uint64_t x, y;
      std::memcpy(&x, &p[0], 8);
      std::memcpy(&y, &p[1], 8);
      return x * 0x9e3779b97f4a7c15ull ^ y;
    };
    std::unordered_multimap<std::uint64_t, std::uint32_t> index;
    for (std::uint32_t v = 0; v < nv; ++v) index.emplace(key(&mesh.xy[2 * std::size_t{v}]), v);
    for (std::uint32_t v = 0; v < domain.nb_vertices(); ++v) {
      if (!domain.is_corner(v)) continue;
      const double* p = domain.vertex(v);
      bool found = false;
      const auto range = index.equal_range(key(p));
      for (auto it = range.first; it != range.second && !found; ++it) {
        const double* q = &mesh.xy[2 * std::size_t{it->second}];
        found = q[0] == p[0] && q[1] == p[1];
      }
      if (!found) {
        return "the domain's corner " + std::to_string(v) + " (" + std::to_string(p[0]) + ", " +
               std::to_string(p[1]) + ") is not a mesh vertex";
      }
    }
  }
  long double area = 0;
  for (std::uint32_t t = 0; t < nt; ++t) {
    const double* a = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t}]}];
    const double* b = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + 1]}];
    const double* c = &mesh.xy[2 * std::size_t{mesh.triangles[3 * std::size_t{t} + 2]}];
    area +=
        0.5L * ((static_cast<long double>(b[0]) - a[0]) * (static_cast<long double>(c[1]) - a[1]) -
                (static_cast<long double>(b[1]) - a[1]) * (static_cast<long double>(c[0]) - a[0]));
  }
  // The boundary vertices lie within kUlps ulps (per coordinate) of the boundary, so the
  // boundary chains may enclose up to 2 kUlps ulps times their length more or less than the
  // domain: with the ulp of the largest coordinate, that bound is below 1e-12 of the area
  // for a domain near the origin, and far above it for a small one far from it (a triangle
  // of side 1e-4 at (1e6, 1e6): 1.2e-12 against an area of 5e-9; its sliding vertices,
  // rounded a few ulps into the domain, cut 2.4e-14 off it, and the check failed).
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  const double big =
      std::max({std::fabs(lo[0]), std::fabs(lo[1]), std::fabs(hi[0]), std::fabs(hi[1])});
  const double ulp = std::nextafter(big, std::numeric_limits<double>::infinity()) - big;
  const long double rounding = 2.0L * kUlps * ulp * boundary_length;
  const long double gap = std::fabs(area - static_cast<long double>(domain.area()));
  if (gap > 1e-12L * domain.area() + rounding) {
    std::ostringstream s;
    s << std::setprecision(17) << "the triangles' areas sum to " << static_cast<double>(area)
      << ", the domain's area is " << domain.area() << " (relative gap "
      << static_cast<double>(gap / domain.area()) << ", above 1e-12";
    if (rounding > 0) {
      s << " plus the boundary's rounding, " << static_cast<double>(rounding / domain.area());
    }
    s << ")";
    return s.str();
  }
  return "";
}

}  // namespace voroclip

namespace voroclip {

void tag_mesh2(const Domain2& domain, Mesh2& mesh) {
  const std::uint32_t nt = mesh.nb_triangles();
  std::unordered_map<std::uint64_t, std::uint32_t> directed;  // edge -> 3 t + k
  directed.reserve(3 * std::size_t{nt});
  const auto tri = [&](std::uint32_t t, int k) { return mesh.triangles[3 * std::size_t{t} + k]; };
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      directed.emplace(std::uint64_t{tri(t, k)} << 32 | tri(t, (k + 1) % 3),
                       3 * t + static_cast<std::uint32_t>(k));
    }
  }
  // Boundary edges in triangle order, with the domain edge under each.
  mesh.boundary_edges.clear();
  mesh.boundary_tags.clear();
  std::unique_ptr<mesh2d::EdgeGrid2> grid;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edge_triangle;  // (t, domain edge)
  for (std::uint32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri(t, k), b = tri(t, (k + 1) % 3);
      if (directed.count(std::uint64_t{b} << 32 | a)) continue;
      std::uint32_t e = mesh2d::domain_edge_under(domain, mesh, a, b);
      if (e == kNone) {
        // A vertex without boundary data (a free site that ended on the boundary): the
        // nearest domain edge to the edge's midpoint (tags change only at mesh vertices).
        if (!grid) grid = std::make_unique<mesh2d::EdgeGrid2>(domain);
        const double m[2] = {
            0.5 * (mesh.xy[2 * std::size_t{a}] + mesh.xy[2 * std::size_t{b}]),
            0.5 * (mesh.xy[2 * std::size_t{a} + 1] + mesh.xy[2 * std::size_t{b} + 1])};
        double d2 = 0;
        grid->nearest(
            m,
            [&](std::uint32_t f) {
              return mesh2d::segment_distance2(m, domain.vertex(f), domain.vertex(domain.next(f)));
            },
            &e, &d2);
      }
      mesh.boundary_edges.push_back(a);
      mesh.boundary_edges.push_back(b);
      mesh.boundary_tags.push_back(e == kNone ? 0 : domain.edge_tag(e));
      if (e != kNone) edge_triangle.emplace_back(t, e);
    }
  }
  // Regions: parts of the mesh connected across edges.
  std::vector<std::uint32_t> part(nt, kNone);
  std::uint32_t nb_parts = 0;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = 0; seed < nt; ++seed) {
    if (part[seed] != kNone) continue;
    part[seed] = nb_parts;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::uint32_t t = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const auto it = directed.find(std::uint64_t{tri(t, (k + 1) % 3)} << 32 | tri(t, k));
        if (it == directed.end()) continue;
        const std::uint32_t u = it->second / 3;
        if (part[u] == kNone) {
          part[u] = nb_parts;
          stack.push_back(u);
        }
      }
    }
    ++nb_parts;
  }
  // A part's region: 1, or with several polygons given (JSON), its polygon's number from 1
  // (the polygon of a domain edge under one of its boundary edges: the polygons are
  // disjoint, so a part lies in one), then the regional attributes.
  std::vector<std::int32_t> region(nb_parts, 1);
  for (const auto& [t, e] : edge_triangle) {
    const std::int32_t polygon = domain.ring_polygon(domain.ring_of(e));
    if (polygon >= 0) region[part[t]] = polygon + 1;
  }
  const std::vector<double>& points = domain.region_points();
  for (std::size_t r = 0; r < domain.region_attributes().size(); ++r) {
    const double value = domain.region_attributes()[r];
    if (!(value == std::floor(value) && std::fabs(value) < 2147483647.0)) {
      throw Error(domain.source() + ": " + domain.region_name(r) + " (" + std::to_string(value) +
                  ") is not an integer; mesh tags are integers");
    }
    const double* p = &points[2 * r];
    std::uint32_t found = kNone;
    for (std::uint32_t t = 0; t < nt && found == kNone; ++t) {
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) {
        inside = orient2d(&mesh.xy[2 * std::size_t{tri(t, k)}],
                          &mesh.xy[2 * std::size_t{tri(t, (k + 1) % 3)}], p) != Sign::negative;
      }
      if (inside) found = t;
    }
    if (found == kNone) {
      throw Error(domain.source() + ": " + domain.region_name(r) + ": its point (" +
                  std::to_string(p[0]) + ", " + std::to_string(p[1]) +
                  ") lies in no triangle of the mesh (outside the domain?)");
    }
    region[part[found]] = static_cast<std::int32_t>(value);
  }
  mesh.triangle_regions.resize(nt);
  for (std::uint32_t t = 0; t < nt; ++t) mesh.triangle_regions[t] = region[part[t]];
}

}  // namespace voroclip
