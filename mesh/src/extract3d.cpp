// Extraction of the tet mesh from the Delaunay triangulation of the final sites (Yan et
// al. 2011, sec. 5.2, "Final mesh extraction"): the tets whose circumcenter lies in the
// domain, decided exactly, then a local repair of a non-manifold boundary (mesh.h).
//
// Location. A uniform grid over the domain's bounding box lists, per cell, the domain tets
// whose bounding box meets the cell (cells of about eight tets of the box's volume); the
// tets are copied in Morton order of their centroid's cell. The cell of a coordinate is
// clamp(floor((x - lo) * inv_h)), a monotone function of x, so a tet whose box meets a
// query box is listed in a cell of the query's cell range: the grid only filters. The
// query box is the proven enclosure of the circumcenter (circumcenter3d_enclosure).
//   1. Walk: from the previous answer (the Delaunay tets are visited in Morton order of
//      their centroid's cell, so it is near) or a tet of the centre's cell, step across
//      the facets that orient3d_fast puts the floating-point centre beyond; the tet
//      reached is tested exactly (orient3d_circumcenter against its four facets,
//      Domain3::kTetFacetVertex listing them so that the tet's inside is negative). A
//      strict inclusion, or an exact zero on a boundary facet, decides.
//   2. Otherwise (the walk left the domain or looped, the centre is on an interior facet,
//      edge or vertex, or there is no error box): every tet listed in the query's cells
//      whose box meets the query box is tested exactly, each once (in the first cell of
//      the query where it is listed: per axis, the larger of the two ranges' starts).
// The walk in floating point only chooses which tet the exact test sees first.
//
// Repair. Boundary facets are the facets of kept tets whose neighbour is not kept (or
// infinite). An edge of the boundary is non-manifold when the tets around it (a cycle,
// closed through infinite tets on the hull) hold two or more runs of kept tets; a vertex is
// non-manifold when its star (the tets around it, connected through their facets that
// contain it) holds two or more components of kept tets, or two or more of non-kept ones
// (the boundary triangles around it then form several fans: on the sphere of its link,
// the number of boundary cycles is the number of kept components plus non-kept components
// minus one). The rule of mesh.h makes it a single run / a disk. Edges are handled before
// vertices, each in increasing order of its vertices: the result is deterministic.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "voroclip/mesh.h"

namespace voroclip {

namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

double tet_volume(const double* a, const double* b, const double* c, const double* d) {
  double u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = b[k] - a[k];
    v[k] = c[k] - a[k];
    w[k] = d[k] - a[k];
  }
  return std::fabs(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                   u[2] * (v[0] * w[1] - v[1] * w[0])) /
         6;
}

}  // namespace

// The domain's tets are copied in Morton order of their centroid's grid cell (`order`
// maps back), so that walks and cell scans touch nearby memory.
struct TetExtractor3::Grid {
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  double inv_h = 1;
  std::uint32_t n[3] = {1, 1, 1};
  std::vector<std::uint32_t> begin;  // per cell + 1
  std::vector<std::uint32_t> tets;   // per cell entry: a tet (in this order)
  std::vector<std::uint32_t> order;  // tet in this order -> Domain3 tet
  std::vector<std::uint32_t> adj;    // per tet, 4: the tet across facet f, or kNone
  std::vector<double> box;           // per tet: lo xyz, hi xyz
  std::vector<double> coords;        // per tet: its 4 vertices, x y z each

  std::uint32_t cell(int axis, double x) const {
    const double f = std::floor((x - lo[axis]) * inv_h);
    if (!(f > 0)) return 0;  // NaN too
    const double top = static_cast<double>(n[axis] - 1);
    return f >= top ? n[axis] - 1 : static_cast<std::uint32_t>(f);
  }
  std::size_t index(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
    return (std::size_t{k} * n[1] + j) * n[0] + i;
  }
};

namespace {

// Interleaves the low 10 bits of x, y, z.
std::uint32_t morton3(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  std::uint32_t key = 0;
  for (int b = 0; b < 10; ++b) {
    key |= ((x >> b & 1u) << (3 * b)) | ((y >> b & 1u) << (3 * b + 1)) |
           ((z >> b & 1u) << (3 * b + 2));
  }
  return key;
}

}  // namespace

TetExtractor3::TetExtractor3(const Domain3& domain) : domain_(&domain), grid_(new Grid) {
  Grid& g = *grid_;
  const std::uint32_t nt = domain.nb_tets();
  for (int c = 0; c < 3; ++c) {
    g.lo[c] = domain.bbox_lo()[c];
    g.hi[c] = domain.bbox_hi()[c];
  }
  const double ext[3] = {g.hi[0] - g.lo[0], g.hi[1] - g.lo[1], g.hi[2] - g.lo[2]};
  // About eight tets per cell of the bounding box (cubes): a tet's box spans a few cells.
  const double vol = std::max(ext[0], 1e-300) * std::max(ext[1], 1e-300) * std::max(ext[2], 1e-300);
  double h = std::cbrt(vol / std::max(1.0, nt / 8.0));
  if (!(h > 0) || !std::isfinite(h)) h = 1;
  for (int c = 0; c < 3; ++c) {
    const double cells = std::min(std::ceil(ext[c] / h), 1024.0);
    g.n[c] = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(cells));
  }
  g.inv_h = 1 / h;
  std::vector<std::uint64_t> keyed(nt);
  for (std::uint32_t t = 0; t < nt; ++t) {
    double centroid[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      for (int c = 0; c < 3; ++c) centroid[c] += 0.25 * domain.vertex(domain.tet_vertex(t, k))[c];
    }
    const std::uint64_t key =
        morton3(g.cell(0, centroid[0]), g.cell(1, centroid[1]), g.cell(2, centroid[2]));
    keyed[t] = key << 32 | t;
  }
  std::sort(keyed.begin(), keyed.end());
  g.order.resize(nt);
  std::vector<std::uint32_t> rank(nt);
  for (std::uint32_t r = 0; r < nt; ++r) {
    g.order[r] = static_cast<std::uint32_t>(keyed[r] & 0xffffffffu);
    rank[g.order[r]] = r;
  }
  g.adj.resize(4 * std::size_t{nt});
  g.box.resize(6 * std::size_t{nt});
  g.coords.resize(12 * std::size_t{nt});
  for (std::uint32_t r = 0; r < nt; ++r) {
    const std::uint32_t t = g.order[r];
    double* b = &g.box[6 * std::size_t{r}];
    for (int c = 0; c < 3; ++c) {
      b[c] = std::numeric_limits<double>::infinity();
      b[3 + c] = -b[c];
    }
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t n = domain.tet_adjacent(t, k);
      g.adj[4 * std::size_t{r} + static_cast<std::size_t>(k)] = n == Domain3::kNone ? n : rank[n];
      const double* p = domain.vertex(domain.tet_vertex(t, k));
      std::copy_n(p, 3, &g.coords[12 * std::size_t{r} + 3 * static_cast<std::size_t>(k)]);
      for (int c = 0; c < 3; ++c) {
        b[c] = std::min(b[c], p[c]);
        b[3 + c] = std::max(b[3 + c], p[c]);
      }
    }
  }
  const std::size_t nc = std::size_t{g.n[0]} * g.n[1] * g.n[2];
  g.begin.assign(nc + 1, 0);
  const auto for_cells = [&](std::uint32_t r, auto visit) {
    const double* b = &g.box[6 * std::size_t{r}];
    for (std::uint32_t k = g.cell(2, b[2]); k <= g.cell(2, b[5]); ++k)
      for (std::uint32_t j = g.cell(1, b[1]); j <= g.cell(1, b[4]); ++j)
        for (std::uint32_t i = g.cell(0, b[0]); i <= g.cell(0, b[3]); ++i) visit(g.index(i, j, k));
  };
  for (std::uint32_t r = 0; r < nt; ++r) for_cells(r, [&](std::size_t c) { ++g.begin[c + 1]; });
  for (std::size_t c = 0; c < nc; ++c) g.begin[c + 1] += g.begin[c];
  g.tets.resize(g.begin[nc]);
  std::vector<std::uint32_t> fill(g.begin.begin(), g.begin.end() - 1);
  for (std::uint32_t r = 0; r < nt; ++r)
    for_cells(r, [&](std::size_t c) { g.tets[fill[c]++] = r; });
}

TetExtractor3::~TetExtractor3() = default;
TetExtractor3::TetExtractor3(TetExtractor3&&) noexcept = default;

Sign TetExtractor3::circumcenter_side(const double* p0, const double* p1, const double* p2,
                                      const double* p3) const {
  bool unbounded = false;
  std::uint32_t hint = Domain3::kNone;
  return locate(p0, p1, p2, p3, unbounded, hint);
}

Sign TetExtractor3::locate(const double* p0, const double* p1, const double* p2, const double* p3,
                           bool& unbounded, std::uint32_t& hint) const {
  const Grid& g = *grid_;
  double centre[3], hw[3], qlo[3], qhi[3];
  if (circumcenter3d_enclosure(p0, p1, p2, p3, centre, hw)) {
    for (int c = 0; c < 3; ++c) {
      qlo[c] = centre[c] - hw[c];
      qhi[c] = centre[c] + hw[c];
      if (qhi[c] < g.lo[c] || qlo[c] > g.hi[c]) return Sign::negative;
    }
  } else {
    // No error box (the tet is too close to flat; the predicate throws for coplanar sites).
    // Such a circumcenter is usually far: first its exact side of the six planes of the
    // domain's bounding box (six exact tests instead of four per domain tet), then every
    // domain tet is a candidate.
    for (int c = 0; c < 3; ++c) {
      for (int upper = 0; upper < 2; ++upper) {
        const double x = upper != 0 ? g.hi[c] : g.lo[c];
        double a[3] = {0, 0, 0}, b[3], d[3], away[3];
        a[c] = x;
        std::copy_n(a, 3, b);
        std::copy_n(a, 3, d);
        std::copy_n(a, 3, away);
        b[(c + 1) % 3] = 1;
        d[(c + 2) % 3] = 1;
        away[c] = upper != 0 ? x + std::fabs(x) + 1 : x - std::fabs(x) - 1;  // strictly outside
        if (orient3d_circumcenter(a, b, d, p0, p1, p2, p3) == orient3d(a, b, d, away)) {
          return Sign::negative;
        }
      }
    }
    unbounded = true;
    for (int c = 0; c < 3; ++c) {
      qlo[c] = g.lo[c];
      qhi[c] = g.hi[c];
      centre[c] = 0.5 * (qlo[c] + qhi[c]);
    }
  }
  return locate_in(centre, qlo, qhi, unbounded, hint,
                   [&](const double* a, const double* b, const double* c) {
                     return orient3d_circumcenter(a, b, c, p0, p1, p2, p3);
                   });
}

Sign TetExtractor3::point_side(const double* p) const {
  const Grid& g = *grid_;
  for (int c = 0; c < 3; ++c) {
    if (!(p[c] >= g.lo[c] && p[c] <= g.hi[c])) {
      if (!std::isfinite(p[c])) throw Error("point_side: a coordinate is not finite");
      return Sign::negative;
    }
  }
  std::uint32_t hint = Domain3::kNone;
  return locate_in(p, p, p, false, hint, [&](const double* a, const double* b, const double* c) {
    return orient3d(a, b, c, p);
  });
}

template <class SideOf>
Sign TetExtractor3::locate_in(const double* centre, const double* qlo, const double* qhi,
                              bool unbounded, std::uint32_t& hint, const SideOf& side) const {
  const Grid& g = *grid_;
  // Exact: is the point in closed tet t? 0 no; 1 strictly inside; 2 on its boundary but
  // not on the domain's boundary; 3 on the domain's boundary.
  const auto test = [&](std::uint32_t t) {
    const double* x = &g.coords[12 * std::size_t{t}];
    int zero_facets = 0;  // bit f: the point is on the plane of facet f
    for (int f = 0; f < 4; ++f) {
      const int* fv = Domain3::kTetFacetVertex[f];
      const Sign s = side(x + 3 * fv[0], x + 3 * fv[1], x + 3 * fv[2]);
      if (s == Sign::positive) return 0;
      if (s == Sign::zero) zero_facets |= 1 << f;
    }
    if (zero_facets == 0) return 1;
    for (int f = 0; f < 4; ++f) {
      if ((zero_facets >> f & 1) != 0 &&
          g.adj[4 * std::size_t{t} + static_cast<std::size_t>(f)] == Domain3::kNone)
        return 3;
    }
    return 2;
  };
  const auto overlaps = [&](std::uint32_t t) {
    const double* b = &g.box[6 * std::size_t{t}];
    return !(b[0] > qhi[0] || b[3] < qlo[0] || b[1] > qhi[1] || b[4] < qlo[1] || b[2] > qhi[2] ||
             b[5] < qlo[2]);
  };
  const std::uint32_t c0[3] = {g.cell(0, qlo[0]), g.cell(1, qlo[1]), g.cell(2, qlo[2])};
  const std::uint32_t c1[3] = {g.cell(0, qhi[0]), g.cell(1, qhi[1]), g.cell(2, qhi[2])};
  const bool single = c0[0] == c1[0] && c0[1] == c1[1] && c0[2] == c1[2];
  if (!unbounded) {
    // The common case: walk in floating point from the hint (or from a tet listed in the
    // centre's cell) towards the floating-point centre, then test the tet reached exactly.
    // The walk only chooses which tet the exact test sees; when it leaves the domain, loops
    // or lands on a tet that does not hold the circumcenter strictly, the exact search
    // below decides.
    // Start: the hint when its box holds the centre, else the first tet of the centre's
    // cell whose box does, else the cell's first tet.
    std::uint32_t t = Domain3::kNone;
    const auto holds = [&](std::uint32_t r) {
      const double* b = &g.box[6 * std::size_t{r}];
      return b[0] <= centre[0] && centre[0] <= b[3] && b[1] <= centre[1] && centre[1] <= b[4] &&
             b[2] <= centre[2] && centre[2] <= b[5];
    };
    if (hint != Domain3::kNone && holds(hint)) {
      t = hint;
    } else {
      const std::size_t cell =
          g.index(g.cell(0, centre[0]), g.cell(1, centre[1]), g.cell(2, centre[2]));
      for (std::uint32_t e = g.begin[cell]; e < g.begin[cell + 1] && t == Domain3::kNone; ++e) {
        if (holds(g.tets[e])) t = g.tets[e];
      }
      if (t == Domain3::kNone && g.begin[cell] < g.begin[cell + 1]) t = g.tets[g.begin[cell]];
    }
    std::uint32_t previous = Domain3::kNone;
    for (int step = 0; step < 256 && t != Domain3::kNone; ++step) {
      const double* x = &g.coords[12 * std::size_t{t}];
      std::uint32_t next = Domain3::kNone;
      bool outside = false;
      for (int f = 0; f < 4; ++f) {
        const int* fv = Domain3::kTetFacetVertex[f];
        if (orient3d_fast(x + 3 * fv[0], x + 3 * fv[1], x + 3 * fv[2], centre) != Sign::positive) {
          continue;
        }
        const std::uint32_t n = g.adj[4 * std::size_t{t} + static_cast<std::size_t>(f)];
        if (n == previous) continue;  // do not step straight back
        outside = n == Domain3::kNone;
        next = n;
        break;
      }
      if (next == Domain3::kNone) {
        if (!outside) {
          hint = t;
          const int r = test(t);
          if (r == 1) return Sign::positive;
          if (r == 3) return Sign::zero;
        }
        break;
      }
      previous = t;
      t = next;
    }
  }
  bool in_closed = false;
  for (std::uint32_t k = c0[2]; k <= c1[2]; ++k) {
    for (std::uint32_t j = c0[1]; j <= c1[1]; ++j) {
      for (std::uint32_t i = c0[0]; i <= c1[0]; ++i) {
        const std::size_t cell = g.index(i, j, k);
        for (std::uint32_t e = g.begin[cell]; e < g.begin[cell + 1]; ++e) {
          const std::uint32_t t = g.tets[e];
          if (!overlaps(t)) continue;
          // Test t in the first cell of the query where it is listed.
          if (!single) {
            const double* b = &g.box[6 * std::size_t{t}];
            if (i != std::max(c0[0], g.cell(0, b[0])) || j != std::max(c0[1], g.cell(1, b[1])) ||
                k != std::max(c0[2], g.cell(2, b[2]))) {
              continue;
            }
          }
          const int r = test(t);
          if (r == 1) return Sign::positive;
          if (r == 3) return Sign::zero;
          in_closed = in_closed || r == 2;
        }
      }
    }
  }
  return in_closed ? Sign::positive : Sign::negative;
}

namespace {

// The local repair of extract3d.cpp's header, on kept flags per tet slot of dt.
class ManifoldRepair {
 public:
  ManifoldRepair(const Delaunay3& dt, std::vector<std::uint8_t>& kept, Extract3Stats& stats)
      : dt_(dt), kept_(kept), stats_(stats), frozen_(kept.size(), 0) {}

  void run(std::uint32_t max_passes) {
    // Phase 1: the rule of mesh.h (least volume changed, a tet changed at most once),
    // until a pass finds nothing. Phase 2, for what phase 1 left: removals only (every
    // kept component but the largest; at a vertex whose kept tets form one component
    // around holes, all of them). Every defect found in phase 2 removes tets, so phase 2
    // ends, with a pass that finds no defect: a manifold boundary.
    for (int phase = 0; phase < 2; ++phase) {
      const bool removal_only = phase == 1;
      for (std::uint32_t pass = 0; removal_only || pass < max_passes; ++pass) {
        ++stats_.nb_repair_passes;
        const std::uint32_t before = stats_.nb_nonmanifold_edges + stats_.nb_nonmanifold_vertices;
        collect_boundary();
        for (const auto& e : edges_) repair_edge(e, removal_only);
        collect_boundary();
        for (const std::uint32_t v : vertices_) repair_vertex(v, removal_only);
        if (stats_.nb_nonmanifold_edges + stats_.nb_nonmanifold_vertices == before) return;
      }
    }
  }

 private:
  struct Edge {
    std::uint32_t a, b, tet;
    bool operator<(const Edge& o) const { return a != o.a ? a < o.a : b < o.b; }
    bool operator==(const Edge& o) const { return a == o.a && b == o.b; }
  };

  bool is_kept(std::uint32_t t) const { return kept_[t] != 0; }

  // Edges and vertices of the boundary triangles, sorted, each edge with a tet holding it.
  void collect_boundary() {
    edges_.clear();
    vertices_.clear();
    for (std::uint32_t t = 0; t < dt_.nb_tet_slots(); ++t) {
      if (!is_kept(t)) continue;
      for (int f = 0; f < 4; ++f) {
        if (is_kept(dt_.tet_adjacent(t, f))) continue;
        const int* fv = Delaunay3::kFacetVertex[f];
        for (int e = 0; e < 3; ++e) {
          std::uint32_t a = dt_.tet_vertex(t, fv[e]), b = dt_.tet_vertex(t, fv[(e + 1) % 3]);
          vertices_.push_back(a);
          if (a > b) std::swap(a, b);
          edges_.push_back({a, b, t});
        }
      }
    }
    std::sort(edges_.begin(), edges_.end());
    edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
    std::sort(vertices_.begin(), vertices_.end());
    vertices_.erase(std::unique(vertices_.begin(), vertices_.end()), vertices_.end());
  }

  int local(std::uint32_t t, std::uint32_t v) const {
    for (int k = 0; k < 4; ++k) {
      if (dt_.tet_vertex(t, k) == v) return k;
    }
    return -1;
  }

  // star_: the tets around edge e in cyclic order.
  void edge_star(const Edge& e) {
    star_.clear();
    std::uint32_t t = e.tet;
    // c, d: the two other vertices of t; turn across the facet opposite c.
    std::uint32_t c = kNone, d = kNone;
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t w = dt_.tet_vertex(t, k);
      if (w == e.a || w == e.b) continue;
      (c == kNone ? c : d) = w;
    }
    do {
      star_.push_back(t);
      const std::uint32_t next = dt_.tet_adjacent(t, local(t, c));
      std::uint32_t other = kNone;
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t w = dt_.tet_vertex(next, k);
        if (w != e.a && w != e.b && w != d) other = w;
      }
      c = d;
      d = other;
      t = next;
    } while (t != e.tet);
  }

  std::uint32_t count_runs() const {
    std::uint32_t runs = 0;
    const std::size_t n = star_.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (is_kept(star_[i]) && !is_kept(star_[(i + n - 1) % n])) ++runs;
    }
    return runs;
  }

  // star_: the tets around v (finite and infinite), breadth-first.
  void vertex_star(std::uint32_t v) {
    star_.clear();
    const std::uint32_t start = dt_.vertex_tet(v);
    if (start == Delaunay3::kNoTet) return;
    star_.push_back(start);
    for (std::size_t i = 0; i < star_.size(); ++i) {
      const std::uint32_t t = star_[i];
      for (int f = 0; f < 4; ++f) {
        if (dt_.tet_vertex(t, f) == v) continue;
        const std::uint32_t n = dt_.tet_adjacent(t, f);
        if (std::find(star_.begin(), star_.end(), n) == star_.end()) star_.push_back(n);
      }
    }
    vertex_ = v;
  }

  // Components of kept and of non-kept tets of the star (vertex_star or edge_star):
  // comp_[i] per star tet; counts nk, ng.
  void components(std::uint32_t& nk, std::uint32_t& ng) {
    const std::size_t n = star_.size();
    comp_.assign(n, kNone);
    nk = ng = 0;
    std::uint32_t next_id = 0;
    for (std::size_t s = 0; s < n; ++s) {
      if (comp_[s] != kNone) continue;
      const bool k = is_kept(star_[s]);
      (k ? nk : ng) += 1;
      comp_[s] = next_id;
      queue_.assign(1, static_cast<std::uint32_t>(s));
      for (std::size_t q = 0; q < queue_.size(); ++q) {
        const std::uint32_t t = star_[queue_[q]];
        for (int f = 0; f < 4; ++f) {
          if (dt_.tet_vertex(t, f) == vertex_) continue;
          const std::uint32_t nb = dt_.tet_adjacent(t, f);
          if (is_kept(nb) != k) continue;
          const auto it = std::find(star_.begin(), star_.end(), nb);
          const auto idx = static_cast<std::size_t>(it - star_.begin());
          if (it == star_.end() || comp_[idx] != kNone) continue;
          comp_[idx] = next_id;
          queue_.push_back(static_cast<std::uint32_t>(idx));
        }
      }
      ++next_id;
    }
  }

  double volume(std::uint32_t t) const {
    if (dt_.is_infinite(t)) return std::numeric_limits<double>::infinity();
    return tet_volume(dt_.point(dt_.tet_vertex(t, 0)), dt_.point(dt_.tet_vertex(t, 1)),
                      dt_.point(dt_.tet_vertex(t, 2)), dt_.point(dt_.tet_vertex(t, 3)));
  }

  // The rule of mesh.h on the components comp_ of star_ (ids [0, nb)). Returns whether
  // anything changed.
  bool apply_rule(std::uint32_t nb, bool removal_only) {
    std::vector<double>& vol = vol_;
    std::vector<std::uint8_t>& kept_comp = kept_comp_;
    std::vector<std::uint8_t>& locked = locked_;
    vol.assign(nb, 0);
    kept_comp.assign(nb, 0);
    locked.assign(nb, 0);
    for (std::size_t s = 0; s < star_.size(); ++s) {
      const std::uint32_t t = star_[s], c = comp_[s];
      vol[c] += volume(t);
      kept_comp[c] = is_kept(t) ? 1 : 0;
      if (frozen_[t] != 0 || dt_.is_infinite(t)) locked[c] = 1;
    }
    // Option A: keep the largest kept component, remove the others. Option B: keep the
    // largest non-kept component, add the others.
    double cost[2] = {0, 0};
    bool valid[2] = {true, true};
    chosen_[0] = chosen_[1] = kNone;
    for (int option = 0; option < 2; ++option) {
      const std::uint8_t side = option == 0 ? 1 : 0;
      std::uint32_t largest = kNone, count = 0;
      for (std::uint32_t c = 0; c < nb; ++c) {
        if (kept_comp[c] != side) continue;
        ++count;
        if (largest == kNone || vol[c] > vol[largest]) largest = c;
      }
      if (count < 2) {
        valid[option] = false;
        continue;
      }
      for (std::uint32_t c = 0; c < nb; ++c) {
        if (kept_comp[c] != side || c == largest) continue;
        if (locked[c] != 0) valid[option] = false;
        cost[option] += vol[c];
      }
      chosen_[option] = largest;
    }
    if (removal_only) {
      // Phase 2: frozen tets may change again, but only towards removal.
      valid[1] = false;
      if (chosen_[0] == kNone || count_kept_components(nb) < 2) {
        // One kept component (around holes of the star): all of it goes.
        bool any = false;
        for (std::size_t s = 0; s < star_.size(); ++s) {
          if (!is_kept(star_[s])) continue;
          kept_[star_[s]] = 0;
          ++stats_.nb_removed;
          any = true;
        }
        return any;
      }
      valid[0] = true;
    }
    int option = -1;
    if (valid[0] && (!valid[1] || cost[0] <= cost[1])) {
      option = 0;
    } else if (valid[1]) {
      option = 1;
    }
    if (option < 0) return false;
    const std::uint8_t side = option == 0 ? 1 : 0;
    for (std::size_t s = 0; s < star_.size(); ++s) {
      const std::uint32_t t = star_[s], c = comp_[s];
      if (kept_comp[c] != side || c == chosen_[option]) continue;
      kept_[t] = side == 1 ? 0 : 1;
      frozen_[t] = 1;
      (side == 1 ? stats_.nb_removed : stats_.nb_added) += 1;
    }
    return true;
  }

  std::uint32_t count_kept_components(std::uint32_t nb) const {
    std::uint32_t n = 0;
    for (std::uint32_t c = 0; c < nb; ++c) n += kept_comp_[c];
    return n;
  }

  bool repair_edge(const Edge& e, bool removal_only) {
    edge_star(e);
    if (count_runs() < 2) return false;
    ++stats_.nb_nonmanifold_edges;
    // Components of a cycle: its runs.
    const std::size_t n = star_.size();
    comp_.assign(n, kNone);
    std::size_t first = 0;
    while (first < n && is_kept(star_[first]) == is_kept(star_[(first + n - 1) % n])) ++first;
    std::uint32_t id = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t s = (first + i) % n;
      if (i > 0 && is_kept(star_[s]) != is_kept(star_[(s + n - 1) % n])) ++id;
      comp_[s] = id;
    }
    return apply_rule(id + 1, removal_only);
  }

  bool repair_vertex(std::uint32_t v, bool removal_only) {
    vertex_star(v);
    std::uint32_t nk = 0, ng = 0;
    components(nk, ng);
    if (nk < 2 && ng < 2) return false;
    ++stats_.nb_nonmanifold_vertices;
    return apply_rule(nk + ng, removal_only);
  }

  const Delaunay3& dt_;
  std::vector<std::uint8_t>& kept_;
  Extract3Stats& stats_;
  std::vector<std::uint8_t> frozen_;
  std::vector<Edge> edges_;
  std::vector<std::uint32_t> vertices_;
  std::vector<std::uint32_t> star_, comp_, queue_;
  std::vector<double> vol_;
  std::vector<std::uint8_t> kept_comp_, locked_;
  std::uint32_t chosen_[2] = {kNone, kNone};
  std::uint32_t vertex_ = kNone;
};

// Boundary filling (mesh.h, SurfacePatches). A boundary facet of the kept tets is a dent
// when a vertex is on no patch, and crosses a crease when its vertices share no patch. The
// finite tet across a dent is added. At a crease, the tet across is added when its
// centroid (rounded) is strictly inside the domain (it fills the chamfer of a convex
// edge), and the kept tet itself is removed when its centroid is strictly outside (it
// bridges a concave edge); exact point location. A tet changes at most once. Passes over
// the slots in order, each seeing the changes of the previous ones.
void fill_boundary(const TetExtractor3& domain, const Delaunay3& dt, const SurfacePatches& sp,
                   std::uint32_t max_passes, std::vector<std::uint8_t>& kept, Extract3Stats& st) {
  if (sp.begin.size() < std::size_t{dt.nb_points()} + 1 || sp.begin.back() > sp.patches.size()) {
    throw Error("extract: surface patches for " +
                std::to_string(sp.begin.size() - (sp.begin.empty() ? 0 : 1)) +
                " points; the triangulation has " + std::to_string(dt.nb_points()));
  }
  const auto shared = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    for (std::uint32_t i = sp.begin[a]; i < sp.begin[a + 1]; ++i) {
      const std::uint32_t patch = sp.patches[i];
      const auto has = [&](std::uint32_t v) {
        for (std::uint32_t j = sp.begin[v]; j < sp.begin[v + 1]; ++j) {
          if (sp.patches[j] == patch) return true;
        }
        return false;
      };
      if (has(b) && has(c)) return true;
    }
    return false;
  };
  const auto centroid_side = [&](std::uint32_t t) {
    double c[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      for (int a = 0; a < 3; ++a) c[a] += 0.25 * dt.point(dt.tet_vertex(t, k))[a];
    }
    return domain.point_side(c);
  };
  std::vector<std::uint8_t> changed(kept.size(), 0);
  std::vector<std::uint32_t> todo;  // 4 * tet + action: 0 add (dent), 1 add (crease), 2 remove
  for (std::uint32_t pass = 0; pass < max_passes; ++pass) {
    todo.clear();
    for (std::uint32_t t = 0; t < dt.nb_tet_slots(); ++t) {
      if (kept[t] == 0) continue;
      for (int f = 0; f < 4; ++f) {
        const std::uint32_t n = dt.tet_adjacent(t, f);
        if (kept[n] != 0) continue;
        const int* fv = Delaunay3::kFacetVertex[f];
        const std::uint32_t v[3] = {dt.tet_vertex(t, fv[0]), dt.tet_vertex(t, fv[1]),
                                    dt.tet_vertex(t, fv[2])};
        bool dent = false;
        for (const std::uint32_t w : v) dent = dent || sp.begin[w] == sp.begin[w + 1];
        const bool finite = !dt.is_infinite(n) && changed[n] == 0;
        if (dent) {
          if (finite) todo.push_back(4 * n);
        } else if (!shared(v[0], v[1], v[2])) {
          if (finite && centroid_side(n) == Sign::positive) {
            todo.push_back(4 * n + 1);
          } else if (changed[t] == 0 && centroid_side(t) == Sign::negative) {
            todo.push_back(4 * t + 2);
          }
        }
      }
    }
    if (todo.empty()) break;
    // Each tet once, by its first action (dent before crease before removal).
    std::sort(todo.begin(), todo.end());
    for (std::size_t i = 0; i < todo.size(); ++i) {
      const std::uint32_t t = todo[i] / 4, action = todo[i] % 4;
      if (i > 0 && todo[i - 1] / 4 == t) continue;
      changed[t] = 1;
      kept[t] = action == 2 ? 0 : 1;
      ++(action == 0 ? st.nb_filled : action == 1 ? st.nb_creases : st.nb_carved);
    }
  }
}

}  // namespace

std::vector<std::uint32_t> TetExtractor3::extract(const Delaunay3& dt,
                                                  const Extract3Options& options,
                                                  Extract3Stats* stats) const {
  const auto t0 = std::chrono::steady_clock::now();
  Extract3Stats st;
  const std::uint32_t ns = dt.nb_tet_slots();
  // Per slot: bit 0 kept, bit 1 on the boundary, bit 2 searched without an error box.
  std::vector<std::uint8_t> flags(ns, 0);
  // The finite tets in Morton order of their centroid's cell: consecutive queries are
  // near each other, so the previous answer is a good start for the next walk.
  const Grid& g = *grid_;
  std::vector<std::uint64_t> order(ns);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, ns, 4096), [&](const auto& range) {
    for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
      std::uint64_t key = 0xffffffffu;  // free and infinite slots last
      if (!dt.is_free(t) && !dt.is_infinite(t)) {
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 4; ++k) {
          for (int a = 0; a < 3; ++a) c[a] += 0.25 * dt.point(dt.tet_vertex(t, k))[a];
        }
        key = morton3(g.cell(0, c[0]), g.cell(1, c[1]), g.cell(2, c[2]));
      }
      order[t] = key << 32 | t;
    }
  });
  std::sort(order.begin(), order.end());
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, ns, 1024), [&](const auto& range) {
    std::uint32_t hint = Domain3::kNone;  // the previous tet's answer: nearby, usually
    for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
      const auto t = static_cast<std::uint32_t>(order[i] & 0xffffffffu);
      if (dt.is_free(t) || dt.is_infinite(t)) continue;
      const double* p[4];
      for (int k = 0; k < 4; ++k) p[k] = dt.point(dt.tet_vertex(t, k));
      bool unbounded = false;
      const Sign s = locate(p[0], p[1], p[2], p[3], unbounded, hint);
      std::uint8_t f = unbounded ? 4 : 0;
      if (s != Sign::negative) f |= 1;
      if (s == Sign::zero) f |= 2;
      flags[t] = f;
    }
  });
  std::vector<std::uint8_t> kept(ns, 0);
  for (std::uint32_t t = 0; t < ns; ++t) {
    if (dt.is_free(t) || dt.is_infinite(t)) continue;
    ++st.nb_delaunay_tets;
    kept[t] = flags[t] & 1;
    st.nb_inside += flags[t] & 1;
    st.nb_on_boundary += (flags[t] >> 1) & 1;
    st.nb_unbounded += (flags[t] >> 2) & 1;
  }
  if (options.surface)
    fill_boundary(*this, dt, *options.surface, options.max_fill_passes, kept, st);
  if (options.repair_manifold) ManifoldRepair(dt, kept, st).run(options.max_repair_passes);
  std::vector<std::uint32_t> tets;
  for (std::uint32_t t = 0; t < ns; ++t) {
    if (kept[t] == 0) continue;
    // Delaunay3's tets have orient3d > 0; swapping the last two gives the right-handed order.
    tets.insert(tets.end(), {dt.tet_vertex(t, 0), dt.tet_vertex(t, 1), dt.tet_vertex(t, 3),
                             dt.tet_vertex(t, 2)});
  }
  st.nb_kept = static_cast<std::uint32_t>(tets.size() / 4);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats) *stats = st;
  return tets;
}

}  // namespace voroclip
