// Extraction of the tet mesh from the Delaunay triangulation of the final sites (Yan et
// al. 2011, sec. 5.2, "Final mesh extraction"): the tets whose circumcenter lies in the
// domain, decided exactly, then a local repair of a non-manifold boundary (mesh.h).
//
// Location: the domain's surface (Surface3::locate_circumcenter, exact ray parity), per
// finite Delaunay tet in parallel, tets in Morton order of their centroids so that
// consecutive queries read nearby parts of the surface.
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

TetExtractor3::TetExtractor3(const Domain3& domain) : domain_(&domain) {}

Sign TetExtractor3::circumcenter_side(const double* p0, const double* p1, const double* p2,
                                      const double* p3) const {
  return domain_->surface().locate_circumcenter(p0, p1, p2, p3);
}

Sign TetExtractor3::point_side(const double* p) const {
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(p[c])) throw Error("point_side: a coordinate is not finite");
  }
  return domain_->locate(p);
}

namespace {

// The local repair of extract3d.cpp's header, on kept flags per tet slot of dt.
class ManifoldRepair {
 public:
  ManifoldRepair(const Delaunay3& dt, std::vector<std::uint8_t>& kept, Extract3Stats& stats)
      : dt_(dt),
        kept_(kept),
        stats_(stats),
        frozen_(kept.size(), 0),
        in_star_(kept.size(), 0),
        star_position_(kept.size(), 0) {}

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
        const std::uint32_t changed = stats_.nb_added + stats_.nb_removed;
        collect_boundary();
        for (const auto& e : edges_) repair_edge(e, removal_only);
        collect_boundary();
        for (const std::uint32_t v : vertices_) repair_vertex(v, removal_only);
        if (stats_.nb_nonmanifold_edges + stats_.nb_nonmanifold_vertices == before) return;
        // A phase-1 pass that found defects but could change no tet (all of them frozen or
        // locked) leaves the same flags, so every further pass would too: on to phase 2 at
        // once (skull_low_resolution at 1,000 vertices: phase 1 ran its 16 passes in most of
        // its 103 extractions, 2.5 s of 12).
        if (stats_.nb_added + stats_.nb_removed == changed) break;
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

  // star_: the tets around v (finite and infinite), breadth-first; position_of(t) finds a
  // tet in it.
  void vertex_star(std::uint32_t v) {
    star_.clear();
    if (++star_stamp_ == 0) {
      std::fill(in_star_.begin(), in_star_.end(), 0);
      star_stamp_ = 1;
    }
    const std::uint32_t start = dt_.vertex_tet(v);
    if (start == Delaunay3::kNoTet) return;
    add_to_star(start);
    for (std::size_t i = 0; i < star_.size(); ++i) {
      const std::uint32_t t = star_[i];
      for (int f = 0; f < 4; ++f) {
        if (dt_.tet_vertex(t, f) == v) continue;
        const std::uint32_t n = dt_.tet_adjacent(t, f);
        if (in_star_[n] != star_stamp_) add_to_star(n);
      }
    }
    vertex_ = v;
  }
  void add_to_star(std::uint32_t t) {
    in_star_[t] = star_stamp_;
    star_position_[t] = static_cast<std::uint32_t>(star_.size());
    star_.push_back(t);
  }
  // The index of tet t in star_ (vertex_star's), or star_.size().
  std::size_t position_of(std::uint32_t t) const {
    return in_star_[t] == star_stamp_ ? star_position_[t] : star_.size();
  }

  // Components of kept and of non-kept tets of vertex_star's star:
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
          const std::size_t idx = position_of(nb);
          if (idx == n || comp_[idx] != kNone) continue;
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
  // Per tet slot: vertex_star's stamp when the tet is in star_, and its index there.
  std::vector<std::uint32_t> in_star_, star_position_;
  std::uint32_t star_stamp_ = 0;
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
  // Per slot: bit 0 kept, bit 1 on the boundary.
  std::vector<std::uint8_t> flags(ns, 0);
  // The finite tets in Morton order of their centroid's cell (of a 1024^3 grid over the
  // domain's bounding box): consecutive queries are near each other.
  const double* lo = domain_->bbox_lo();
  const double* hi = domain_->bbox_hi();
  const auto cell = [&](int a, double x) -> std::uint32_t {
    const double f = std::floor((x - lo[a]) / (hi[a] - lo[a]) * 1024);
    if (!(f > 0)) return 0;
    return f >= 1023 ? 1023u : static_cast<std::uint32_t>(f);
  };
  std::vector<std::uint64_t> order(ns);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, ns, 4096), [&](const auto& range) {
    for (std::uint32_t t = range.begin(); t != range.end(); ++t) {
      std::uint64_t key = 0xffffffffu;  // free and infinite slots last
      if (!dt.is_free(t) && !dt.is_infinite(t)) {
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 4; ++k) {
          for (int a = 0; a < 3; ++a) c[a] += 0.25 * dt.point(dt.tet_vertex(t, k))[a];
        }
        key = morton3(cell(0, c[0]), cell(1, c[1]), cell(2, c[2]));
      }
      order[t] = key << 32 | t;
    }
  });
  std::sort(order.begin(), order.end());
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, ns, 1024), [&](const auto& range) {
    for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
      const auto t = static_cast<std::uint32_t>(order[i] & 0xffffffffu);
      if (dt.is_free(t) || dt.is_infinite(t)) continue;
      const double* p[4];
      for (int k = 0; k < 4; ++k) p[k] = dt.point(dt.tet_vertex(t, k));
      const Sign s = circumcenter_side(p[0], p[1], p[2], p[3]);
      std::uint8_t f = 0;
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
