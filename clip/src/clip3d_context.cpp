// The context of one 3D clipped Voronoi diagram (clip3d.cpp, clip3d_internal.h): what the
// units share.
//
// Coordinates of symbolic vertices (DESIGN.md, "Exactness"; Yan et al. 2011, sec. 4: the
// vertices of the restricted surface and of the clipped cells). A vertex is kept as what
// defines it; its coordinates are computed here, in floating point, from its sorted
// global ids only, so that every cell (and every unit) that meets it computes the same
// bits: a mesh edge ∩ one bisector, a boundary triangle's plane ∩ two bisectors, a
// Voronoi vertex (three bisectors: the circumcentre of four sites). No decision depends on
// them.
//
// Stars (the Voronoi neighbours of a site are its Delaunay neighbours): the tets around a
// site, breadth first, and per thread (Stars) the neighbour lists of the sites met, with
// their geometry, kept for the rest of the compute.
#include "clip3d_internal.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace voroclip {

namespace clip3 {

Clip3Context::Clip3Context(const Domain3& d, const Delaunay3& t, const Clip3Options& o,
                           detail::ClipPoll* p)
    : domain(d),
      surface(d.surface()),
      dt(t),
      options(o),
      n(t.nb_points()),
      weighted(!o.density.is_constant()),
      linear_density(o.density.kind == Density3::Kind::kVertexLinear),
      callback_density(o.density.kind == Density3::Kind::kCallback ? &o.density : nullptr),
      keep_surface(o.keep_surface || o.keep_geometry),
      poll(p) {
  // The near box (Clip3Context::far): the bounding box grown by its largest extent.
  const double* lo = d.bbox_lo();
  const double* hi = d.bbox_hi();
  const double extent = std::max(std::max(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
  for (int k = 0; k < 3; ++k) {
    near_lo[k] = lo[k] - extent;
    near_hi[k] = hi[k] + extent;
    centre[k] = 0.5 * (lo[k] + hi[k]);
  }
  any_far = true;  // far() tests the box while any_far is set
  bool found = false;
  for (std::uint32_t i = 0; i < n && !found; ++i) found = far(i);
  any_far = found;
}

// Offsets of a far site from the domain's centre up to 2^500 (~3e150): the squared
// distances (F, the feet, the energy ~ |offset|^2 V) stay below 2^1002, finite, and the
// exact constructions' expansions cover such spans (plan_expansion_scaling, else big
// integers). Beyond, the energy alone may overflow: an error rather than inf or NaN.
constexpr double kMaxFarOffset = 0x1p500;

void Clip3Context::check_far_site(std::uint32_t i) const {
  const double* p = site(i);
  for (int k = 0; k < 3; ++k) {
    if (!(std::fabs(p[k] - centre[k]) <= kMaxFarOffset)) {
      throw Error("clip3d: site " + std::to_string(i) + " (" + std::to_string(p[0]) + ", " +
                  std::to_string(p[1]) + ", " + std::to_string(p[2]) +
                  ") is too far from the domain for its cell's integrals in double precision "
                  "(a coordinate more than 2^500 from the domain's centre), and its cell meets "
                  "the domain");
    }
  }
}

void Clip3Context::foot(std::uint32_t i, std::uint32_t j, double* h) const {
  const double* pi = site(i);
  const double* pj = site(j);
  if (!far(i)) {
    for (int k = 0; k < 3; ++k) h[k] = 0.5 * (pj[k] - pi[k]);
    return;
  }
  const double f = bisector_value3d_exact(centre, pi, pj);
  const double e[3] = {pj[0] - pi[0], pj[1] - pi[1], pj[2] - pi[2]};
  const double ee = (e[0] * e[0] + e[1] * e[1]) + e[2] * e[2];
  const double t = -f / (2 * ee);
  for (int k = 0; k < 3; ++k) h[k] = t * e[k];
}

DensityBatch& thread_density_batch() {
  thread_local DensityBatch batch;
  return batch;
}

void DensityBatch::flush() {
  struct Clear {
    DensityBatch& b;
    ~Clear() { b.tets_.clear(); }
  } clear{*this};
  const std::size_t count = tets_.size();
  if (count == 0) return;
  const Density3& rho = *rho_;
  const bool quadratic = rho.rule == Density3::Rule::kQuadratic;
  const std::size_t per = quadratic ? 10 : 14;
  index_.resize(per * count);
  points_.clear();
  if (quadratic) {
    for (std::size_t t = 0; t < count; ++t) {
      const Tet& c = tets_[t];
      double p[30];
      p2_nodes(c.x, c.a, c.b, c.c, p);
      for (std::size_t n = 0; n < 10; ++n) {
        std::uint64_t b[3];
        std::memcpy(b, p + 3 * n, sizeof b);
        const std::uint64_t h = (b[0] * 0x9E3779B97F4A7C15ull) ^ (b[1] * 0xC2B2AE3D27D4EB4Full) ^
                                (b[2] * 0x165667B19E3779F9ull);
        std::uint32_t& e = table_[h >> 52];  // the top 12 bits: kSlots
        if (3 * std::size_t{e} + 3 <= points_.size() &&
            std::memcmp(points_.data() + 3 * std::size_t{e}, b, sizeof b) == 0) {
          index_[10 * t + n] = e;
        } else {
          e = static_cast<std::uint32_t>(points_.size() / 3);
          index_[10 * t + n] = e;
          points_.insert(points_.end(), p + 3 * n, p + 3 * n + 3);
        }
      }
    }
  } else {
    points_.resize(3 * 14 * count);
    for (std::size_t t = 0; t < count; ++t) {
      const Tet& c = tets_[t];
      degree5_points(c.x, c.a, c.b, c.c, points_.data() + 3 * 14 * t);
      for (std::size_t n = 0; n < 14; ++n) {
        index_[14 * t + n] = static_cast<std::uint32_t>(14 * t + n);
      }
    }
  }
  const std::size_t m = points_.size() / 3;
  values_.resize(m);
  if (rho.batch) {
    rho.batch(points_.data(), m, values_.data());
  } else {
    for (std::size_t k = 0; k < m; ++k) {
      values_[k] = rho.callback(points_[3 * k], points_[3 * k + 1], points_[3 * k + 2]);
    }
  }
  for (std::size_t t = 0; t < count; ++t) {
    const Tet& c = tets_[t];
    double f[14];
    for (std::size_t n = 0; n < per; ++n) f[n] = values_[index_[per * t + n]];
    if (quadratic) {
      add_tet_p2(f, c.a, c.b, c.c, *c.r);
    } else {
      add_tet_degree5(f, c.a, c.b, c.c, *c.r);
    }
  }
}

void DensityBatch::evaluate_staged() {
  const std::size_t m = staged_;
  if (m == 0) return;
  const std::size_t first = values_.size();
  values_.resize(first + m);
  double* out = values_.data() + first;
  const Density3& rho = *rho_;
  if (rho.batch) {
    rho.batch(stage_, m, out);
  } else {
    for (std::size_t k = 0; k < m; ++k) {
      out[k] = rho.callback(stage_[3 * k], stage_[3 * k + 1], stage_[3 * k + 2]);
    }
  }
  staged_ = 0;
}

void Clip3Context::star(std::uint32_t v, Star& s) const {
  const std::uint32_t slots = dt.nb_tet_slots();
  s.reset_if_needed(slots);
  s.first = s.next;
  s.tets.clear();
  const std::uint32_t t0 = dt.vertex_tet(v);
  s.mark[t0] = s.first;
  s.tets.push_back(t0);
  for (std::size_t q = 0; q < s.tets.size(); ++q) {
    const std::uint32_t t = s.tets[q];
    for (int f = 0; f < 4; ++f) {
      if (dt.tet_vertex(t, f) == v) continue;  // the facet opposite v does not contain v
      const std::uint32_t t2 = dt.tet_adjacent(t, f);
      if (s.mark[t2] < s.first) {
        s.mark[t2] = s.first + static_cast<std::uint32_t>(s.tets.size());
        s.tets.push_back(t2);
        dt.prefetch_tet(t2);
      }
    }
  }
  s.next = s.first + static_cast<std::uint32_t>(s.tets.size());
}

// F(x) = |x - p|^2 - |x - q|^2 relative to the midpoint: 2 (x - m).(q - p), halved.
static double bisector_f(const double* a, const double* p, const double* q) {
  double f = 0;
  for (int c = 0; c < 3; ++c) f += (a[c] - 0.5 * (p[c] + q[c])) * (q[c] - p[c]);
  return f;
}

void Clip3Context::edge_point(std::uint32_t ma, std::uint32_t mb, std::uint32_t s0,
                              std::uint32_t s1, double* x) const {
  const double* a = domain.vertex(ma);
  const double* b = domain.vertex(mb);
  double fa, fb;
  if (far(s0) || far(s1)) {
    // F exactly: the midpoint form keeps nothing of it for sites 1e20 away.
    fa = bisector_value3d_exact(a, site(s0), site(s1));
    fb = bisector_value3d_exact(b, site(s0), site(s1));
  } else {
    fa = bisector_f(a, site(s0), site(s1));
    fb = bisector_f(b, site(s0), site(s1));
  }
  double s = fa / (fa - fb);
  if (!(s >= 0)) s = 0;
  if (s > 1) s = 1;
  for (int c = 0; c < 3; ++c) x[c] = a[c] + s * (b[c] - a[c]);
}

void Clip3Context::facet_point(const std::uint32_t* mesh, const std::uint32_t* sites,
                               double* x) const {
  const double* a = domain.vertex(mesh[0]);
  const double* b = domain.vertex(mesh[1]);
  const double* c = domain.vertex(mesh[2]);
  const double* p0 = site(sites[0]);
  const double* p1 = site(sites[1]);
  const double* p2 = site(sites[2]);
  if ((far(sites[0]) || far(sites[1]) || far(sites[2])) &&
      plane_bisectors_point3d_absolute(a, b, c, p0, p1, p2, x)) {
    return;
  }
  const double k0 = bisector_f(a, p0, p1), k1 = bisector_f(b, p0, p1), k2 = bisector_f(c, p0, p1);
  const double l0 = bisector_f(a, p0, p2), l1 = bisector_f(b, p0, p2), l2 = bisector_f(c, p0, p2);
  // Barycentric coordinates: [1 1 1; k; l] lambda = (1, 0, 0). Accurate to the last bits
  // when the two bisectors' traces on the plane are far from parallel (its determinant d
  // is not a small part of its terms: a CVT's iterates need those bits to converge).
  const double ca = k1 * l2 - k2 * l1, cb = k2 * l0 - k0 * l2, cc = k0 * l1 - k1 * l0;
  const double d = ca + cb + cc;
  const double terms = (std::fabs(k1 * l2) + std::fabs(k2 * l1)) +
                       (std::fabs(k2 * l0) + std::fabs(k0 * l2)) +
                       (std::fabs(k0 * l1) + std::fabs(k1 * l0));
  // Else (traces at a small angle: bisector(p0, p1) and bisector(p0, p2) meet at an angle of
  // |p1 - p2| / |p1 - p0|; for sites 3e-14 apart this solve put the point 1.3e-3 from the
  // exact one, a cell volume of -2.3e-4: tests/clip/fuzz_regressions/
  // clip3d_near_coincident_facet_point.xyz) the construction of predicates.h, accurate
  // however close the sites (its exact stage there).
  if (!(std::fabs(d) >= 0x1p-20 * terms) && plane_bisectors_point3d(a, b, c, p0, p1, p2, x)) {
    return;
  }
  double la = ca / d, lb = cb / d, lc = cc / d;
  if (!std::isfinite(la) || !std::isfinite(lb) || !std::isfinite(lc)) la = lb = lc = 1.0 / 3;
  for (int q = 0; q < 3; ++q) x[q] = la * a[q] + lb * b[q] + lc * c[q];
}

void Clip3Context::voronoi_point(const std::uint32_t* sites, double* x) const {
  // A Delaunay tet is never flat (the perturbation makes zero-volume tets impossible), but
  // it can be flat to the last bits: nearly cospherical sites, such as a CVT's mirror-
  // symmetric ones, whose floating-point determinant is rounding error or zero.
  // circumcenter3d falls back to exact arithmetic there, so the vertex is accurate, never
  // NaN.
  // With a far site, exactly to the point's own bits (circumcenter3d: of its offset from
  // sites[0], which for a site 1e20 away is nothing).
  if (far(sites[0]) || far(sites[1]) || far(sites[2]) || far(sites[3])) {
    circumcenter3d_absolute(site(sites[0]), site(sites[1]), site(sites[2]), site(sites[3]), x);
    return;
  }
  circumcenter3d(site(sites[0]), site(sites[1]), site(sites[2]), site(sites[3]), x);
}

const Star& Stars::pooled_star(const Clip3Context& ctx, std::uint32_t v) {
  if (nbr_offset_.size() != ctx.n || nbr_offset_[v] == kNone) {
    ctx.star(v, star_);
    return star_;
  }
  const std::uint32_t off = nbr_pool_[nbr_offset_[v] + 1];
  Star& st = star_;
  const std::uint32_t slots = ctx.dt.nb_tet_slots();
  st.reset_if_needed(slots);
  st.first = st.next;
  const std::uint32_t* tets = star_pool_.data() + off + 1;
  const std::uint32_t m = tets[-1];
  st.tets.assign(tets, tets + m);
  for (std::uint32_t q = 0; q < m; ++q) st.mark[tets[q]] = st.first + q;
  st.next = st.first + m;
  return star_;
}

NeighborList Stars::neighbors(const Clip3Context& ctx, std::uint32_t c) {
  const std::uint32_t n = ctx.n;
  if (nbr_offset_.size() != n) nbr_offset_.assign(n, kNone);
  std::uint32_t off = nbr_offset_[c];
  if (off == kNone) {
    if (site_mark_.size() != n || site_gen_ == 0xffffffffu) {
      site_mark_.assign(n, 0);
      site_gen_ = 0;
    }
    const std::uint32_t gen = ++site_gen_;
    ctx.star(c, star_);
    off = static_cast<std::uint32_t>(nbr_pool_.size());
    nbr_pool_.push_back(0);
    nbr_pool_.push_back(static_cast<std::uint32_t>(star_pool_.size()));
    nbr_geo_.push_back(NbrGeo{});
    nbr_geo_.push_back(NbrGeo{});
    star_pool_.push_back(static_cast<std::uint32_t>(star_.tets.size()));
    star_pool_.insert(star_pool_.end(), star_.tets.begin(), star_.tets.end());
    const double* pc = ctx.site(c);
    for (const std::uint32_t t : star_.tets) {
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t w = ctx.dt.tet_vertex(t, k);
        if (w == c || w == Delaunay3::kInfinite || site_mark_[w] == gen) continue;
        site_mark_[w] = gen;
        nbr_pool_.push_back(w);
        const double* pw = ctx.site(w);
        NbrGeo g;
        for (int q = 0; q < 3; ++q) g.e[q] = pw[q] - pc[q];
        g.ee = (g.e[0] * g.e[0] + g.e[1] * g.e[1]) + g.e[2] * g.e[2];
        g.reach = 2 * std::sqrt(g.ee) * (1 + 1e-14);
        g.ee_err = 2e-15 * g.ee;
        nbr_geo_.push_back(g);
      }
    }
    nbr_pool_[off] = static_cast<std::uint32_t>(nbr_pool_.size()) - off - 2;
    nbr_offset_[c] = off;
  }
  return {nbr_pool_.data() + off + 2, nbr_geo_.data() + off + 2, nbr_pool_[off]};
}

}  // namespace clip3

}  // namespace voroclip
