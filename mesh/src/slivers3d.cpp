// Sliver removal by vertex perturbation (Tournois, Srinivasan & Alliez, "Perturbing slivers
// in 3D Delaunay meshes", IMR 2009; Yan et al. 2011, sec. 5.2, ref. [36]).
//
// A sliver is a kept tet (TetExtractor3) whose smallest dihedral angle is below the target.
// Each round:
//   1. triangulate the sites, extract the mesh, measure every kept tet's smallest dihedral
//      angle (the criterion: Q1);
//   2. take the movable vertices of slivers, worst first (by the smallest Q1 of their kept
//      tets, then index), and process them in waves: each wave takes an independent set of
//      the vertices left (no two neighbours in the round's triangulation), chooses their
//      moves in parallel, then moves them; a vertex all of whose slivers had a vertex moved
//      in this round waits for the next round;
//   3. the move of a vertex v is chosen on a local triangulation: the Delaunay
//      triangulation of v and of its neighbours up to two rings (round's adjacency, current
//      positions). Its score is the smallest Q1 of the local tets incident to v, and of
//      those among v's first ring, that the extraction rule keeps (the exact location is
//      done for tets with a constrained vertex; tets of interior sites are kept). The
//      neighbours' triangulation is built once per vertex and each position inserted into it
//      (its cavity), which gives the same tets as building the whole one each time. Candidate
//      positions x: along the gradient of the squared circumradius of v's worst tet (moving
//      v there grows that tet's circumsphere until a neighbour enters it and the tet leaves
//      the triangulation: Tournois et al.'s main perturbation), against it, along the
//      gradient of its volume, and along pseudo-random directions; steps are fractions of
//      the mean length of v's edges. A vertex on the surface or on a feature line moves
//      within it (the candidate is projected by the caller's projector, as in the
//      constrained CVT). The best candidate is taken when it beats the current position's
//      score by kMinGain degrees.
// The rounds stop when there is no sliver, when a round moves nothing, when a round
// neither removes a sliver nor raises the smallest angle by min_progress_deg, or after
// max_rounds. The local triangulation only chooses moves: the mesh is always extracted
// from the global triangulation, exactly. The result does not depend on the thread count.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mesh3d_pipeline.h"
#include "mesh3d_tags.h"
#include "voroclip/mesh.h"

namespace voroclip {

namespace {

using Kind = SiteConstraint3::Kind;
constexpr double kMinGain = 0.01;               // degrees
constexpr std::size_t kMaxNeighbourhood = 256;  // sites (LocalScorer::set_vertex)

using mesh3::cross3;
using mesh3::dot3;
using mesh3::smallest_dihedral_deg;
using mesh3::sub3;

// The perturbation's criterion, Q1 (tet_shape's q1_deg, without the other measures: it is
// evaluated for every tet of every local triangulation).
double min_dihedral_deg(const double* p0, const double* p1, const double* p2, const double* p3) {
  // Face f is opposite vertex f; n[f] its normal pointing away from vertex f. The dihedral
  // angle at the edge shared by faces f and g is pi - angle(n[f], n[g]).
  const double* p[4] = {p0, p1, p2, p3};
  double n[4][3], len[4];
  for (int f = 0; f < 4; ++f) {
    const double* a = p[(f + 1) % 4];
    const double* b = p[(f + 2) % 4];
    const double* c = p[(f + 3) % 4];
    double u[3], v[3], w[3];
    sub3(b, a, u);
    sub3(c, a, v);
    cross3(u, v, n[f]);
    sub3(p[f], a, w);
    if (dot3(n[f], w) > 0) {
      for (double& x : n[f]) x = -x;
    }
    len[f] = std::sqrt(dot3(n[f], n[f]));
  }
  return smallest_dihedral_deg(n, len);
}

// The global triangulation's insertion in zones from kZonePoints points per zone (two zones
// from 7/16 of it: Delaunay3Options::points_per_zone), so that the perturbation's rebuilds
// at some thousands of sites share the cores. The tets are the same, their numbering (so the
// extracted tets' order) depends on it but never on the thread count. Bunny at 10,000
// vertices, 2 threads, the 21 rebuilds of its slivers phase: 0.59 s with the default
// (131072: no zone), 0.46 s with 2048 or 4096, 0.49 s with 1024 (session 27).
constexpr std::uint32_t kZonePoints = 2048;

Delaunay3Options zoned_options() {
  Delaunay3Options o;
  o.points_per_zone = kZonePoints;
  return o;
}

// What one round knows of the global mesh.
struct GlobalState {
  Delaunay3 dt{zoned_options()};
  std::vector<std::uint32_t> tets;       // kept, 4 per tet
  std::vector<double> q1;                // per kept tet
  std::vector<std::uint32_t> vtx_begin;  // per site + 1: its kept tets
  std::vector<std::uint32_t> vtx_tets;
  std::vector<double> vertex_q1;  // per site: smallest Q1 of its kept tets (180: none)
};

// A deterministic pseudo-random unit vector from (a, b, c).
void hashed_direction(std::uint64_t a, std::uint64_t b, std::uint64_t c, double* d) {
  std::uint64_t h = a * 0x9e3779b97f4a7c15ull ^
                    (b + 0x632be59bd9b4e019ull) * 0xbf58476d1ce4e5b9ull ^
                    (c + 0x8cb92ba72f3d8dd7ull) * 0x94d049bb133111ebull;
  for (;;) {
    double len2 = 0;
    for (int k = 0; k < 3; ++k) {
      h ^= h >> 31;
      h *= 0xbf58476d1ce4e5b9ull;
      h ^= h >> 29;
      d[k] = static_cast<double>(h >> 11) * 0x1p-52 - 1;
      len2 += d[k] * d[k];
    }
    if (len2 > 0.01 && len2 <= 1) {
      const double inv = 1 / std::sqrt(len2);
      for (int k = 0; k < 3; ++k) d[k] *= inv;
      return;
    }
  }
}

class LocalScorer {
 public:
  LocalScorer(const TetExtractor3& extractor) : extractor_(extractor) {}

  // Sets the neighbourhood of v: its first ring (ring1) and second ring in g's
  // triangulation, at the sites' current positions. constrained(w): w is not free. A second
  // ring of more than kMaxNeighbourhood sites is cut down to the sites within twice the
  // longest edge of v's kept tets: a boundary site sees across the outside, and where the
  // surface sites of a near-planar patch are lifted slightly off its triangles (the smooth
  // surface on a planar face that is not exactly planar in the input) it sees most of the
  // patch, hundreds of sites far from the kept tets near v, the ones scored, and each local
  // triangulation costs that much more. Smaller neighbourhoods are left whole: cut, their
  // convex hull brings flat tets whose circumcenters are far and imprecise, which are
  // expensive to locate.
  template <class Constrained>
  void set_vertex(const GlobalState& g, const std::vector<double>& sites, std::uint32_t v,
                  Constrained constrained) {
    g.dt.vertex_neighbors(v, ring1_);
    const auto second_ring = [&](auto keep) {
      others_ = ring1_;
      for (const std::uint32_t w : ring1_) {
        g.dt.vertex_neighbors(w, scratch_);
        for (const std::uint32_t y : scratch_) {
          if (y != v && keep(y)) others_.push_back(y);
        }
      }
    };
    second_ring([](std::uint32_t) { return true; });
    if (others_.size() > kMaxNeighbourhood) {
      const double* x = &sites[3 * std::size_t{v}];
      const auto dist2 = [&](std::uint32_t w) {
        double d[3];
        sub3(&sites[3 * std::size_t{w}], x, d);
        return dot3(d, d);
      };
      double reach2 = 0;
      for (std::uint32_t e = g.vtx_begin[v]; e < g.vtx_begin[v + 1]; ++e) {
        const std::uint32_t* t = &g.tets[4 * std::size_t{g.vtx_tets[e]}];
        for (int k = 0; k < 4; ++k) reach2 = std::max(reach2, dist2(t[k]));
      }
      if (reach2 > 0) {
        const auto near = [&](std::uint32_t w) { return dist2(w) <= 4 * reach2; };
        ring1_.erase(
            std::remove_if(ring1_.begin(), ring1_.end(), [&](std::uint32_t w) { return !near(w); }),
            ring1_.end());
        second_ring(near);
      }
    }
    std::sort(others_.begin(), others_.end());
    others_.erase(std::unique(others_.begin(), others_.end()), others_.end());
    // Local point 0 is the moving vertex, then the others in order.
    pts_.assign(3, 0.0);
    in_ring1_.assign(1, 1);
    constrained_.assign(1, constrained(v) ? 1 : 0);
    for (const std::uint32_t w : others_) {
      pts_.insert(pts_.end(), &sites[3 * std::size_t{w}], &sites[3 * std::size_t{w}] + 3);
      in_ring1_.push_back(std::binary_search(ring1_.begin(), ring1_.end(), w) ? 1 : 0);
      constrained_.push_back(constrained(w) ? 1 : 0);
    }
    prepare_base();
  }

  // The smallest Q1 over the kept local tets at v's position x (180 when none). With
  // `worst`, the other three vertices of the worst kept tet incident to v go there (9
  // values; false returned in `found` when v has no kept tet). The local triangulation is
  // that of the others (base_, made once per vertex by set_vertex) with x inserted: its tets
  // without x are the base's outside x's Bowyer-Watson cavity, those with x join x to the
  // cavity's boundary facets. The base takes the others' local indices less one, which keeps
  // their order, and x is the first point, so the perturbation that decides degenerate cases
  // (Delaunay3: the indices as infinitesimal weights) is that of a triangulation of all the
  // points, which is unique: the same tets as building it (score_whole), at the cost of a
  // cavity instead of a triangulation per position (up to 28 per vertex and round).
  double score(const double* x, double* worst = nullptr, bool* found = nullptr) {
    if (!base_ok_ || !std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) {
      return score_whole(x, worst, found);
    }
    std::copy_n(x, 3, pts_.begin());
    const std::uint32_t start = base_.locate(x, hint_);
    hint_ = start;
    if (!base_.is_infinite(start)) {
      for (int k = 0; k < 4; ++k) {
        const double* p = base_.point(base_.tet_vertex(start, k));
        // x on another site: the triangulation of all the points drops that one (a duplicate
        // of x, whose index is smaller).
        if (p[0] == x[0] && p[1] == x[1] && p[2] == x[2]) return score_whole(x, worst, found);
      }
    }
    // The cavity: breadth-first from the tet that holds x (in conflict: x is inside its
    // closed interior, or strictly beyond its hull facet).
    if (++epoch_ == 0) {
      std::fill(in_cavity_.begin(), in_cavity_.end(), 0);
      std::fill(outside_.begin(), outside_.end(), 0);
      epoch_ = 1;
    }
    cavity_.assign(1, start);
    in_cavity_[start] = epoch_;
    facets_.clear();
    for (std::size_t i = 0; i < cavity_.size(); ++i) {
      const std::uint32_t t = cavity_[i];
      for (int f = 0; f < 4; ++f) {
        const std::uint32_t u = base_.tet_adjacent(t, f);
        if (in_cavity_[u] == epoch_) continue;
        if (outside_[u] != epoch_) {
          if (in_conflict(u, x)) {
            in_cavity_[u] = epoch_;
            cavity_.push_back(u);
            continue;
          }
          outside_[u] = epoch_;
        }
        facets_.push_back(4 * t + static_cast<std::uint32_t>(f));
      }
    }
    Lowest lowest;
    // The tets with x: x and a finite boundary facet of the cavity.
    for (const std::uint32_t code : facets_) {
      std::array<std::uint32_t, 4> w{};
      bool finite = true;
      for (int j = 0; j < 3; ++j) {
        const std::uint32_t b = base_.tet_vertex(code / 4, Delaunay3::kFacetVertex[code % 4][j]);
        finite = finite && b != Delaunay3::kInfinite;
        w[j + 1] = b + 1;
      }
      if (!finite) continue;
      sort4(w);
      offer(lowest, w, worst != nullptr);
    }
    // The tets of the first ring without x: the base's, by increasing Q1, the first one
    // kept and outside the cavity.
    for (const RingTet& r : ring_tets_) {
      if (r.q >= lowest.q) break;
      if (in_cavity_[r.slot] == epoch_) continue;
      std::int8_t& k = ring_kept_[r.slot];
      if (k < 0) k = kept(base_tet(r.slot)) ? 1 : 0;
      if (k == 1) {
        lowest.q = r.q;
        break;
      }
    }
    return report(lowest, worst, found);
  }

  // score from the local triangulation of x and the others built whole: where the base
  // cannot be made (fewer than 4 others, all in a plane, two at one place) or x is not finite
  // or on another site, and for check_local_scores.
  double score_whole(const double* x, double* worst, bool* found) {
    std::copy_n(x, 3, pts_.begin());
    const auto n = static_cast<std::uint32_t>(pts_.size() / 3);
    if (found) *found = false;
    if (n < 4) return 180;
    try {
      local_.build(pts_.data(), n);
    } catch (const Error&) {
      return 0;  // degenerate local set: never preferred
    }
    Lowest lowest;
    for (std::uint32_t t = 0; t < local_.nb_tet_slots(); ++t) {
      if (local_.is_free(t) || local_.is_infinite(t)) continue;
      std::array<std::uint32_t, 4> w;
      bool all_ring = true;
      for (int k = 0; k < 4; ++k) {
        w[k] = local_.tet_vertex(t, k);
        all_ring = all_ring && in_ring1_[w[k]] != 0;
      }
      sort4(w);
      const bool has0 = w[0] == 0;
      if (!has0 && !all_ring) continue;
      offer(lowest, w, worst != nullptr && has0);
    }
    return report(lowest, worst, found);
  }

 private:
  // score's running result: the smallest Q1 of the kept tets offered, and the worst kept tet
  // with x, ties broken by its other three vertices (local indices, ascending).
  struct Lowest {
    double q = 180, incident_q = 181;
    std::array<std::uint32_t, 3> incident{};
    bool any_incident = false;
  };
  // Offers tet w (local indices, ascending), as one with x when with_x.
  void offer(Lowest& l, const std::array<std::uint32_t, 4>& w, bool with_x) const {
    const double q = measure(w);
    const std::array<std::uint32_t, 3> others{w[1], w[2], w[3]};
    const bool incident =
        with_x && (q < l.incident_q || (q == l.incident_q && others < l.incident));
    if (q >= l.q && !incident) return;
    if (!kept(w)) return;
    l.q = std::min(l.q, q);
    if (incident) {
      l.incident_q = q;
      l.incident = others;
      l.any_incident = true;
    }
  }
  double report(const Lowest& l, double* worst, bool* found) const {
    if (found) *found = l.any_incident;
    if (l.any_incident) {
      for (int j = 0; j < 3; ++j) std::copy_n(local_point(l.incident[j]), 3, worst + 3 * j);
    }
    return l.q;
  }

  // A tet of local indices in ascending order (the order every measure below takes, so that
  // a tet's measures do not depend on how a triangulation lists it).
  static void sort4(std::array<std::uint32_t, 4>& w) {
    const auto order = [&](int i, int j) {
      if (w[j] < w[i]) std::swap(w[i], w[j]);
    };
    order(0, 1);
    order(2, 3);
    order(0, 2);
    order(1, 3);
    order(1, 2);
  }
  const double* local_point(std::uint32_t i) const { return &pts_[3 * std::size_t{i}]; }
  double measure(const std::array<std::uint32_t, 4>& w) const {
    return min_dihedral_deg(local_point(w[0]), local_point(w[1]), local_point(w[2]),
                            local_point(w[3]));
  }
  // Whether the extraction keeps the tet: tets among interior sites only have their
  // circumcenter inside (near them): the exact location is for tets at the boundary.
  bool kept(const std::array<std::uint32_t, 4>& w) const {
    const bool constrained = constrained_[w[0]] != 0 || constrained_[w[1]] != 0 ||
                             constrained_[w[2]] != 0 || constrained_[w[3]] != 0;
    return !constrained ||
           extractor_.circumcenter_side(local_point(w[0]), local_point(w[1]), local_point(w[2]),
                                        local_point(w[3])) != Sign::negative;
  }

  // The base: the Delaunay triangulation of the others, and its tets among the first ring
  // by increasing Q1.
  void prepare_base() {
    base_ok_ = false;
    hint_ = Delaunay3::kNoTet;
    const auto m = static_cast<std::uint32_t>(pts_.size() / 3) - 1;
    if (m < 4) return;
    try {
      base_.build(pts_.data() + 3, m);
    } catch (const Error&) {
      return;
    }
    if (base_.nb_unique_points() != m) return;
    const std::uint32_t slots = base_.nb_tet_slots();
    in_cavity_.assign(slots, 0);
    outside_.assign(slots, 0);
    epoch_ = 0;
    ring_kept_.assign(slots, -1);
    ring_tets_.clear();
    for (std::uint32_t t = 0; t < slots; ++t) {
      if (base_.is_infinite(t)) continue;
      const std::array<std::uint32_t, 4> w = base_tet(t);
      if (in_ring1_[w[0]] != 0 && in_ring1_[w[1]] != 0 && in_ring1_[w[2]] != 0 &&
          in_ring1_[w[3]] != 0) {
        ring_tets_.push_back({measure(w), t});
      }
    }
    std::sort(ring_tets_.begin(), ring_tets_.end(), [](const RingTet& a, const RingTet& b) {
      return a.q < b.q || (a.q == b.q && a.slot < b.slot);
    });
    base_ok_ = true;
  }
  // Finite tet t of the base in local indices, ascending.
  std::array<std::uint32_t, 4> base_tet(std::uint32_t t) const {
    std::array<std::uint32_t, 4> w{};
    for (int k = 0; k < 4; ++k) w[k] = base_.tet_vertex(t, k) + 1;
    sort4(w);
    return w;
  }
  // Delaunay3's conflict rule (delaunay.h), x with local index 0.
  bool in_conflict(std::uint32_t t, const double* x) const {
    const std::uint32_t v0 = base_.tet_vertex(t, 0), v1 = base_.tet_vertex(t, 1),
                        v2 = base_.tet_vertex(t, 2), v3 = base_.tet_vertex(t, 3);
    if (v3 != Delaunay3::kInfinite) {
      const double *a = base_.point(v0), *b = base_.point(v1), *c = base_.point(v2),
                   *d = base_.point(v3);
      Sign r = insphere(a, b, c, d, x);
      if (r == Sign::zero) r = insphere_sos(a, b, c, d, x, v0 + 1, v1 + 1, v2 + 1, v3 + 1, 0);
      return r == Sign::positive;
    }
    const double *a = base_.point(v2), *b = base_.point(v1), *c = base_.point(v0);
    const Sign o = orient3d(a, b, c, x);
    if (o != Sign::zero) return o == Sign::negative;
    const std::uint32_t u = base_.tet_adjacent(t, 3);
    const std::uint32_t d = base_.tet_vertex(u, base_.tet_adjacent_facet(t, 3));
    return insphere_sos(a, b, c, base_.point(d), x, v2 + 1, v1 + 1, v0 + 1, d + 1, 0) ==
           Sign::positive;
  }

 public:
  bool has_base() const { return base_ok_; }

  // The mean distance from v's position x to its first ring.
  double mean_edge(const double* x) const {
    double sum = 0;
    std::uint32_t count = 0;
    for (std::size_t i = 1; i < in_ring1_.size(); ++i) {
      if (in_ring1_[i] == 0) continue;
      double d[3];
      sub3(&pts_[3 * i], x, d);
      sum += std::sqrt(dot3(d, d));
      ++count;
    }
    return count > 0 ? sum / count : 0;
  }

 private:
  const TetExtractor3& extractor_;
  std::vector<std::uint32_t> ring1_, others_, scratch_;
  std::vector<double> pts_;
  std::vector<std::uint8_t> in_ring1_, constrained_;
  Delaunay3 local_;
  // The base (prepare_base) and the cavity's scratch.
  struct RingTet {
    double q;
    std::uint32_t slot;
  };
  Delaunay3 base_;
  bool base_ok_ = false;
  std::uint32_t hint_ = Delaunay3::kNoTet;
  std::vector<RingTet> ring_tets_;
  std::vector<std::int8_t> ring_kept_;              // per base slot: -1 not known yet, 0, 1
  std::vector<std::uint32_t> in_cavity_, outside_;  // per base slot: the epoch when marked
  std::uint32_t epoch_ = 0;
  std::vector<std::uint32_t> cavity_, facets_;
};

void build_state(GlobalState& g, const TetExtractor3& extractor, const std::vector<double>& sites,
                 const Extract3Options& options, Extract3Stats* extraction) {
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  g.dt.build(sites.data(), n);
  g.tets = extractor.extract(g.dt, options, extraction);
  const std::size_t nt = g.tets.size() / 4;
  g.q1.resize(nt);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nt, 1024), [&](const auto& range) {
    for (std::size_t t = range.begin(); t != range.end(); ++t) {
      const std::uint32_t* v = &g.tets[4 * t];
      g.q1[t] = min_dihedral_deg(&sites[3 * std::size_t{v[0]}], &sites[3 * std::size_t{v[1]}],
                                 &sites[3 * std::size_t{v[2]}], &sites[3 * std::size_t{v[3]}]);
    }
  });
  g.vtx_begin.assign(n + 1, 0);
  for (const std::uint32_t v : g.tets) ++g.vtx_begin[v + 1];
  for (std::uint32_t v = 0; v < n; ++v) g.vtx_begin[v + 1] += g.vtx_begin[v];
  g.vtx_tets.resize(g.tets.size());
  std::vector<std::uint32_t> fill(g.vtx_begin.begin(), g.vtx_begin.end() - 1);
  g.vertex_q1.assign(n, 180);
  for (std::size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t v = g.tets[4 * t + static_cast<std::size_t>(k)];
      g.vtx_tets[fill[v]++] = static_cast<std::uint32_t>(t);
      g.vertex_q1[v] = std::min(g.vertex_q1[v], g.q1[t]);
    }
  }
}

}  // namespace

Perturb3Stats perturb_slivers3(const TetExtractor3& extractor, std::vector<double>& sites,
                               const std::vector<SiteConstraint3::Kind>& kinds,
                               const SiteProjector3& project, const Perturb3Options& options,
                               std::vector<std::uint32_t>* mesh, Extract3Stats* extraction) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  if (sites.size() % 3 != 0)
    throw Error("perturb_slivers3: the site array's length is not a multiple of 3");
  if (!kinds.empty() && kinds.size() != n) {
    throw Error("perturb_slivers3: " + std::to_string(kinds.size()) + " constraints for " +
                std::to_string(n) + " sites");
  }
  const auto kind = [&](std::uint32_t v) { return kinds.empty() ? Kind::kFree : kinds[v]; };
  for (std::uint32_t v = 0; v < n; ++v) {
    if ((kind(v) == Kind::kSurface || kind(v) == Kind::kCurve) && !project) {
      throw Error("perturb_slivers3: site " + std::to_string(v) +
                  " is constrained to a surface or curve, but no projection is given");
    }
  }
  // Chooses a new position for v (into out) from the local triangulation of its
  // neighbourhood at the current positions; false when none is better.
  const auto try_move = [&](const GlobalState& gs, const std::vector<double>& pos, std::uint32_t v,
                            std::uint32_t round, LocalScorer& scorer, double* out) {
    const double* x0 = &pos[3 * std::size_t{v}];
    scorer.set_vertex(gs, pos, v, [&](std::uint32_t w) { return kind(w) != Kind::kFree; });
    double q[9];
    bool found = false;
    const double base = scorer.score(x0, q, &found);
    if (base >= options.target_dihedral_deg || !found) return false;
    const double length = scorer.mean_edge(x0);
    if (!(length > 0)) return false;
    // Directions: the gradient of the worst tet's squared circumradius with respect to v,
    // d R^2 / d v = 2 ((c - q0) . m / ((q0 - v) . m)) (c - v), c its circumcenter and m
    // the normal of the face (q0, q1, q2) opposite v; its opposite; the gradient of its
    // volume (m, away from the face); then pseudo-random ones.
    double dirs[8][3];
    int nd = 0;
    {
      double a[3], b[3], e[3], bc[3], ca[3], ab[3], m[3], u1[3], u2[3];
      sub3(q, x0, a);
      sub3(q + 3, x0, b);
      sub3(q + 6, x0, e);
      cross3(b, e, bc);
      cross3(e, a, ca);
      cross3(a, b, ab);
      const double det = 2 * dot3(a, bc);
      const double la = dot3(a, a), lb = dot3(b, b), lc = dot3(e, e);
      double rel[3];  // c - v
      for (int k = 0; k < 3; ++k) rel[k] = (la * bc[k] + lb * ca[k] + lc * ab[k]) / det;
      sub3(q + 3, q, u1);
      sub3(q + 6, q, u2);
      cross3(u1, u2, m);
      double cq[3];  // c - q0 = rel - a
      for (int k = 0; k < 3; ++k) cq[k] = rel[k] - a[k];
      const double factor = dot3(cq, m) / dot3(a, m);
      double gr[3];
      for (int k = 0; k < 3; ++k) gr[k] = factor * rel[k];
      const double len = std::sqrt(dot3(gr, gr));
      if (len > 0 && std::isfinite(len)) {
        for (int k = 0; k < 3; ++k) {
          dirs[nd][k] = gr[k] / len;
          dirs[nd + 1][k] = -gr[k] / len;
        }
        nd += 2;
      }
      const double lm = std::sqrt(dot3(m, m));
      if (lm > 0) {
        // a = q0 - v: v is on the side of the face opposite to a's direction along m.
        const double sgn = dot3(a, m) > 0 ? -1 / lm : 1 / lm;
        for (int k = 0; k < 3; ++k) dirs[nd][k] = sgn * m[k];
        ++nd;
      }
    }
    while (nd < 8) {
      hashed_direction(options.seed, v, round * 8u + static_cast<std::uint32_t>(nd), dirs[nd]);
      ++nd;
    }
    double best = base + kMinGain;
    bool improved = false;
    static constexpr double kSteps[4] = {0.05, 0.1, 0.2, 0.35};
    for (int d = 0; d < nd && best < options.target_dihedral_deg; ++d) {
      for (const double step : kSteps) {
        if (d >= 3 && step < 0.1) continue;  // random directions: the larger steps only
        double x[3];
        for (int k = 0; k < 3; ++k) x[k] = x0[k] + step * length * dirs[d][k];
        const Kind kd = kind(v);
        if (kd == Kind::kSurface || kd == Kind::kCurve) {
          double pq[3], dir[3];
          project(v, kd, x, pq, dir);
          std::copy_n(pq, 3, x);
        }
        const double sc = scorer.score(x);
        if (sc > best) {
          best = sc;
          std::copy_n(x, 3, out);
          improved = true;
        }
      }
    }
    return improved;
  };
  Perturb3Stats stats;
  GlobalState g;
  std::vector<std::uint8_t> blocked(n), moved_now(n);
  std::vector<std::uint32_t> candidates, chosen, left, neighbors;
  std::vector<double> moved_to;
  std::vector<std::uint8_t> moved;
  std::vector<double> before;  // the sites before the last round's moves (keep_round)
  // keep_round: the rounds run unchecked, each round's moves and statistics kept. When the
  // final mesh is refused, the first refused round is found from them, and the rounds go on
  // from it, each checked: as if they had run checked from the start, without a second run
  // from the start (skull_low_resolution at 10,000 vertices: 13.24 s, now 11.64) and without a
  // check per round when the final mesh is kept (3.5 % of bunny's time at 10,000; session 30).
  // The mesh is also checked after rounds 1, 4, 16, ...: a refusal there ends the unchecked
  // rounds, and the rounds go on checked from the first refused one (elk at 10,000: round 1
  // refused, and 17 more rounds were run for nothing, all undone; session 36), unless the
  // starting mesh is refused too: that is left to the moves, which may repair it.
  const bool record = static_cast<bool>(options.keep_round);
  std::vector<double> first_sites;
  if (record) first_sites = sites;
  std::vector<std::pair<std::uint32_t, std::array<double, 3>>> round_moves;
  std::vector<std::size_t> moves_begin;    // per round, into round_moves, and its end
  std::vector<Perturb3Stats> round_stats;  // at the start of each round
  bool checking = false;
  bool early_checks = true;               // the unchecked rounds' meshes checked after rounds 4^k
  bool refused_early = false;             // one of them was refused
  std::vector<std::uint32_t> first_tets;  // the starting mesh (checked after such a refusal)
  for (std::uint32_t first_round = 0;;) {
    for (std::uint32_t round = first_round;; ++round) {
      build_state(g, extractor, sites, options.extraction, extraction);
      if (record && !checking) {
        round_stats.push_back(stats);
        if (round == 0) {
          first_tets = g.tets;
        } else if (early_checks && (round & (round - 1)) == 0 && (round & 0x55555555u) != 0 &&
                   !options.keep_round(sites, g.tets)) {
          // Refused after round 1, 4, 16, ...: the end of the unchecked rounds, unless the
          // start was refused too (the moves may yet repair it).
          early_checks = options.keep_round(first_sites, first_tets);
          if (early_checks) {
            refused_early = true;
            break;
          }
        }
      }
      bool just_undone = false;
      if (round > 0 && checking && !options.keep_round(sites, g.tets)) {
        // Undone; the rounds go on with the surface, feature and corner vertices fixed (their
        // moves are the ones that can change the boundary), and stop at the next refusal.
        sites.swap(before);
        build_state(g, extractor, sites, options.extraction, extraction);
        if (stats.undone) break;
        stats.undone = just_undone = true;
      }
      const std::size_t nt = g.q1.size();
      std::uint32_t nb_slivers = 0;
      double worst = 180;
      for (std::size_t t = 0; t < nt; ++t) {
        nb_slivers += g.q1[t] < options.target_dihedral_deg ? 1 : 0;
        worst = std::min(worst, g.q1[t]);
      }
      const bool stalled = round > 0 && !just_undone && nb_slivers >= stats.final_slivers &&
                           worst < stats.final_min_dihedral_deg + options.min_progress_deg;
      if (round == 0) {
        stats.initial_slivers = nb_slivers;
        stats.initial_min_dihedral_deg = worst;
      }
      stats.final_slivers = nb_slivers;
      stats.final_min_dihedral_deg = worst;
      if (nb_slivers == 0 || round == options.max_rounds || stalled) break;
      if (options.progress && !options.progress(round, nb_slivers, worst)) {
        stats.cancelled = true;
        break;
      }
      ++stats.rounds;
      if (checking) before = sites;
      if (record && !checking) moves_begin.push_back(round_moves.size());

      // Movable vertices of slivers, worst first, processed in waves: each wave takes an
      // independent set of the vertices left (no two neighbours in this round's
      // triangulation), moves them in parallel, then the next wave sees the new positions.
      candidates.clear();
      for (std::uint32_t v = 0; v < n; ++v) {
        if (g.vertex_q1[v] < options.target_dihedral_deg && kind(v) != Kind::kFixed &&
            (!stats.undone || kind(v) == Kind::kFree)) {
          candidates.push_back(v);
        }
      }
      std::sort(candidates.begin(), candidates.end(), [&](std::uint32_t a, std::uint32_t b) {
        return g.vertex_q1[a] != g.vertex_q1[b] ? g.vertex_q1[a] < g.vertex_q1[b] : a < b;
      });
      std::uint32_t nb_moved = 0;
      // A sliver with a vertex moved in this round has changed: its other vertices wait for
      // the next round's triangulation unless another of their slivers is untouched.
      const auto untouched_sliver = [&](std::uint32_t v) {
        for (std::uint32_t e = g.vtx_begin[v]; e < g.vtx_begin[v + 1]; ++e) {
          const std::uint32_t t = g.vtx_tets[e];
          if (!(g.q1[t] < options.target_dihedral_deg)) continue;
          bool touched = false;
          for (int k = 0; k < 4; ++k) {
            touched =
                touched || moved_now[g.tets[4 * std::size_t{t} + static_cast<std::size_t>(k)]] != 0;
          }
          if (!touched) return true;
        }
        return false;
      };
      std::fill(moved_now.begin(), moved_now.end(), 0);
      while (!candidates.empty()) {
        chosen.clear();
        left.clear();
        for (const std::uint32_t v : candidates) {
          if (!untouched_sliver(v)) continue;
          if (blocked[v] != 0) {
            left.push_back(v);
            continue;
          }
          chosen.push_back(v);
          blocked[v] = 1;
          g.dt.vertex_neighbors(v, neighbors);
          for (const std::uint32_t w : neighbors) blocked[w] = 1;
        }
        for (const std::uint32_t v : chosen) {
          blocked[v] = 0;
          g.dt.vertex_neighbors(v, neighbors);
          for (const std::uint32_t w : neighbors) blocked[w] = 0;
        }
        candidates.swap(left);
        moved_to.assign(3 * chosen.size(), 0);
        moved.assign(chosen.size(), 0);
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, chosen.size(), 2), [&](const auto& range) {
              LocalScorer scorer(extractor);
              for (std::size_t c = range.begin(); c != range.end(); ++c) {
                moved[c] = try_move(g, sites, chosen[c], round, scorer, &moved_to[3 * c]) ? 1 : 0;
              }
            });
        for (std::size_t c = 0; c < chosen.size(); ++c) {
          if (moved[c] == 0) continue;
          std::copy_n(&moved_to[3 * c], 3, &sites[3 * std::size_t{chosen[c]}]);
          if (record && !checking) {
            round_moves.emplace_back(
                chosen[c],
                std::array<double, 3>{moved_to[3 * c], moved_to[3 * c + 1], moved_to[3 * c + 2]});
          }
          moved_now[chosen[c]] = 1;
          ++nb_moved;
        }
      }
      stats.moves += nb_moved;
      if (nb_moved == 0) break;
    }
    // The final sites are the last ones kept (every exit follows a triangulation of them).
    if (!refused_early && (!options.keep_round || checking || stats.cancelled || stats.moves == 0 ||
                           options.keep_round(sites, g.tets))) {
      break;
    }
    // The sites at the start of each round from the first one's and the moves, checked in
    // order; the last ones are the final sites, refused.
    moves_begin.push_back(round_moves.size());
    std::vector<double> previous;
    std::size_t refused = 0;
    for (;;) {
      previous = first_sites;
      for (std::size_t m = moves_begin[refused]; m < moves_begin[refused + 1]; ++m) {
        std::copy_n(round_moves[m].second.data(), 3,
                    &first_sites[3 * std::size_t{round_moves[m].first}]);
      }
      ++refused;
      if (refused + 1 == round_stats.size()) break;
      build_state(g, extractor, first_sites, options.extraction, extraction);
      if (!options.keep_round(first_sites, g.tets)) break;
    }
    sites = std::move(first_sites);
    before = std::move(previous);
    stats = round_stats[refused];
    first_round = static_cast<std::uint32_t>(refused);
    checking = true;
    refused_early = false;
  }
  // Every exit follows a triangulation of the final sites (no move since): g holds the
  // final mesh.
  if (mesh) *mesh = std::move(g.tets);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace voroclip

namespace voroclip::mesh3 {

std::vector<SliverCenter> sliver_centers(const std::vector<double>& sites,
                                         const std::vector<std::uint32_t>& tets, double below_deg,
                                         double* lowest) {
  std::vector<std::pair<double, std::uint32_t>> bad;
  *lowest = 180;
  for (std::size_t t = 0; t < tets.size() / 4; ++t) {
    const std::uint32_t* v = &tets[4 * t];
    const double q1 =
        min_dihedral_deg(&sites[3 * std::size_t{v[0]}], &sites[3 * std::size_t{v[1]}],
                         &sites[3 * std::size_t{v[2]}], &sites[3 * std::size_t{v[3]}]);
    *lowest = std::min(*lowest, q1);
    if (q1 < below_deg) bad.emplace_back(q1, static_cast<std::uint32_t>(t));
  }
  std::sort(bad.begin(), bad.end());
  std::vector<SliverCenter> taken;
  for (const auto& [q1, t] : bad) {
    const std::uint32_t* v = &tets[4 * std::size_t{t}];
    const double* p[4];
    for (int k = 0; k < 4; ++k) p[k] = &sites[3 * std::size_t{v[k]}];
    if (orient3d(p[0], p[1], p[2], p[3]) == Sign::zero) continue;
    SliverCenter s;
    s.q1_deg = q1;
    circumcenter3d(p[0], p[1], p[2], p[3], s.center.data());
    double rel[3];
    sub3(s.center.data(), p[0], rel);
    s.radius = std::sqrt(dot3(rel, rel));
    double longest2 = 0;
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        double d[3];
        sub3(p[i], p[j], d);
        longest2 = std::max(longest2, dot3(d, d));
      }
    }
    if (!(s.radius * s.radius <= longest2)) continue;
    const bool near = std::any_of(taken.begin(), taken.end(), [&](const SliverCenter& o) {
      double d[3];
      sub3(o.center.data(), s.center.data(), d);
      return dot3(d, d) < s.radius * s.radius / 4;
    });
    if (!near) taken.push_back(s);
  }
  return taken;
}

std::uint32_t peel_flat_boundary_tets(
    const std::vector<double>& sites, const std::vector<Kind>& kinds,
    std::vector<std::uint32_t>& tets, double max_q1_deg, std::uint32_t passes,
    const std::function<bool(const std::vector<std::uint32_t>&)>& keep) {
  std::uint32_t removed = 0;
  std::vector<std::uint32_t> triangles, face_tet, next;
  std::vector<std::uint8_t> boundary_faces, taken;
  std::vector<std::pair<double, std::uint32_t>> flat;
  for (std::uint32_t pass = 0; pass < passes; ++pass) {
    const std::size_t nt = tets.size() / 4;
    boundary_triangles(tets, triangles, face_tet);
    boundary_faces.assign(nt, 0);
    for (const std::uint32_t t : face_tet) ++boundary_faces[t];
    flat.clear();
    for (std::size_t t = 0; t < nt; ++t) {
      const std::uint32_t* v = &tets[4 * t];
      if (boundary_faces[t] < 2 || kinds[v[0]] == Kind::kFree || kinds[v[1]] == Kind::kFree ||
          kinds[v[2]] == Kind::kFree || kinds[v[3]] == Kind::kFree) {
        continue;
      }
      const double q1 =
          min_dihedral_deg(&sites[3 * std::size_t{v[0]}], &sites[3 * std::size_t{v[1]}],
                           &sites[3 * std::size_t{v[2]}], &sites[3 * std::size_t{v[3]}]);
      if (q1 < max_q1_deg) flat.emplace_back(q1, static_cast<std::uint32_t>(t));
    }
    if (flat.empty()) break;
    std::sort(flat.begin(), flat.end());
    // Worst first; a tet goes only when none of its vertices lost a tet in this pass, so
    // that each removal sees the boundary it was chosen on.
    taken.assign(sites.size() / 3, 0);
    std::vector<std::uint8_t> drop(nt, 0);
    std::uint32_t dropped = 0;
    for (const auto& [q1, t] : flat) {
      const std::uint32_t* v = &tets[4 * std::size_t{t}];
      if (taken[v[0]] != 0 || taken[v[1]] != 0 || taken[v[2]] != 0 || taken[v[3]] != 0) continue;
      for (int k = 0; k < 4; ++k) taken[v[k]] = 1;
      drop[t] = 1;
      ++dropped;
    }
    next.clear();
    for (std::size_t t = 0; t < nt; ++t) {
      if (drop[t] == 0) next.insert(next.end(), &tets[4 * t], &tets[4 * t] + 4);
    }
    if (next.empty() || (keep && !keep(next))) break;
    tets.swap(next);
    removed += dropped;
  }
  return removed;
}

LocalScoreCheck check_local_scores(const TetExtractor3& extractor, const std::vector<double>& sites,
                                   const std::vector<SiteConstraint3::Kind>& kinds,
                                   const std::vector<double>& positions_per_vertex) {
  GlobalState g;
  build_state(g, extractor, sites, Extract3Options{}, nullptr);
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  const std::size_t per = positions_per_vertex.size() / 3;
  LocalScoreCheck check;
  LocalScorer scorer(extractor);
  std::vector<std::uint32_t> ring;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (g.vtx_begin[v] == g.vtx_begin[v + 1]) continue;
    scorer.set_vertex(g, sites, v, [&](std::uint32_t w) {
      return !kinds.empty() && kinds[w] != SiteConstraint3::Kind::kFree;
    });
    if (scorer.has_base()) ++check.vertices_with_base;
    // The positions: v's own, each neighbour's (a duplicate), the midpoints of v and its
    // neighbours, and v's plus each of the given offsets.
    std::vector<double> at(sites.begin() + 3 * std::ptrdiff_t{v},
                           sites.begin() + 3 * std::ptrdiff_t{v} + 3);
    g.dt.vertex_neighbors(v, ring);
    for (const std::uint32_t w : ring) {
      for (int k = 0; k < 3; ++k) at.push_back(sites[3 * std::size_t{w} + k]);
      for (int k = 0; k < 3; ++k) {
        at.push_back(0.5 * (sites[3 * std::size_t{v} + k] + sites[3 * std::size_t{w} + k]));
      }
    }
    for (std::size_t i = 0; i < per; ++i) {
      for (int k = 0; k < 3; ++k) {
        at.push_back(sites[3 * std::size_t{v} + k] + positions_per_vertex[3 * i + k]);
      }
    }
    for (std::size_t i = 0; i < at.size(); i += 3) {
      double w1[9] = {}, w2[9] = {};
      bool f1 = false, f2 = false;
      const double s1 = scorer.score(&at[i], w1, &f1);
      const double s2 = scorer.score_whole(&at[i], w2, &f2);
      ++check.positions;
      bool same = s1 == s2 && f1 == f2;
      for (int k = 0; k < 9 && same && f1; ++k) same = w1[k] == w2[k];
      if (!same) ++check.mismatches;
    }
  }
  return check;
}

}  // namespace voroclip::mesh3
