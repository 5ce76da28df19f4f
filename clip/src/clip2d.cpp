// The 2D clipped Voronoi diagram: Yan, Wang, Lévy & Liu, "Efficient computation of
// clipped Voronoi diagram for mesh generation", CAD 2011, section 3.
//
// 1. Boundary cells (sec. 3.2). Each domain ring is walked edge by edge through the
//    Voronoi cells it crosses: starting in the cell of its first vertex (nearest site,
//    then a descent over Voronoi neighbours with the perturbed side test), the exit of an
//    edge from the current cell c is the first bisector(c, k) it crosses, among the
//    neighbours k whose side holds the edge's end. This is the paper's propagation of
//    cell–edge pairs, visiting each pair once, in ring order. It cuts the boundary into
//    chains: maximal pieces of the boundary inside one cell, each running from an entry
//    crossing to an exit crossing (edge ∩ bisector vertices), or a whole ring inside one
//    cell.
// 2. Boundary cells are assembled from their chains: going around the convex cell
//    counter-clockwise, each exit crossing is followed by the part of the cell's boundary
//    up to the next crossing (an entry), then by that entry's chain, until the ring
//    closes (the domain is on the left of its boundary and the cell on the left of its
//    own, so the clipped region is on the left of every ring). A cell without crossings
//    adds its whole boundary as a ring when that boundary lies inside the domain, decided
//    by the parity of the domain rings around the site that stay outside the cell. The
//    paper clips with Sutherland–Hodgman instead; this assembly gives every piece and
//    hole of a non-convex clipped cell, with the vertices kept symbolic.
// 3. Cells that no ring crosses lie wholly inside or wholly outside the domain. A
//    boundary cell tells each such neighbour which (its shared Voronoi edge is inside the
//    domain exactly when the assembly walked it); a flood fill over Voronoi neighbours
//    gives the rest. Inner cells are the Voronoi polygons of the triangulation, unclipped.
//
// Exactness. Every decision is one of the predicates of predicates.h on symbolic
// vertices (domain vertex, domain edge ∩ bisector, Voronoi vertex) with the symbolic
// perturbation of the triangulation, so it never meets a tie: sites on the boundary,
// bisectors through domain vertices and cocircular sites need no special case.
// Coordinates are computed only for integration and output, each symbolic vertex by one
// deterministic formula (edge ∩ bisector(b, c) with b < c), so neighbouring cells share
// bit-identical vertices.
//
// Threads: the ring walks run in sequence (they are cheap); the assembly of boundary
// cells and the integration of inner cells are TBB loops writing per-cell slots.
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "clip_poll.h"
#include "voroclip/clip.h"

namespace voroclip {

// Internals of this file (a named namespace: Clip2Impl, a friend of ClippedVoronoi2, uses
// them).
namespace clip2 {

constexpr std::uint32_t kNone = 0xffffffffu;
using Kind = ClipVertex2::Kind;

ClipVertex2 domain_vertex(std::uint32_t v) { return {Kind::kDomainVertex, v, 0, 0}; }
ClipVertex2 edge_bisector(std::uint32_t e, std::uint32_t i, std::uint32_t k) {
  return {Kind::kEdgeBisector, e, std::min(i, k), std::max(i, k)};
}
ClipVertex2 voronoi_vertex(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  std::array<std::uint32_t, 3> s{a, b, c};
  std::sort(s.begin(), s.end());
  return {Kind::kVoronoi, s[0], s[1], s[2]};
}

// A maximal piece of the domain boundary inside one cell. Its vertices are
// chain_vertices[begin, end). An open chain starts at the crossing of edge entry_edge with
// bisector(cell, entry_site) and ends at the crossing of edge exit_edge with
// bisector(cell, exit_site); a closed chain is a whole ring (entry_site == kNone).
struct Chain {
  std::uint32_t cell;
  std::uint32_t begin, end;
  std::uint32_t entry_edge, entry_site;
  std::uint32_t exit_edge, exit_site;
  std::uint32_t ring;  // the domain ring it belongs to
};

// Per boundary cell, what the assembly produces.
struct CellOut {
  std::vector<ClipVertex2> vertices;     // rings, concatenated
  std::vector<std::uint32_t> tris;       // per vertex: its triangle if a Voronoi vertex
  std::vector<std::uint32_t> ring_ends;  // end offset of each ring in `vertices`
  std::vector<std::uint32_t> walked;     // neighbours whose whole Voronoi edge was walked
};

// Integrals over a cell of rho, rho x, rho |x - s|^2, and the area, accumulated ring by
// ring over the fan of triangles (s, v_j, v_j+1) from the site s (signed areas: valid
// for any set of closed rings).
struct Moments {
  double area = 0, mass = 0, mx = 0, my = 0, energy = 0;  // mx, my relative to s
};

// A cell's moments relative to an origin o (its first ring vertex).
struct Acc {
  Moments m;
  double o[2];
};

// Dunavant's degree-4 rule (6 points) on a triangle, barycentric coordinates and weights
// summing to 1.
constexpr double kQa = 0.445948490915965, kQb = 0.091576213509771;
constexpr double kQwa = 0.223381589678011, kQwb = 0.109951743655322;
constexpr double kQuad[6][4] = {{kQa, kQa, 1 - 2 * kQa, kQwa}, {kQa, 1 - 2 * kQa, kQa, kQwa},
                                {1 - 2 * kQa, kQa, kQa, kQwa}, {kQb, kQb, 1 - 2 * kQb, kQwb},
                                {kQb, 1 - 2 * kQb, kQb, kQwb}, {1 - 2 * kQb, kQb, kQb, kQwb}};

// Radon's degree-5 rule (7 points, positive weights summing to 1) for a callback
// density, as the 3D cells' degree-5 rule: the energy (rho |x - x_i|^2) is exact for rho
// of degree <= 3. For a smooth rho its error, and so the mismatch between the gradient
// 2 m (x_i - c_i) and the derivative of the computed energy, is smaller than the degree-4
// rule's (test_density, 50 sites, rho = exp(x/2 - 3y/10) + 1/(1 + |x|^2): 1.2e-5 -> 3.7e-6
// of max |g|). Barycentric points (1/3, 1/3, 1/3) and (a, a, 1 - 2a) for
// a = (6 -+ sqrt 15) / 21, weights 9/40 and (155 -+ sqrt 15) / 1200, to 17 digits.
constexpr double kR1 = 0.10128650732345633, kR2 = 0.47014206410511505;
constexpr double kRw1 = 0.12593918054482717, kRw2 = 0.13239415278850616;
constexpr double kQuad7[7][4] = {
    {1.0 / 3, 1.0 / 3, 1.0 / 3, 9.0 / 40}, {kR1, kR1, 1 - 2 * kR1, kRw1},
    {kR1, 1 - 2 * kR1, kR1, kRw1},         {1 - 2 * kR1, kR1, kR1, kRw1},
    {kR2, kR2, 1 - 2 * kR2, kRw2},         {kR2, 1 - 2 * kR2, kR2, kRw2},
    {1 - 2 * kR2, kR2, kR2, kRw2}};

void add_triangle(const Density2& rho, const double* s, double ux, double uy, double wx, double wy,
                  Moments& m) {
  const double a = 0.5 * (ux * wy - uy * wx);
  m.area += a;
  switch (rho.kind) {
    case Density2::Kind::kConstant: {
      const double r = rho.value;
      m.mass += r * a;
      m.mx += r * a * (ux + wx) / 3;
      m.my += r * a * (uy + wy) / 3;
      m.energy += r * a * (ux * ux + uy * uy + wx * wx + wy * wy + ux * wx + uy * wy) / 6;
      return;
    }
    case Density2::Kind::kGrid: {
      // rho linear on the triangle, from its values at the three vertices: exact moments.
      const double r0 = rho(s[0], s[1]), r1 = rho(s[0] + ux, s[1] + uy);
      const double r2 = rho(s[0] + wx, s[1] + wy);
      m.mass += a * (r0 + r1 + r2) / 3;
      m.mx += a * ((r0 + 2 * r1 + r2) * ux + (r0 + r1 + 2 * r2) * wx) / 12;
      m.my += a * ((r0 + 2 * r1 + r2) * uy + (r0 + r1 + 2 * r2) * wy) / 12;
      double e = 0;  // degree 3: the degree-4 rule is exact
      for (const auto& q : kQuad) {
        const double x = q[1] * ux + q[2] * wx, y = q[1] * uy + q[2] * wy;
        e += q[3] * (q[0] * r0 + q[1] * r1 + q[2] * r2) * (x * x + y * y);
      }
      m.energy += a * e;
      return;
    }
    case Density2::Kind::kCallback: {
      double mass = 0, mx = 0, my = 0, e = 0;
      for (const auto& q : kQuad7) {
        const double x = q[1] * ux + q[2] * wx, y = q[1] * uy + q[2] * wy;
        const double r = q[3] * rho.callback(s[0] + x, s[1] + y);
        mass += r;
        mx += r * x;
        my += r * y;
        e += r * (x * x + y * y);
      }
      m.mass += a * mass;
      m.mx += a * mx;
      m.my += a * my;
      m.energy += a * e;
      return;
    }
  }
}

// The moments of the counter-clockwise triangle (o + a, o + b, o + c) relative to o, for
// the pieces of boundary cells below (add_triangle is this with a = 0 and signed areas,
// kept apart so that the fans of constant densities keep their arithmetic).
void add_triangle_at(const Density2& rho, const double* o, const double* a, const double* b,
                     const double* c, Moments& m) {
  const double ar = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
  // The pieces are counter-clockwise: a flat one (or one turned over by rounding) adds
  // nothing, and its quadrature points, on the cell's edge up to rounding, are not asked.
  if (!(ar > 0)) return;
  m.area += ar;
  double r[3] = {1, 1, 1};
  if (rho.kind == Density2::Kind::kConstant) {
    r[0] = r[1] = r[2] = rho.value;
  } else if (rho.kind == Density2::Kind::kGrid) {
    r[0] = rho(o[0] + a[0], o[1] + a[1]);
    r[1] = rho(o[0] + b[0], o[1] + b[1]);
    r[2] = rho(o[0] + c[0], o[1] + c[1]);
  }
  if (rho.kind != Density2::Kind::kCallback) {
    // rho linear on the triangle from its vertex values: exact mass and first moment; the
    // second moment (degree 3) by the degree-4 rule.
    m.mass += ar * (r[0] + r[1] + r[2]) / 3;
    for (int k = 0; k < 2; ++k) {
      (k == 0 ? m.mx : m.my) += ar *
                                ((2 * r[0] + r[1] + r[2]) * a[k] + (r[0] + 2 * r[1] + r[2]) * b[k] +
                                 (r[0] + r[1] + 2 * r[2]) * c[k]) /
                                12;
    }
    double e = 0;
    for (const auto& q : kQuad) {
      const double x = q[0] * a[0] + q[1] * b[0] + q[2] * c[0];
      const double y = q[0] * a[1] + q[1] * b[1] + q[2] * c[1];
      e += q[3] * (q[0] * r[0] + q[1] * r[1] + q[2] * r[2]) * (x * x + y * y);
    }
    m.energy += ar * e;
    return;
  }
  double mass = 0, mx = 0, my = 0, e = 0;
  for (const auto& q : kQuad7) {
    const double x = q[0] * a[0] + q[1] * b[0] + q[2] * c[0];
    const double y = q[0] * a[1] + q[1] * b[1] + q[2] * c[1];
    const double w = q[3] * rho.callback(o[0] + x, o[1] + y);
    mass += w;
    mx += w * x;
    my += w * y;
    e += w * (x * x + y * y);
  }
  m.mass += ar * mass;
  m.mx += ar * mx;
  m.my += ar * my;
  m.energy += ar * e;
}

// Is the ring (count points, counter-clockwise) convex: no right turn (exact)?
bool ring_convex(const double* ring, std::size_t count) {
  for (std::size_t j = 0; j < count; ++j) {
    if (orient2d(ring + 2 * j, ring + 2 * ((j + 1) % count), ring + 2 * ((j + 2) % count)) ==
        Sign::negative) {
      return false;
    }
  }
  return true;
}

// The moments, relative to o, of the region bounded by the rings (xy, ring_ends: end
// offsets in points), integrated over pieces that lie inside it: the horizontal slabs
// between consecutive vertex ordinates cut it into trapezoids (in each slab the edges
// spanning it, ordered by abscissa, bound the region between the 1st and 2nd, 3rd and 4th,
// ...), each split into two triangles. A fan from one point would do with signed
// triangles, but its quadrature points then lie outside the cell (across holes, out of the
// domain), where a density may be huge or undefined, and the cancellation of a quadrature
// of a sharp density fails there (a negative mass, seen with mesh2d's sizing density next
// to a small hole). The number of edges spanning a slab is even exactly (the rings are
// closed and the comparisons are of ordinates); only the abscissas are rounded.
struct SlabScratch {
  std::vector<double> ys;
  std::vector<std::array<double, 3>> crossing;  // per spanning edge: sort key, x at y0, y1
};
void add_rings_by_slabs(const Density2& rho, const double* o, const std::vector<double>& xy,
                        const std::vector<std::uint32_t>& ring_ends, SlabScratch& scratch,
                        Moments& m) {
  std::vector<double>& ys = scratch.ys;
  ys.clear();
  for (std::size_t k = 0; k < xy.size() / 2; ++k) ys.push_back(xy[2 * k + 1]);
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
  // x on edge (p, q) at ordinate y, exact at its ends.
  const auto x_at = [](const double* p, const double* q, double y) {
    if (y == p[1]) return p[0];
    if (y == q[1]) return q[0];
    return p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]);
  };
  for (std::size_t s = 0; s + 1 < ys.size(); ++s) {
    const double y0 = ys[s], y1 = ys[s + 1];
    auto& crossing = scratch.crossing;
    crossing.clear();
    std::uint32_t begin = 0;
    for (const std::uint32_t end : ring_ends) {
      for (std::uint32_t k = begin; k < end; ++k) {
        const double* p = &xy[2 * std::size_t{k}];
        const double* q = &xy[2 * std::size_t{k + 1 < end ? k + 1 : begin}];
        if (std::min(p[1], q[1]) > y0 || std::max(p[1], q[1]) < y1) continue;
        const double xa = x_at(p, q, y0), xb = x_at(p, q, y1);
        crossing.push_back({xa + xb, xa, xb});
      }
      begin = end;
    }
    std::sort(crossing.begin(), crossing.end());
    for (std::size_t k = 0; k + 1 < crossing.size(); k += 2) {
      const auto& l = crossing[k];
      const auto& r = crossing[k + 1];
      const double p0[2] = {l[1] - o[0], y0 - o[1]}, p1[2] = {r[1] - o[0], y0 - o[1]};
      const double p2[2] = {r[2] - o[0], y1 - o[1]}, p3[2] = {l[2] - o[0], y1 - o[1]};
      add_triangle_at(rho, o, p0, p1, p2, m);
      add_triangle_at(rho, o, p0, p2, p3, m);
    }
  }
}

// Exact parity test: does ring r of the domain wind around p (p not on the ring)?
bool ring_encloses(const Domain2& domain, std::uint32_t r, const double* p) {
  bool inside = false;
  for (std::uint32_t v = domain.ring_begin(r); v < domain.ring_end(r); ++v) {
    const double* a = domain.vertex(v);
    const double* b = domain.vertex(domain.next(v));
    const bool a_above = a[1] > p[1], b_above = b[1] > p[1];
    if (a_above == b_above) continue;
    // The edge crosses the horizontal line through p (half-open in y): is p left of it?
    const Sign o = a_above ? orient2d(b, a, p) : orient2d(a, b, p);
    if (o == Sign::positive) inside = !inside;
  }
  return inside;
}

}  // namespace clip2

using namespace clip2;

struct ClippedVoronoi2::Workspace {
  std::vector<double> circ;     // circumcenter of each finite triangle
  std::vector<clip2::Acc> acc;  // per cell, in triangle order: moments and their origin
  std::vector<std::uint32_t> cell_chain_begin, kind, order, pos, kind_q, tri_q, bucket;
  std::vector<std::int8_t> status;
  std::vector<std::uint8_t> is_b;
};

ClippedVoronoi2::ClippedVoronoi2() : ws_(std::make_unique<Workspace>()) {}
ClippedVoronoi2::~ClippedVoronoi2() = default;
ClippedVoronoi2::ClippedVoronoi2(ClippedVoronoi2&&) noexcept = default;
ClippedVoronoi2& ClippedVoronoi2::operator=(ClippedVoronoi2&&) noexcept = default;

struct Clip2Impl {
  const Domain2& domain;
  const Delaunay2& dt;
  const Clip2Options& options;
  ClippedVoronoi2& out;
  Clip2Impl(const Domain2& d, const Delaunay2& t, const Clip2Options& o, ClippedVoronoi2& r)
      : domain(d),
        dt(t),
        options(o),
        out(r),
        ws(*r.ws_),
        circ(ws.circ),
        cell_chain_begin(ws.cell_chain_begin),
        status(ws.status),
        poll(o.progress, "clip2d") {}
  ClippedVoronoi2::Workspace& ws;

  std::uint32_t n = 0;
  std::vector<double>& circ;  // circumcenter of each finite triangle
  std::vector<Chain> chains;
  std::vector<ClipVertex2> chain_vertices;
  std::vector<std::uint32_t>& cell_chain_begin;  // chains sorted by cell: CSR offsets
  std::vector<std::uint32_t> chain_order;
  std::vector<std::uint32_t> boundary_cells;
  std::vector<CellOut> cell_out;     // per boundary cell, in boundary_cells order
  std::vector<std::int8_t>& status;  // per site: 1 inside, 0 outside, -1 unknown
  detail::ClipPoll poll;             // progress and cancel, between chunks

  const double* site(std::uint32_t i) const { return dt.point(i); }
  // Sites far outside the domain: outside its bounding box grown by its largest extent on
  // every side. Their bisectors' points on domain edges and their Voronoi vertices are
  // constructed exactly (bisector_value2d_exact, circumcenter2d_absolute): in floating
  // point, (x - (p + q) / 2).(q - p) keeps nothing of F for sites 1e20 away, and a
  // circumcentre offset from a site 1e20 away nothing of the centre near the domain.
  // Other sites keep every bit of their constructions. (Cells are integrated from a ring
  // vertex, near the cell, whatever the site.)
  bool any_far = false;
  double near_lo[2] = {0, 0}, near_hi[2] = {0, 0};
  bool far(std::uint32_t i) const {
    if (!any_far) return false;
    const double* p = site(i);
    return !(p[0] >= near_lo[0] && p[0] <= near_hi[0] && p[1] >= near_lo[1] && p[1] <= near_hi[1]);
  }
  void find_far_sites() {
    const double* lo = domain.bbox_lo();
    const double* hi = domain.bbox_hi();
    const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
    for (int k = 0; k < 2; ++k) {
      near_lo[k] = lo[k] - extent;
      near_hi[k] = hi[k] + extent;
    }
    any_far = true;
    bool found = false;
    for (std::uint32_t i = 0; i < n && !found; ++i) found = far(i);
    any_far = found;
  }

  // ---- Symbolic vertex coordinates (one formula per vertex, shared by every cell)
  void coords(const ClipVertex2& v, double* xy) const {
    switch (v.kind) {
      case Kind::kDomainVertex:
        xy[0] = domain.vertex(v.a)[0];
        xy[1] = domain.vertex(v.a)[1];
        return;
      case Kind::kEdgeBisector: {
        const double* a = domain.vertex(v.a);
        const double* b = domain.vertex(domain.next(v.a));
        const double* pi = site(v.b);
        const double* pk = site(v.c);
        // F(x) = |x - pi|^2 - |x - pk|^2 = 2 x.(pk - pi) + |pi|^2 - |pk|^2, zero at q.
        double fa, fb;
        if (far(v.b) || far(v.c)) {
          fa = bisector_value2d_exact(a, pi, pk);
          fb = bisector_value2d_exact(b, pi, pk);
        } else {
          const double dx = pk[0] - pi[0], dy = pk[1] - pi[1];
          const double mx = 0.5 * (pi[0] + pk[0]), my = 0.5 * (pi[1] + pk[1]);
          fa = (a[0] - mx) * dx + (a[1] - my) * dy;
          fb = (b[0] - mx) * dx + (b[1] - my) * dy;
        }
        double t = fa / (fa - fb);
        if (!(t >= 0)) t = 0;  // rounding (or a symbolic tie) at an end
        if (t > 1) t = 1;
        xy[0] = a[0] + t * (b[0] - a[0]);
        xy[1] = a[1] + t * (b[1] - a[1]);
        return;
      }
      case Kind::kVoronoi:
        break;
    }
    throw Error("clip2d: internal error: a Voronoi vertex without its triangle");
  }

  // ---- Step 1: walk the rings.
  std::uint32_t cell_of_vertex(const double* a, std::uint32_t hint,
                               std::vector<std::uint32_t>& scratch) const {
    std::uint32_t c = dt.nearest_vertex(a[0], a[1], hint);
    // Descent to the perturbed cell: exact ties between sites go to the larger index.
    for (bool moved = true; moved;) {
      moved = false;
      dt.vertex_neighbors(c, scratch);
      for (const std::uint32_t k : scratch) {
        if (bisector_side_vertex2d(site(c), site(k), a, c, k) == Sign::positive) {
          c = k;
          moved = true;
          break;
        }
      }
    }
    return c;
  }

  void walk_rings() {
    std::vector<std::uint32_t> nbrs, candidates;
    std::uint32_t hint = Delaunay2::kNone;
    for (std::uint32_t r = 0; r < domain.nb_rings(); ++r) {
      const std::uint32_t v0 = domain.ring_begin(r);
      const std::uint32_t c0 = cell_of_vertex(domain.vertex(v0), hint, nbrs);
      hint = dt.vertex_triangle(c0);
      const std::size_t first_chain = chains.size();
      std::uint32_t c = c0;
      Chain cur{c, static_cast<std::uint32_t>(chain_vertices.size()), 0, kNone, kNone, kNone, kNone,
                r};
      chain_vertices.push_back(domain_vertex(v0));
      std::uint32_t v = v0;
      do {
        const std::uint32_t w = domain.next(v);
        const double* a = domain.vertex(v);
        const double* b = domain.vertex(w);
        for (;;) {
          dt.vertex_neighbors(c, nbrs);
          candidates.clear();
          for (const std::uint32_t k : nbrs) {
            if (bisector_side_vertex2d(site(c), site(k), b, c, k) == Sign::positive) {
              candidates.push_back(k);
            }
          }
          if (candidates.empty()) break;
          std::uint32_t best = candidates[0];
          for (std::size_t j = 1; j < candidates.size(); ++j) {
            const std::uint32_t k = candidates[j];
            if (bisector_side_edge2d(site(c), site(k), site(best), a, b, c, k, best) ==
                Sign::negative) {
              best = k;
            }
          }
          // Leave c through bisector(c, best) on edge v.
          chain_vertices.push_back(edge_bisector(v, c, best));
          cur.end = static_cast<std::uint32_t>(chain_vertices.size());
          cur.exit_edge = v;
          cur.exit_site = best;
          chains.push_back(cur);
          cur = Chain{
              best, static_cast<std::uint32_t>(chain_vertices.size()), 0, v, c, kNone, kNone, r};
          chain_vertices.push_back(edge_bisector(v, c, best));
          c = best;
        }
        if (w != v0) chain_vertices.push_back(domain_vertex(w));
        v = w;
      } while (v != v0);
      if (c != c0) {
        throw Error("clip2d: internal error: the walk around ring " + std::to_string(r) +
                    " did not return to its first cell");
      }
      cur.end = static_cast<std::uint32_t>(chain_vertices.size());
      if (chains.size() == first_chain) {
        chains.push_back(cur);  // the whole ring lies in one cell: a closed chain
        continue;
      }
      // The last chain continues into the first one (they are in cell c0, split at v0):
      // append the first chain's vertices to it and let it replace the first.
      Chain& first = chains[first_chain];
      std::vector<ClipVertex2> tail(chain_vertices.begin() + first.begin,
                                    chain_vertices.begin() + first.end);
      const std::uint32_t begin = cur.begin;
      chain_vertices.insert(chain_vertices.end(), tail.begin(), tail.end());
      first.begin = begin;
      first.end = static_cast<std::uint32_t>(chain_vertices.size());
      first.entry_edge = cur.entry_edge;
      first.entry_site = cur.entry_site;
    }
    // Chains grouped by cell (counting sort, stable: ring order within a cell).
    cell_chain_begin.assign(n + 1, 0);
    for (const Chain& ch : chains) ++cell_chain_begin[ch.cell + 1];
    for (std::uint32_t i = 0; i < n; ++i) cell_chain_begin[i + 1] += cell_chain_begin[i];
    chain_order.resize(chains.size());
    std::vector<std::uint32_t> fill(cell_chain_begin.begin(), cell_chain_begin.end() - 1);
    for (std::uint32_t k = 0; k < chains.size(); ++k) chain_order[fill[chains[k].cell]++] = k;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (cell_chain_begin[i + 1] > cell_chain_begin[i]) boundary_cells.push_back(i);
    }
  }

  // ---- Step 2: assemble a boundary cell.
  struct Crossing {
    std::uint32_t chain;
    bool entry;
    std::uint32_t slot;  // position of the neighbour (Voronoi edge) around the cell
    std::uint32_t edge;  // domain edge crossing it
  };

  void assemble(std::uint32_t c, std::vector<std::uint32_t>& tris, std::vector<std::uint32_t>& nbrs,
                std::vector<Crossing>& xs, CellOut& res) const {
    dt.triangles_around_vertex(c, tris);
    const std::uint32_t nt = static_cast<std::uint32_t>(tris.size());
    nbrs.clear();
    for (const std::uint32_t t : tris) {
      nbrs.push_back(dt.tri_vertex(t, (dt.local_index(t, c) + 1) % 3));
    }
    const bool hull = dt.is_hull_vertex(c);
    if (hull) {
      const std::uint32_t t = tris.back();
      nbrs.push_back(dt.tri_vertex(t, (dt.local_index(t, c) + 2) % 3));
    }
    const std::uint32_t m = static_cast<std::uint32_t>(nbrs.size());
    // Voronoi edge of neighbour slot j runs from the circumcenter of tris[j - 1] to that
    // of tris[j] (counter-clockwise around c); for a hull cell slot 0 comes from infinity
    // and slot m - 1 goes to infinity.
    const auto slot_of = [&](std::uint32_t k) {
      for (std::uint32_t j = 0; j < m; ++j) {
        if (nbrs[j] == k) return j;
      }
      throw Error("clip2d: internal error: crossing with a site that is not a neighbour");
    };
    const auto push_voronoi = [&](std::uint32_t j) {
      const std::uint32_t t = tris[j % nt];
      res.vertices.push_back(
          voronoi_vertex(dt.tri_vertex(t, 0), dt.tri_vertex(t, 1), dt.tri_vertex(t, 2)));
      res.tris.push_back(t);
    };
    const auto push_chain = [&](const Chain& ch) {
      for (std::uint32_t k = ch.begin; k < ch.end; ++k) {
        res.vertices.push_back(chain_vertices[k]);
        res.tris.push_back(kNone);
      }
    };
    const auto push_ring_end = [&] {
      res.ring_ends.push_back(static_cast<std::uint32_t>(res.vertices.size()));
    };

    xs.clear();
    bool open = false;
    std::vector<std::uint8_t> ring_in_cell;  // rings with a chain in this cell
    for (std::uint32_t q = cell_chain_begin[c]; q < cell_chain_begin[c + 1]; ++q) {
      const Chain& ch = chains[chain_order[q]];
      if (ch.entry_site == kNone) {
        push_chain(ch);
        push_ring_end();
        if (ring_in_cell.empty()) ring_in_cell.assign(domain.nb_rings(), 0);
        ring_in_cell[ch.ring] = 1;
        continue;
      }
      open = true;
      xs.push_back({chain_order[q], true, slot_of(ch.entry_site), ch.entry_edge});
      xs.push_back({chain_order[q], false, slot_of(ch.exit_site), ch.exit_edge});
    }

    if (!open) {
      // No crossing: the cell's boundary is wholly inside or outside the domain. Inside
      // exactly when an odd number of the rings that miss the cell wind around the site.
      if (hull) return;
      bool inside = false;
      for (std::uint32_t r = 0; r < domain.nb_rings(); ++r) {
        if (!ring_in_cell.empty() && ring_in_cell[r]) continue;
        if (ring_encloses(domain, r, site(c))) inside = !inside;
      }
      if (!inside) return;
      for (std::uint32_t j = 0; j < m; ++j) push_voronoi(j);
      push_ring_end();
      res.walked = nbrs;
      return;
    }

    // Crossings in counter-clockwise order around the cell.
    const double* pc = site(c);
    std::sort(xs.begin(), xs.end(), [&](const Crossing& x, const Crossing& y) {
      if (x.slot != y.slot) return x.slot < y.slot;
      if (x.edge == y.edge && x.chain == y.chain) return false;
      const std::uint32_t k = nbrs[x.slot];
      const double* a1 = domain.vertex(x.edge);
      const double* b1 = domain.vertex(domain.next(x.edge));
      const double* a2 = domain.vertex(y.edge);
      const double* b2 = domain.vertex(domain.next(y.edge));
      const Sign s = compare_on_bisector2d(pc, site(k), a1, b1, a2, b2, c, k);
      if (s == Sign::zero) {
        throw Error("clip2d: internal error: two boundary edges cross bisector(" +
                    std::to_string(c) + ", " + std::to_string(k) + ") at the same point");
      }
      return s == Sign::positive;
    });
    const std::uint32_t nx = static_cast<std::uint32_t>(xs.size());
    // Position of each chain's exit in the sorted crossings.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> exit_of;
    for (std::uint32_t q = 0; q < nx; ++q) {
      if (!xs[q].entry) exit_of.emplace_back(xs[q].chain, q);
    }
    std::sort(exit_of.begin(), exit_of.end());
    std::vector<std::uint8_t> used(nx, 0);
    std::vector<std::uint8_t> walked(m, 0);
    for (std::uint32_t s0 = 0; s0 < nx; ++s0) {
      if (xs[s0].entry || used[s0]) continue;
      // Start a ring at the chain ending at exit s0.
      std::uint32_t s = s0;
      for (std::uint32_t guard = 0;; ++guard) {
        if (guard > nx) throw Error("clip2d: internal error: a cell ring does not close");
        used[s] = 1;
        const std::uint32_t next = (s + 1) % nx;
        const Crossing& ex = xs[s];
        const Crossing& en = xs[next];
        if (!en.entry) {
          throw Error("clip2d: internal error: two exits in a row around cell " +
                      std::to_string(c));
        }
        // Voronoi vertices between the exit and the next entry.
        std::uint32_t steps = (en.slot + m - ex.slot) % m;
        if (next <= s && en.slot == ex.slot) steps = m;  // all the way around
        if (hull && ex.slot + steps > m - 1) {
          throw Error("clip2d: internal error: cell " + std::to_string(c) +
                      " would be closed through infinity");
        }
        for (std::uint32_t j = 0; j < steps; ++j) {
          push_voronoi(ex.slot + j);
          if (j > 0) walked[(ex.slot + j) % m] = 1;
        }
        // The entry's chain, from its entry crossing to its exit crossing.
        push_chain(chains[en.chain]);
        used[next] = 1;
        // Continue at that chain's exit.
        const auto it = std::lower_bound(exit_of.begin(), exit_of.end(),
                                         std::make_pair(en.chain, std::uint32_t{0}));
        const std::uint32_t e = it->second;
        if (e == s0) break;
        s = e;
      }
      push_ring_end();
    }
    for (std::uint32_t j = 0; j < m; ++j) {
      if (walked[j]) res.walked.push_back(nbrs[j]);
    }
  }

  void run() {
    n = dt.nb_points();
    const std::uint32_t nt = dt.nb_triangles();
    poll.phase("cells", n);
    circ.resize(2 * std::size_t{nt});
    find_far_sites();
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nt, 4096), [&](const auto& range) {
      if (!poll.running()) return;
      for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
        const std::uint32_t a = dt.tri_vertex(t, 0), b = dt.tri_vertex(t, 1),
                            c = dt.tri_vertex(t, 2);
        if (far(a) || far(b) || far(c)) {
          circumcenter2d_absolute(site(a), site(b), site(c), circ.data() + 2 * std::size_t{t});
        } else {
          dt.circumcenter(t, circ.data() + 2 * std::size_t{t});
        }
      }
      poll.chunk(0);
    });
    poll.check();
    walk_rings();

    // Assemble boundary cells.
    cell_out.assign(boundary_cells.size(), CellOut{});
    struct Scratch {
      std::vector<std::uint32_t> tris, nbrs;
      std::vector<Crossing> xs;
    };
    tbb::enumerable_thread_specific<Scratch> scratch;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, boundary_cells.size(), 16),
                      [&](const auto& range) {
                        if (!poll.running()) return;
                        Scratch& s = scratch.local();
                        for (std::size_t q = range.begin(); q != range.end(); ++q) {
                          assemble(boundary_cells[q], s.tris, s.nbrs, s.xs, cell_out[q]);
                        }
                        poll.chunk(0);  // counted in cells below
                      });
    poll.check();

    classify_inner_cells();
    integrate();
  }

  // ---- Step 3: inside or outside, for the cells no ring crosses. Each boundary cell
  // seeds its other neighbours (inside when it walked their whole Voronoi edge); when a
  // seed says outside (sites outside the domain), the seeds spread over the components of
  // the graph of non-boundary cells (union-find over Delaunay edges, in triangle order).
  void classify_inner_cells() {
    status.assign(n, -1);
    std::vector<std::uint8_t>& is_b = ws.is_b;
    is_b.assign(n, 0);
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
          throw Error("clip2d: internal error: inconsistent inside/outside seeds at site " +
                      std::to_string(k));
        }
        status[k] = st;
        any_outside = any_outside || st == 0;
      }
    }
    if (!any_outside) {
      // Every component of non-boundary cells touches a boundary cell, and all said inside.
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
    const std::vector<std::uint32_t>& tv = dt.tri_vertices();
    for (std::size_t t = 0; t < dt.nb_triangles(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t u = tv[3 * t + static_cast<std::size_t>(k)];
        const std::uint32_t w = tv[3 * t + static_cast<std::size_t>((k + 1) % 3)];
        if (is_b[u] || is_b[w]) continue;
        const std::uint32_t ru = find(u), rw = find(w);
        if (ru != rw) parent[std::max(ru, rw)] = std::min(ru, rw);
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

  // The finite triangles around vertex v (t0: one of them) counter-clockwise, read straight
  // from the
  // neighbour codes (3t' + k': v is at k' + 1 in the triangle t' across edge k + 1 of t).
  // Returns false for a hull vertex (then `tris` is not filled: use the Delaunay2 walk).
  bool inner_fan(std::uint32_t v, std::uint32_t t0, std::vector<std::uint32_t>& tris) const {
    tris.clear();
    const std::vector<std::uint32_t>& tv = dt.tri_vertices();
    const std::vector<std::uint32_t>& tn = dt.tri_neighbors();
    const std::uint32_t nt = dt.nb_triangles();
    std::uint32_t t = t0;
    std::uint32_t k = tv[3 * std::size_t{t}] == v ? 0 : tv[3 * std::size_t{t} + 1] == v ? 1 : 2;
    do {
      tris.push_back(t);
      const std::uint32_t code = tn[3 * std::size_t{t} + (k + 1) % 3];
      t = code / 3;
      if (t >= nt) return false;
      k = (code % 3 + 1) % 3;
    } while (t != t0);
    return true;
  }

  void integrate() {
    out.cells_.resize(n);
    out.nb_boundary_ = static_cast<std::uint32_t>(boundary_cells.size());
    // Per site, one word: the boundary cell's slot, kInner (inside, unclipped) or kEmpty
    // (a duplicate, or outside the domain).
    constexpr std::uint32_t kInner = 0xfffffffeu, kEmpty = 0xffffffffu;
    std::vector<std::uint32_t>& kind = ws.kind;
    kind.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      kind[i] = dt.duplicate_of(i) == i && status[i] == 1 ? kInner : kEmpty;
    }
    for (std::uint32_t q = 0; q < boundary_cells.size(); ++q) kind[boundary_cells[q]] = q;

    const Density2& rho = options.density;
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> tri_scratch;
    tbb::enumerable_thread_specific<std::vector<double>> xy_scratch;
    tbb::enumerable_thread_specific<SlabScratch> slab_scratch;
    // Two passes, so that no pass reads memory at random per cell (sites come in any
    // order; the triangles are numbered along the BRIO curve):
    //  A. cells in the order of their first triangle (so neighbouring cells read
    //     neighbouring triangles), moments relative to the cell's first ring vertex o,
    //     written in that order;
    //  B. cells in index order: moments moved to the site (energy by the parallel-axis
    //     identity), written in place.
    const std::uint32_t nt = dt.nb_triangles();
    std::vector<std::uint32_t>& order = ws.order;
    std::vector<std::uint32_t>& pos = ws.pos;
    std::vector<std::uint32_t>& kind_q = ws.kind_q;
    std::vector<std::uint32_t>& tri_q = ws.tri_q;
    std::vector<std::uint32_t>& bucket = ws.bucket;
    order.resize(n);
    pos.resize(n);
    kind_q.resize(n);
    tri_q.resize(n);
    bucket.assign(std::size_t{nt} + 2, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t t = kind[i] != kEmpty ? dt.vertex_triangle(i) : nt;
      ++bucket[std::size_t{t} + 1];
    }
    for (std::size_t t = 0; t + 1 < bucket.size(); ++t) bucket[t + 1] += bucket[t];
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t t = kind[i] != kEmpty ? dt.vertex_triangle(i) : nt;
      const std::uint32_t q = bucket[t]++;
      order[q] = i;
      pos[i] = q;
      kind_q[q] = kind[i];
      tri_q[q] = t;
    }
    std::vector<Acc>& acc = ws.acc;
    acc.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 1024), [&](const auto& range) {
      if (!poll.running()) return;
      std::vector<std::uint32_t>& tris = tri_scratch.local();
      std::vector<double>& xy = xy_scratch.local();
      for (std::uint32_t q = range.begin(); q != range.end(); ++q) {
        Acc& a = acc[q];
        a.m = Moments{};
        a.o[0] = a.o[1] = 0;
        const std::uint32_t ki = kind_q[q];
        if (ki == kEmpty) continue;  // a duplicate, or a cell outside the domain
        bool first = true;
        const auto add_ring = [&](const double* ring, std::size_t count) {
          if (first) {
            a.o[0] = ring[0];
            a.o[1] = ring[1];
            first = false;
          }
          for (std::size_t j = 0; j < count; ++j) {
            const double* u = ring + 2 * j;
            const double* w = ring + 2 * ((j + 1) % count);
            add_triangle(rho, a.o, u[0] - a.o[0], u[1] - a.o[1], w[0] - a.o[0], w[1] - a.o[1], a.m);
          }
        };
        if (ki != kInner) {
          const CellOut& co = cell_out[ki];
          const std::uint32_t nb = co.ring_ends.empty() ? 0 : co.ring_ends.back();
          xy.resize(2 * std::size_t{nb});
          for (std::uint32_t k = 0; k < nb; ++k) vertex_xy(co, k, xy.data() + 2 * std::size_t{k});
          // A variable density is integrated only inside the cell: a convex cell by its
          // fan, any other by slabs (add_rings_by_slabs).
          if (!rho.is_constant() && nb > 0) {
            a.o[0] = xy[0];
            a.o[1] = xy[1];
            if (co.ring_ends.size() == 1 && ring_convex(xy.data(), nb)) {
              const double zero[2] = {0, 0};
              for (std::uint32_t k = 1; k + 1 < nb; ++k) {
                const double u[2] = {xy[2 * k] - a.o[0], xy[2 * k + 1] - a.o[1]};
                const double w[2] = {xy[2 * k + 2] - a.o[0], xy[2 * k + 3] - a.o[1]};
                add_triangle_at(rho, a.o, zero, u, w, a.m);
              }
            } else {
              add_rings_by_slabs(rho, a.o, xy, co.ring_ends, slab_scratch.local(), a.m);
            }
          } else {
            std::uint32_t begin = 0;
            for (const std::uint32_t end : co.ring_ends) {
              add_ring(xy.data() + 2 * std::size_t{begin}, end - begin);
              begin = end;
            }
          }
        } else {
          const std::uint32_t i = order[q];
          if (!inner_fan(i, tri_q[q], tris)) dt.triangles_around_vertex(i, tris);
          xy.resize(2 * tris.size());
          for (std::size_t k = 0; k < tris.size(); ++k) {
            xy[2 * k] = circ[2 * std::size_t{tris[k]}];
            xy[2 * k + 1] = circ[2 * std::size_t{tris[k]} + 1];
          }
          add_ring(xy.data(), tris.size());
        }
      }
      poll.chunk(range.size());
    });
    poll.check();
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 4096), [&](const auto& range) {
      for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
        const Acc& a = acc[pos[i]];
        const double* s = site(i);
        const double dx = a.o[0] - s[0], dy = a.o[1] - s[1];
        // Offsets above 2^500 (~3e150): the energy |o - s|^2 area may overflow.
        if (a.m.area != 0 && !(std::fabs(dx) <= 0x1p500 && std::fabs(dy) <= 0x1p500)) {
          throw Error("clip2d: site " + std::to_string(i) + " (" + std::to_string(s[0]) + ", " +
                      std::to_string(s[1]) +
                      ") is too far from the domain for its cell's integrals in double "
                      "precision (a coordinate more than 2^500 from its cell), and its cell "
                      "meets the domain");
        }
        ClippedVoronoi2::Cell& cell = out.cells_[i];
        cell.area = a.m.area;
        cell.mass = a.m.mass;
        // ∫rho |x - s|^2 = ∫rho |x - o|^2 + 2 (o - s).∫rho (x - o) + |o - s|^2 ∫rho
        cell.energy = a.m.energy + 2 * (dx * a.m.mx + dy * a.m.my) + (dx * dx + dy * dy) * a.m.mass;
        cell.centroid[0] = a.m.mass > 0 ? a.o[0] + a.m.mx / a.m.mass : s[0];
        cell.centroid[1] = a.m.mass > 0 ? a.o[1] + a.m.my / a.m.mass : s[1];
        cell.boundary = kind[i] < kInner ? 1 : 0;
      }
    });
    out.total_area_ = out.total_mass_ = out.total_energy_ = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      out.total_area_ += out.cells_[i].area;
      out.total_mass_ += out.cells_[i].mass;
      out.total_energy_ += out.cells_[i].energy;
    }

    out.cell_ring_begin_.clear();
    out.ring_vertex_begin_.clear();
    out.vertices_.clear();
    out.vertex_xy_.clear();
    if (!options.keep_geometry) return;
    std::vector<std::uint32_t> tris;
    out.cell_ring_begin_.push_back(0);
    out.ring_vertex_begin_.push_back(0);
    const auto push_vertex = [&](const CellOut& co, std::uint32_t k) {
      double xy[2];
      vertex_xy(co, k, xy);
      out.vertices_.push_back(co.vertices[k]);
      out.vertex_xy_.push_back(xy[0]);
      out.vertex_xy_.push_back(xy[1]);
    };
    for (std::uint32_t i = 0; i < n; ++i) {
      if (kind[i] < kInner) {
        const CellOut& co = cell_out[kind[i]];
        std::uint32_t begin = 0;
        for (const std::uint32_t end : co.ring_ends) {
          for (std::uint32_t k = begin; k < end; ++k) push_vertex(co, k);
          out.ring_vertex_begin_.push_back(static_cast<std::uint32_t>(out.vertices_.size()));
          begin = end;
        }
      } else if (kind[i] == kInner) {
        dt.triangles_around_vertex(i, tris);
        for (const std::uint32_t t : tris) {
          out.vertices_.push_back(
              voronoi_vertex(dt.tri_vertex(t, 0), dt.tri_vertex(t, 1), dt.tri_vertex(t, 2)));
          out.vertex_xy_.push_back(circ[2 * std::size_t{t}]);
          out.vertex_xy_.push_back(circ[2 * std::size_t{t} + 1]);
        }
        out.ring_vertex_begin_.push_back(static_cast<std::uint32_t>(out.vertices_.size()));
      }
      out.cell_ring_begin_.push_back(static_cast<std::uint32_t>(out.ring_vertex_begin_.size() - 1));
    }
  }

  void vertex_xy(const CellOut& co, std::uint32_t k, double* xy) const {
    if (co.tris[k] == kNone) {
      coords(co.vertices[k], xy);
      return;
    }
    xy[0] = circ[2 * std::size_t{co.tris[k]}];
    xy[1] = circ[2 * std::size_t{co.tris[k]} + 1];
  }
};

void ClippedVoronoi2::compute(const Domain2& domain, const Delaunay2& dt,
                              const Clip2Options& options) {
  nb_auxiliary_ = 0;
  seconds_delaunay_ = 0;
  if (domain.nb_rings() == 0) throw Error("clip2d: the domain is empty");
  if (dt.nb_points() == 0) throw Error("clip2d: no sites");
  if (!ws_) ws_ = std::make_unique<Workspace>();  // a moved-from object
  Clip2Impl impl(domain, dt, options, *this);
  try {
    impl.run();
  } catch (...) {
    cells_.clear();  // partly written
    throw;
  }
}

namespace {

// The dimension of the affine hull of n >= 1 points (0: one point, 1: a line, 2: the
// plane), decided exactly, and a direction along the line (dimension 1).
int affine_dimension2(const double* xy, std::uint32_t n, double* along) {
  const double* a = xy;
  std::uint32_t j = 1;
  while (j < n && xy[2 * j] == a[0] && xy[2 * j + 1] == a[1]) ++j;
  if (j == n) return 0;
  const double* b = xy + 2 * std::size_t{j};
  for (std::uint32_t k = j + 1; k < n; ++k) {
    if (orient2d(a, b, xy + 2 * std::size_t{k}) != Sign::zero) return 2;
  }
  along[0] = b[0] - a[0];
  along[1] = b[1] - a[1];
  return 1;
}

}  // namespace

void ClippedVoronoi2::compute(const Domain2& domain, const double* sites, std::uint32_t n,
                              const Clip2Options& options) {
  if (n == 0) throw Error("clip2d: no sites");
  if (domain.nb_rings() == 0) throw Error("clip2d: the domain is empty");
  const auto t0 = std::chrono::steady_clock::now();
  sites_.assign(sites, sites + 2 * std::size_t{n});
  double lo[2], hi[2];
  // A non-finite coordinate: the triangulation names the site.
  const bool finite = finite_bounding_box(sites, n, 2, lo, hi) == n;
  double along[2] = {1, 0};
  const int dimension = finite ? affine_dimension2(sites, n, along) : 2;
  std::uint32_t k = 0;
  if (dimension < 2) {
    // One site, or sites on one line: 3 or 2 auxiliary sites at distance L >= 4 D from the
    // centre c of the bounding box B of the domain and the sites (diagonal D). A point x
    // of the domain is within D of every site and at least L - D/2 > D from an auxiliary
    // site, so the auxiliary cells miss the domain and every site's cell is what it is
    // without them, exactly: the predicates decide on the sites as given; the auxiliary
    // coordinates only have to be far, not exact.
    double blo[2], bhi[2];
    for (int a = 0; a < 2; ++a) {
      blo[a] = std::min(lo[a], domain.bbox_lo()[a]);
      bhi[a] = std::max(hi[a], domain.bbox_hi()[a]);
    }
    const double c[2] = {0.5 * blo[0] + 0.5 * bhi[0], 0.5 * blo[1] + 0.5 * bhi[1]};
    const double diagonal = std::hypot(bhi[0] - blo[0], bhi[1] - blo[1]);
    const double far = std::ldexp(1.0, std::ilogb(std::max(diagonal, 1e-300)) + 3);  // >= 4 D
    std::vector<std::array<double, 2>> directions;
    if (dimension == 1) {  // both ways across the line
      const double l = std::hypot(along[0], along[1]);
      directions = {{-along[1] / l, along[0] / l}, {along[1] / l, -along[0] / l}};
    } else {  // a triangle around c
      const double h = std::sqrt(3.0) / 2;
      directions = {{1, 0}, {-0.5, h}, {-0.5, -h}};
    }
    for (const auto& d : directions) {
      const double q[2] = {c[0] + far * d[0], c[1] + far * d[1]};
      if (!std::isfinite(q[0]) || !std::isfinite(q[1])) {
        throw Error("clip2d: the sites do not span the plane (" +
                    std::string(dimension == 0 ? "one point" : "one line") +
                    ") and lie too far out for auxiliary sites beyond them");
      }
      sites_.push_back(q[0]);
      sites_.push_back(q[1]);
    }
    k = static_cast<std::uint32_t>(directions.size());
  }
  dt_.build(sites_.data(), n + k);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  compute(domain, dt_, options);
  seconds_delaunay_ = seconds;
  if (k == 0) return;
  // The auxiliary cells are empty and last: dropping them leaves every offset in place.
  for (std::uint32_t i = n; i < n + k; ++i) {
    if (cells_[i].area != 0 || cells_[i].boundary != 0) {
      throw Error("clip2d: internal error: an auxiliary site's cell meets the domain");
    }
  }
  cells_.resize(n);
  if (!cell_ring_begin_.empty()) cell_ring_begin_.resize(std::size_t{n} + 1);
  nb_auxiliary_ = k;
}

}  // namespace voroclip
