// Delaunay3: Bowyer–Watson insertion; see delaunay3.h for the storage, the local numbering
// and the conflict rules.
#include "voroclip/delaunay.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "nearest.h"
#include "spatial_sort.h"
#include "voroclip/core.h"

namespace voroclip {

namespace {

bool same_point(const double* a, const double* b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

// Exactly collinear: every axis-aligned projection of the triangle has zero area.
bool collinear(const double* a, const double* b, const double* c) {
  const double ayz[2] = {a[1], a[2]}, byz[2] = {b[1], b[2]}, cyz[2] = {c[1], c[2]};
  const double azx[2] = {a[2], a[0]}, bzx[2] = {b[2], b[0]}, czx[2] = {c[2], c[0]};
  return orient2d(a, b, c) == Sign::zero && orient2d(ayz, byz, cyz) == Sign::zero &&
         orient2d(azx, bzx, czx) == Sign::zero;
}

constexpr std::uint64_t edge_key(std::uint32_t u, std::uint32_t v) {
  return (static_cast<std::uint64_t>(u) << 32) | v;
}

}  // namespace

bool Delaunay3::is_infinite(std::uint32_t t) const { return infinite_slot(t) >= 0; }

int Delaunay3::infinite_slot(std::uint32_t t) const {
  const std::uint32_t* v = &tet_vertices_[4 * static_cast<std::size_t>(t)];
  return v[0] == kInfinite   ? 0
         : v[1] == kInfinite ? 1
         : v[2] == kInfinite ? 2
         : v[3] == kInfinite ? 3
                             : -1;
}

std::uint32_t Delaunay3::new_tet() {
  if (!free_tets_.empty()) {
    const std::uint32_t t = free_tets_.back();
    free_tets_.pop_back();
    std::fill_n(&tet_neighbors_[4 * static_cast<std::size_t>(t)], 4, 0u);
    return t;
  }
  const auto t = nb_tet_slots();
  if (t >= kMaxTets) throw Error("Delaunay3: more than 2^28 tetrahedra; input too large");
  tet_vertices_.resize(tet_vertices_.size() + 4);
  tet_neighbors_.resize(tet_neighbors_.size() + 4);
  return t;
}

void Delaunay3::free_tet(std::uint32_t t) {
  tet_vertices_[4 * static_cast<std::size_t>(t)] = kFreeVertex;
  free_tets_.push_back(t);
}

bool Delaunay3::in_conflict(std::uint32_t t, std::uint32_t q) const {
  const std::uint32_t* v = &tet_vertices_[4 * static_cast<std::size_t>(t)];
  const double* pq = point(q);
  const int s = infinite_slot(t);
  if (s < 0) {
    Sign r = insphere(point(v[0]), point(v[1]), point(v[2]), point(v[3]), pq, filter_);
    if (r == Sign::zero) {
      r = insphere_sos(point(v[0]), point(v[1]), point(v[2]), point(v[3]), pq, sos_id(v[0]),
                       sos_id(v[1]), sos_id(v[2]), sos_id(v[3]), sos_id(q));
    }
    return r == Sign::positive;
  }
  const std::uint32_t a = v[kFacetVertex[s][0]], b = v[kFacetVertex[s][1]],
                      c = v[kFacetVertex[s][2]];
  const Sign o = orient3d(point(a), point(b), point(c), pq, filter_);
  if (o != Sign::zero) return o == Sign::negative;
  // On the hull facet's plane: inside its circumcircle (see the header).
  const std::uint32_t n = tet_adjacent(t, s);
  const std::uint32_t d = tet_vertex(n, tet_adjacent_facet(t, s));
  return insphere_sos(point(a), point(b), point(c), point(d), pq, sos_id(a), sos_id(b), sos_id(c),
                      sos_id(d), sos_id(q)) == Sign::positive;
}

template <bool kStaticFilter>
std::uint32_t Delaunay3::walk(const double* p, std::uint32_t hint) const {
  std::uint32_t t = hint;
  if (const int s = infinite_slot(t); s >= 0) t = tet_adjacent(t, s);
  std::uint32_t previous = kNoTet;
  // Visibility walk, remembering the tet it came from (Devillers, Pion & Teillaud 2002);
  // it terminates in a Delaunay triangulation (Edelsbrunner 1990). The facet tested
  // first rotates deterministically, which avoids the worst cases of a fixed order.
  const std::size_t limit = 16 * static_cast<std::size_t>(nb_tet_slots()) + 64;
  for (std::size_t step = 0; step < limit; ++step) {
    const std::uint32_t* v = &tet_vertices_[4 * static_cast<std::size_t>(t)];
    bool moved = false;
    for (int i = 0; i < 4; ++i) {
      const int f = static_cast<int>((step + static_cast<std::size_t>(i)) & 3u);
      const std::uint32_t n = tet_adjacent(t, f);
      if (n == previous) continue;
      const double* a = point(v[kFacetVertex[f][0]]);
      const double* b = point(v[kFacetVertex[f][1]]);
      const double* c = point(v[kFacetVertex[f][2]]);
      // The static filter holds only for points inside the input's box: queries use the
      // plain predicate.
      const Sign o = kStaticFilter ? orient3d(a, b, c, p, filter_) : orient3d(a, b, c, p);
      if (o == Sign::positive) {
        previous = t;
        t = n;
        moved = true;
        break;
      }
    }
    if (!moved || infinite_slot(t) >= 0) return t;
  }
  throw Error("Delaunay3: internal error, the point location walk did not terminate");
}

std::uint32_t Delaunay3::locate(std::uint32_t q, std::uint32_t hint,
                                std::uint32_t& duplicate) const {
  duplicate = kInfinite;
  const double* pq = point(q);
  const std::uint32_t t = walk<true>(pq, hint);
  if (infinite_slot(t) < 0) {
    for (int k = 0; k < 4; ++k) {
      if (same_point(point(tet_vertex(t, k)), pq)) duplicate = tet_vertex(t, k);
    }
  }
  return t;
}

std::uint32_t Delaunay3::locate(const double* p, std::uint32_t hint) const {
  require_finite_query(p);
  if (hint == kNoTet || hint >= nb_tet_slots() || is_free(hint)) hint = any_tet();
  return walk<false>(p, hint);
}

std::uint32_t Delaunay3::nearest_vertex(const double* p, std::uint32_t hint) const {
  const std::uint32_t t = locate(p, hint);
  std::uint32_t v = kInfinite;
  for (int k = 0; k < 4 && v == kInfinite; ++k) v = tet_vertex(t, k);
  return detail::nearest_on_delaunay_graph(
      v, [this](std::uint32_t w, std::vector<std::uint32_t>& out) { vertex_neighbors(w, out); },
      [this, p](std::uint32_t w, std::uint32_t u) {
        return compare_distance3d(p, point(w), point(u));
      });
}

std::uint32_t Delaunay3::any_tet() const {
  for (std::uint32_t t = 0; t < nb_tet_slots(); ++t) {
    if (!is_free(t)) return t;
  }
  throw Error("Delaunay3: the triangulation is empty (build() has not succeeded)");
}

void Delaunay3::require_finite_query(const double* p) const {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
    throw Error("Delaunay3: the query point has a non-finite coordinate");
  }
}

void Delaunay3::insert(std::uint32_t q, std::uint32_t& hint) {
  std::uint32_t duplicate;
  const std::uint32_t start = locate(q, hint, duplicate);
  if (duplicate != kInfinite) {
    duplicate_internal_[q] = duplicate;
    return;
  }
  // Cavity: tets in conflict, found by a search from the located one (which is in
  // conflict: q lies in it, or strictly beyond its hull facet). Mark 0 flags cavity tets,
  // mark 1 tets tested and found outside; cavity tets are recycled below (which clears
  // their marks) and the outside marks are cleared at the end.
  constexpr int kInCavity = 0, kOutside = 1;
  cavity_.clear();
  boundary_.clear();
  stack_.clear();
  mark(start, kInCavity);
  cavity_.push_back(start);
  stack_.push_back(start);
  while (!stack_.empty()) {
    const std::uint32_t t = stack_.back();
    stack_.pop_back();
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t n = tet_adjacent(t, f);
      if (marked(n, kInCavity)) continue;
      if (!marked(n, kOutside)) {
        if (in_conflict(n, q)) {
          mark(n, kInCavity);
          cavity_.push_back(n);
          stack_.push_back(n);
          continue;
        }
        mark(n, kOutside);
      }
      BoundaryFacet b{n, tet_adjacent_facet(t, f), f, {}};
      for (int k = 0; k < 4; ++k) b.vertex[k] = k == f ? q : tet_vertex(t, k);
      boundary_.push_back(b);
    }
  }

  // One new tet per boundary facet: the dead tet's vertices with q in place of the vertex
  // opposite the facet (so it keeps the dead tet's positive orientation). Its facets
  // through q are glued pairwise by their edge: the facet (q, u, v) of one new tet is the
  // facet (q, v, u) of another. The cavity's slots are freed first, so that the new tets
  // reuse them while they are still in cache.
  for (const std::uint32_t t : cavity_) free_tet(t);
  const std::size_t nb_new = boundary_.size();
  std::size_t table_size = 64;
  while (table_size < 8 * nb_new) table_size *= 2;
  edge_keys_.assign(table_size, ~std::uint64_t{0});
  edge_values_.resize(table_size);
  const std::size_t mask = table_size - 1;
  std::uint32_t last = kNoTet;
  for (const BoundaryFacet& b : boundary_) {
    const std::uint32_t nt = new_tet();
    std::copy_n(b.vertex, 4, &tet_vertices_[4 * static_cast<std::size_t>(nt)]);
    set_neighbors(nt, b.dead_facet, b.tet, b.facet);
    for (int f = 0; f < 4; ++f) {
      if (f == b.dead_facet) continue;
      // The facet's vertices, rotated to start at q: (q, u, v).
      const int* fv = kFacetVertex[f];
      int at = 0;
      while (fv[at] != b.dead_facet) ++at;
      const std::uint32_t u = tet_vertex(nt, fv[(at + 1) % 3]);
      const std::uint32_t w = tet_vertex(nt, fv[(at + 2) % 3]);
      const std::uint64_t want = edge_key(w, u);
      std::size_t h = static_cast<std::size_t>((want * 0x9E3779B97F4A7C15ull) >> 40) & mask;
      bool glued = false;
      while (edge_keys_[h] != ~std::uint64_t{0}) {
        if (edge_keys_[h] == want) {
          const std::uint32_t other = edge_values_[h];
          set_neighbors(nt, f, other / 4, static_cast<int>(other % 4));
          edge_keys_[h] = ~std::uint64_t{0} - 1;  // tombstone: used
          glued = true;
          break;
        }
        h = (h + 1) & mask;
      }
      if (!glued) {
        const std::uint64_t key = edge_key(u, w);
        std::size_t g = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 40) & mask;
        while (edge_keys_[g] != ~std::uint64_t{0} && edge_keys_[g] != ~std::uint64_t{0} - 1) {
          g = (g + 1) & mask;
        }
        edge_keys_[g] = key;
        edge_values_[g] = 4 * nt + static_cast<std::uint32_t>(f);
      }
    }
    last = nt;
  }
  for (const BoundaryFacet& b : boundary_) unmark(b.tet, kOutside);
  hint = last;
}

std::uint32_t Delaunay3::initial_tetrahedron(const std::vector<std::uint32_t>& order) {
  // The first four affinely independent points of the insertion order.
  std::uint32_t chosen[4];
  std::size_t i = 0;
  const std::size_t n = order.size();
  chosen[0] = order[0];
  for (i = 1; i < n && same_point(point(order[i]), point(chosen[0])); ++i) {
  }
  if (i == n) throw Error("Delaunay3: all points coincide; need 4 affinely independent points");
  chosen[1] = order[i];
  for (++i; i < n && collinear(point(chosen[0]), point(chosen[1]), point(order[i])); ++i) {
  }
  if (i == n)
    throw Error("Delaunay3: all points are collinear; need 4 affinely independent points");
  chosen[2] = order[i];
  Sign o = Sign::zero;
  for (++i; i < n; ++i) {
    o = orient3d(point(chosen[0]), point(chosen[1]), point(chosen[2]), point(order[i]));
    if (o != Sign::zero) break;
  }
  if (i == n) throw Error("Delaunay3: all points are coplanar; need 4 affinely independent points");
  chosen[3] = order[i];
  if (o == Sign::negative) std::swap(chosen[0], chosen[1]);

  const std::uint32_t t0 = new_tet();
  for (int k = 0; k < 4; ++k) tet_vertices_[4 * t0 + static_cast<std::uint32_t>(k)] = chosen[k];
  // An infinite tet on each facet (a, b, c) of t0 lists it reversed: (b, c, a, inf) has
  // facet 3 = (a, c, b). Their facets through the infinite vertex are glued by edge.
  std::uint32_t inf[4];
  for (int f = 0; f < 4; ++f) {
    inf[f] = new_tet();
    const std::uint32_t a = chosen[kFacetVertex[f][0]], b = chosen[kFacetVertex[f][1]],
                        c = chosen[kFacetVertex[f][2]];
    std::uint32_t* v = &tet_vertices_[4 * static_cast<std::size_t>(inf[f])];
    v[0] = b;
    v[1] = c;
    v[2] = a;
    v[3] = kInfinite;
    set_neighbors(t0, f, inf[f], 3);
  }
  for (int f = 0; f < 4; ++f) {
    for (int g = 0; g < 3; ++g) {
      // Facet g of inf[f] holds the infinite vertex and the edge opposite v[g].
      for (int f2 = 0; f2 < 4; ++f2) {
        if (f2 == f) continue;
        for (int g2 = 0; g2 < 3; ++g2) {
          const auto shares = [&](std::uint32_t t1, int h1, std::uint32_t t2, int h2) {
            int common = 0;
            for (int x = 0; x < 3; ++x) {
              for (int y = 0; y < 3; ++y) {
                common +=
                    tet_vertex(t1, kFacetVertex[h1][x]) == tet_vertex(t2, kFacetVertex[h2][y]);
              }
            }
            return common == 3;
          };
          if (shares(inf[f], g, inf[f2], g2)) {
            tet_neighbors_[4 * inf[f] + static_cast<std::uint32_t>(g)] =
                4 * inf[f2] + static_cast<std::uint32_t>(g2);
          }
        }
      }
    }
  }
  return t0;
}

void Delaunay3::build(const double* xyz, std::uint32_t n) {
  for (std::uint32_t i = 0; i < n; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!std::isfinite(xyz[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(j)])) {
        throw Error("Delaunay3: point " + std::to_string(i) + " has a non-finite coordinate");
      }
    }
  }
  if (n < 4) {
    throw Error("Delaunay3: " + std::to_string(n) + " points; need 4 affinely independent points");
  }
  xyz_ = xyz;
  nb_points_ = n;
  filter_ = StaticFilter::bounding(xyz, n, 3);
  duplicate_of_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) duplicate_of_[i] = i;

  input_id_ = detail::brio_order(xyz, n, 3);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      // Duplicates whose smallest index was not the one inserted first: build again
      // without them, so that every vertex carries the smallest index of its group (the
      // index its symbolic perturbation uses).
      std::vector<std::uint32_t> group_min(n, kInfinite);
      bool relabel = false;
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t v = duplicate_of_[i];
        group_min[v] = std::min(group_min[v], i);
        relabel = relabel || group_min[v] < v;
      }
      if (!relabel) break;
      for (std::uint32_t i = 0; i < n; ++i) duplicate_of_[i] = group_min[duplicate_of_[i]];
      std::vector<std::uint32_t> kept;
      kept.reserve(n);
      for (const std::uint32_t i : input_id_) {
        if (duplicate_of_[i] == i) kept.push_back(i);
      }
      input_id_.swap(kept);
    }
    // Internal numbering: position in the insertion order.
    const auto m = static_cast<std::uint32_t>(input_id_.size());
    sorted_xyz_.resize(3 * static_cast<std::size_t>(m));
    for (std::uint32_t v = 0; v < m; ++v) {
      std::copy_n(xyz + 3 * static_cast<std::size_t>(input_id_[v]), 3,
                  &sorted_xyz_[3 * static_cast<std::size_t>(v)]);
    }
    pts_ = sorted_xyz_.data();
    sos_ids_ = input_id_.data();
    duplicate_internal_.resize(m);
    for (std::uint32_t v = 0; v < m; ++v) duplicate_internal_[v] = v;
    // Uniform random points give about 6.75 tets per point.
    const std::size_t expected = 27 * static_cast<std::size_t>(m) / 4 + 64;
    tet_vertices_.clear();
    tet_neighbors_.clear();
    free_tets_.clear();
    tet_vertices_.reserve(4 * expected);
    tet_neighbors_.reserve(4 * expected);

    std::vector<std::uint32_t> order(m);
    for (std::uint32_t v = 0; v < m; ++v) order[v] = v;
    // The first four affinely independent points of the order form the initial tet; the
    // points passed over to find them are inserted later like any other.
    const std::uint32_t t0 = initial_tetrahedron(order);
    const std::uint32_t used[4] = {tet_vertex(t0, 0), tet_vertex(t0, 1), tet_vertex(t0, 2),
                                   tet_vertex(t0, 3)};
    std::uint32_t hint = t0;
    for (std::uint32_t q = 0; q < m; ++q) {
      if (q != used[0] && q != used[1] && q != used[2] && q != used[3]) insert(q, hint);
    }
    for (std::uint32_t v = 0; v < m; ++v) {
      duplicate_of_[input_id_[v]] = input_id_[duplicate_internal_[v]];
    }
  }

  // Back to input indices (free slots keep their marker).
  for (std::uint32_t& v : tet_vertices_) {
    if (v != kInfinite && v != kFreeVertex) v = input_id_[v];
  }
  pts_ = xyz_;
  sos_ids_ = nullptr;

  vertex_tet_.assign(n, kNoTet);
  nb_finite_tets_ = 0;
  for (std::uint32_t t = 0; t < nb_tet_slots(); ++t) {
    if (is_free(t)) continue;
    const bool finite = !is_infinite(t);
    nb_finite_tets_ += finite ? 1 : 0;
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t v = tet_vertex(t, k);
      if (v != kInfinite && (vertex_tet_[v] == kNoTet || finite)) vertex_tet_[v] = t;
    }
  }
  nb_unique_ = 0;
  for (std::uint32_t i = 0; i < n; ++i) nb_unique_ += duplicate_of_[i] == i ? 1 : 0;
}

void Delaunay3::vertex_star(std::uint32_t v, std::vector<std::uint32_t>& star) const {
  // Breadth-first over the tets around v (finite and infinite), through the facets that
  // contain v. Stars are small (about 27 tets for uniform points): a linear search for
  // visited tets beats any set.
  star.clear();
  const std::uint32_t start = vertex_tet_[v];
  if (start == kNoTet) return;
  star.push_back(start);
  for (std::size_t i = 0; i < star.size(); ++i) {
    const std::uint32_t t = star[i];
    for (int f = 0; f < 4; ++f) {
      if (tet_vertex(t, f) == v) continue;  // the facet opposite v does not contain v
      const std::uint32_t n = tet_adjacent(t, f);
      if (std::find(star.begin(), star.end(), n) == star.end()) star.push_back(n);
    }
  }
}

void Delaunay3::vertex_tets(std::uint32_t v, std::vector<std::uint32_t>& out) const {
  vertex_star(v, out);
  out.erase(
      std::remove_if(out.begin(), out.end(), [this](std::uint32_t t) { return is_infinite(t); }),
      out.end());
  std::sort(out.begin(), out.end());
}

void Delaunay3::vertex_neighbors(std::uint32_t v, std::vector<std::uint32_t>& out) const {
  std::vector<std::uint32_t> star;
  vertex_star(v, star);
  out.clear();
  for (const std::uint32_t t : star) {
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t w = tet_vertex(t, k);
      if (w != v && w != kInfinite) out.push_back(w);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

std::vector<std::uint32_t> Delaunay3::hull_vertices() const {
  std::vector<std::uint32_t> out;
  for (std::uint32_t t = 0; t < nb_tet_slots(); ++t) {
    if (is_free(t) || !is_infinite(t)) continue;
    for (int k = 0; k < 4; ++k) {
      if (tet_vertex(t, k) != kInfinite) out.push_back(tet_vertex(t, k));
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void Delaunay3::circumcenter(std::uint32_t t, double* out) const {
  // Center = a + (|b'|^2 (c' x d') + |c'|^2 (d' x b') + |d'|^2 (b' x c')) / (2 det), with
  // b' = b - a etc.: floating point, for output and clipping only.
  const double* a = point(tet_vertex(t, 0));
  double b[3], c[3], d[3];
  for (int j = 0; j < 3; ++j) {
    b[j] = point(tet_vertex(t, 1))[j] - a[j];
    c[j] = point(tet_vertex(t, 2))[j] - a[j];
    d[j] = point(tet_vertex(t, 3))[j] - a[j];
  }
  const auto cross = [](const double* x, const double* y, double* r) {
    r[0] = x[1] * y[2] - x[2] * y[1];
    r[1] = x[2] * y[0] - x[0] * y[2];
    r[2] = x[0] * y[1] - x[1] * y[0];
  };
  double cd[3], db[3], bc[3];
  cross(c, d, cd);
  cross(d, b, db);
  cross(b, c, bc);
  const double bb = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
  const double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
  const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  const double det = b[0] * cd[0] + b[1] * cd[1] + b[2] * cd[2];
  for (int j = 0; j < 3; ++j) out[j] = a[j] + (bb * cd[j] + cc * db[j] + dd * bc[j]) / (2 * det);
}

std::size_t Delaunay3::memory_bytes() const {
  const auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(tet_vertices_) + bytes(tet_neighbors_) + bytes(free_tets_) + bytes(vertex_tet_) +
         bytes(duplicate_of_) + bytes(duplicate_internal_) + bytes(sorted_xyz_) + bytes(input_id_) +
         bytes(cavity_) + bytes(stack_) + bytes(boundary_) + bytes(edge_keys_) +
         bytes(edge_values_);
}

std::string Delaunay3::check_topology() const {
  std::vector<std::uint32_t> facet_a(3), facet_b(3);
  for (std::uint32_t t = 0; t < nb_tet_slots(); ++t) {
    if (is_free(t)) continue;
    int infinite = 0;
    for (int k = 0; k < 4; ++k) infinite += tet_vertex(t, k) == kInfinite;
    if (infinite > 1) return "tet " + std::to_string(t) + " has several infinite vertices";
    if (infinite == 0 &&
        orient3d(point(tet_vertex(t, 0)), point(tet_vertex(t, 1)), point(tet_vertex(t, 2)),
                 point(tet_vertex(t, 3))) != Sign::positive) {
      return "finite tet " + std::to_string(t) + " is not positively oriented";
    }
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t n = tet_adjacent(t, f);
      const int g = tet_adjacent_facet(t, f);
      if (n >= nb_tet_slots() || is_free(n)) {
        return "tet " + std::to_string(t) + " facet " + std::to_string(f) + ": bad neighbour";
      }
      if (tet_adjacent(n, g) != t || tet_adjacent_facet(n, g) != f) {
        return "tet " + std::to_string(t) + " facet " + std::to_string(f) + ": not symmetric";
      }
      // The shared facet, listed reversed by the neighbour: (a, b, c) vs a rotation of
      // (a, c, b).
      for (int i = 0; i < 3; ++i) {
        facet_a[static_cast<std::size_t>(i)] = tet_vertex(t, kFacetVertex[f][i]);
        facet_b[static_cast<std::size_t>(i)] = tet_vertex(n, kFacetVertex[g][2 - i]);
      }
      bool match = false;
      for (int r = 0; r < 3 && !match; ++r) {
        std::rotate(facet_b.begin(), facet_b.begin() + 1, facet_b.end());
        match = facet_a == facet_b;
      }
      if (!match) {
        return "tet " + std::to_string(t) + " facet " + std::to_string(f) +
               ": the neighbour does not list the same facet reversed";
      }
    }
  }
  for (std::uint32_t v = 0; v < nb_points_; ++v) {
    const std::uint32_t t = vertex_tet_[v];
    if (duplicate_of_[v] != v) {
      if (t != kNoTet) return "duplicate point " + std::to_string(v) + " is a vertex";
      continue;
    }
    if (t == kNoTet || is_free(t)) return "vertex " + std::to_string(v) + " has no tet";
    bool has = false;
    for (int k = 0; k < 4; ++k) has = has || tet_vertex(t, k) == v;
    if (!has) return "vertex " + std::to_string(v) + ": its tet does not contain it";
  }
  return {};
}

std::string Delaunay3::check_delaunay() const {
  for (std::uint32_t t = 0; t < nb_tet_slots(); ++t) {
    if (is_free(t)) continue;
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t n = tet_adjacent(t, f);
      const std::uint32_t opposite = tet_vertex(n, tet_adjacent_facet(t, f));
      if (opposite == kInfinite) continue;  // checked from the infinite tet's side
      if (in_conflict(t, opposite)) {
        return "tet " + std::to_string(t) + " is in conflict with vertex " +
               std::to_string(opposite) + " of its neighbour " + std::to_string(n);
      }
    }
  }
  return {};
}

}  // namespace voroclip
