// Cells of the 3D clipped Voronoi diagram straight from the Delaunay triangulation (Yan et
// al. 2011, sec. 4, the boundary cells by the divergence theorem instead of tet by tet;
// clip3d.cpp gives the overview): DelaunayCells (clip3d_cells.h), which reads the
// RestrictedSurface of the surface pass; each thread has a Scratch of its own and its Stars.
// The cells' faces for export are in clip3d_faces.cpp.
//
// Cones over the boundary. For a region R bounded by an outward-oriented closed surface,
// ∫_R g = Σ over faces of the signed integral of g over the cone from p_i to the face (the
// cones' indicator functions sum to R's), for any g and any apex. Cell i ∩ Ω is bounded by
// its restricted surface polygons (clip3d_surface.cpp) and, on each bisector(i, j), by the
// region F_ij ∩ Ω of its Voronoi facet F_ij. That region is planar; a fan from the foot
// m_ij = (p_i + p_j) / 2 over its oriented boundary gives its cone, and the boundary is made
// of (a) the pieces of F_ij's Voronoi edges inside Ω and (b) the edges of the restricted
// polygons on bisector(i, j) (the surface pass adds those). So cell i needs, per Voronoi
// edge around it, the piece inside Ω: add_edge_piece.
//
// Voronoi edges. The edge dual to Delaunay facet (i, j, k) between tets T and T' runs from
// the circumcentre c_T to c_T' along the normal of the facet pointing out of T (for the
// perturbed Delaunay triangulation the edge is [t_T, t_T'] along that normal, t_T <= t_T').
// With (i, j, k, l) an even permutation of T's positive vertex order (l opposite the
// facet), that normal is (p_j - p_i) x (p_k - p_i) and the edge runs counter-clockwise
// around p_j - p_i: kFaceOther numbers (j, k) so. Each facet of a star is taken once, from
// the tet of the smaller index (or the finite one).
//
// Inside or outside. A Voronoi vertex (a tet's circumcentre) of an inner cell is inside
// Ω. For boundary cells the surface pass gives, per Voronoi edge, its crossings with the
// surface: an edge with one crossing has one end inside, the one it leaves Ω from
// (voronoi_edge_direction3d), and across a Delaunay facet the flag flips with the parity
// of its crossings; an infinite tet (a vertex at infinity) is outside. A boundary cell
// places its star's vertices from the crossings of its star's facets, by a breadth-first
// search over the star; no floating-point decision is involved. When none of them has a
// single crossing nor an infinite neighbour (a surface component that meets at most two
// cells, or only multiply-crossed edges), the flags come from a search over all tets from
// the infinite ones (global_flags).
//
// Other cells. A cell that does not meet the surface lies wholly inside or outside Ω
// (cells are connected), and so does each connected group of them (adjacent cells share a
// facet). Every group borders a boundary cell (the Delaunay graph is connected), whose
// star places the vertices the group's cells share with it: the boundary cells report
// those, groups reported outside are spread by a search through their neighbours, every
// other cell is inside.
#include "clip3d_cells.h"

#include <algorithm>
#include <array>
#include <string>
#include <utility>
#include <vector>

namespace voroclip {

namespace clip3 {

namespace {

struct FaceOtherTable {
  std::int8_t v[4][4][2];
};

constexpr FaceOtherTable make_face_other() {
  FaceOtherTable t{};
  for (int li = 0; li < 4; ++li) {
    for (int f = 0; f < 4; ++f) {
      if (li == f) {
        t.v[li][f][0] = t.v[li][f][1] = -1;
        continue;
      }
      int o[2] = {0, 0}, q = 0;
      for (int k = 0; k < 4; ++k) {
        if (k != li && k != f) o[q++] = k;
      }
      const int p[4] = {li, o[0], o[1], f};
      int inversions = 0;
      for (int a = 0; a < 4; ++a) {
        for (int b = a + 1; b < 4; ++b) inversions += p[a] > p[b] ? 1 : 0;
      }
      const bool even = inversions % 2 == 0;
      t.v[li][f][0] = static_cast<std::int8_t>(even ? o[0] : o[1]);
      t.v[li][f][1] = static_cast<std::int8_t>(even ? o[1] : o[0]);
    }
  }
  return t;
}

constexpr FaceOtherTable kTable = make_face_other();

}  // namespace

const std::int8_t kFaceOther[4][4][2] = {
    {{kTable.v[0][0][0], kTable.v[0][0][1]},
     {kTable.v[0][1][0], kTable.v[0][1][1]},
     {kTable.v[0][2][0], kTable.v[0][2][1]},
     {kTable.v[0][3][0], kTable.v[0][3][1]}},
    {{kTable.v[1][0][0], kTable.v[1][0][1]},
     {kTable.v[1][1][0], kTable.v[1][1][1]},
     {kTable.v[1][2][0], kTable.v[1][2][1]},
     {kTable.v[1][3][0], kTable.v[1][3][1]}},
    {{kTable.v[2][0][0], kTable.v[2][0][1]},
     {kTable.v[2][1][0], kTable.v[2][1][1]},
     {kTable.v[2][2][0], kTable.v[2][2][1]},
     {kTable.v[2][3][0], kTable.v[2][3][1]}},
    {{kTable.v[3][0][0], kTable.v[3][0][1]},
     {kTable.v[3][1][0], kTable.v[3][1][1]},
     {kTable.v[3][2][0], kTable.v[3][2][1]},
     {kTable.v[3][3][0], kTable.v[3][3][1]}},
};

namespace {

[[noreturn]] void internal_error(const std::string& what) {
  throw Error("clip3d: internal error: " + what);
}

}  // namespace

bool DelaunayCells::boundary_cell(std::uint32_t i, const std::int8_t* global_flag, Stars& stars,
                                  Scratch& s, Moments& r, std::vector<Segment>* segments) const {
  const Star& st = stars.pooled_star(ctx_, i);
  const std::vector<std::uint32_t>& tets = st.tets;
  const std::size_t m = tets.size();
  std::vector<std::int8_t>& flag = s.flag;
  flag.assign(m, -1);
  // The crossings of the Voronoi edge dual to each facet of each tet (only between boundary
  // cells; a facet shared by two tets of the star is looked up once).
  std::vector<const EdgeCrossings*>& fx = s.fx;
  fx.assign(4 * m, nullptr);
  std::vector<std::uint8_t>& known = s.known;
  known.assign(4 * m, 0);
  constexpr std::size_t kAhead = 4;
  for (std::size_t q = 0; q < kAhead && q < m; ++q) ctx_.dt.prefetch_tet(tets[q]);
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t t = tets[q];
    // A pooled star's records are not in cache (its traversal was long ago): the records a
    // few tets ahead, and the circumcentres' cache entries (read below).
    if (q + kAhead < m) ctx_.dt.prefetch_tet(tets[q + kAhead]);
    s.circ.prefetch(t);
    std::uint32_t w[4];
    int nb = 0;
    for (int k = 0; k < 4; ++k) {
      w[k] = ctx_.dt.tet_vertex(t, k);
      nb += w[k] != Delaunay3::kInfinite && rs_.is_boundary[w[k]] ? 1 : 0;
      // The tet across the facet opposite i is outside the star; the placement below reads
      // its record (is it infinite?).
      if (w[k] == i) ctx_.dt.prefetch_tet(ctx_.dt.tet_adjacent(t, k));
    }
    if (nb < 3) continue;
    for (int f = 0; f < 4; ++f) {
      if (known[4 * q + f]) continue;
      const EdgeCrossings* x = nullptr;
      const std::uint32_t a = w[f == 0 ? 1 : 0], b = w[f <= 1 ? 2 : 1], c = w[f <= 2 ? 3 : 2];
      if (a != Delaunay3::kInfinite && b != Delaunay3::kInfinite && c != Delaunay3::kInfinite &&
          rs_.is_boundary[a] && rs_.is_boundary[b] && rs_.is_boundary[c]) {
        x = rs_.find_crossings(a, b, c);
      }
      fx[4 * q + f] = x;
      const std::uint32_t t2 = ctx_.dt.tet_adjacent(t, f);
      if (st.contains(t2)) {
        const std::size_t k2 =
            4 * std::size_t{st.pos(t2)} + std::size_t(ctx_.dt.tet_adjacent_facet(t, f));
        fx[k2] = x;
        known[k2] = 1;
      }
    }
  }
  std::vector<std::uint32_t>& queue = s.queue;
  queue.clear();
  const auto place = [&](std::size_t q, int v) {
    if (flag[q] == -1) {
      flag[q] = static_cast<std::int8_t>(v);
      queue.push_back(static_cast<std::uint32_t>(q));
    } else if (flag[q] != v) {
      internal_error("Voronoi vertex of tet " + std::to_string(tets[q]) +
                     " placed both inside and outside (cell " + std::to_string(i) + ")");
    }
  };
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t t = tets[q];
    if (ctx_.infinite(t)) {
      place(q, 0);
      continue;
    }
    if (global_flag) {
      place(q, global_flag[t]);
      continue;
    }
    for (int f = 0; f < 4; ++f) {
      const EdgeCrossings* x = fx[4 * q + f];
      const std::uint32_t count = x ? x->count : 0;
      if (ctx_.infinite(ctx_.dt.tet_adjacent(t, f))) {
        place(q, static_cast<int>(count & 1));
      } else if (count == 1) {
        // The edge leaves t along (p_s1 - p_s0) x (p_s2 - p_s0) when (s0, s1, s2, opposite)
        // is an even permutation of t's vertices; it leaves Ω there when sigma > 0.
        int l0 = 0;
        while (ctx_.dt.tet_vertex(t, l0) != x->s[0]) ++l0;
        const bool even = ctx_.dt.tet_vertex(t, kFaceOther[l0][f][0]) == x->s[1];
        place(q, (even ? x->sigma : -x->sigma) > 0 ? 1 : 0);
      }
    }
  }
  if (queue.empty()) return false;
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const std::uint32_t q = queue[h];
    const std::uint32_t t = tets[q];
    for (int f = 0; f < 4; ++f) {
      if (ctx_.dt.tet_vertex(t, f) == i) continue;
      const EdgeCrossings* x = fx[4 * q + f];
      const int parity = x ? static_cast<int>(x->count & 1) : 0;
      place(st.pos(ctx_.dt.tet_adjacent(t, f)), flag[q] ^ parity);
    }
  }
  // The non-boundary sites of the star take the flag of their tets.
  if (s.site_mark.size() != ctx_.n || s.site_gen == 0xffffffffu) {
    s.site_mark.assign(ctx_.n, 0);
    s.site_gen = 0;
  }
  const std::uint32_t gen = ++s.site_gen;
  const auto report = [&](std::size_t q, const std::uint32_t* v) {
    for (int k = 0; k < 4; ++k) {
      if (v[k] == Delaunay3::kInfinite || rs_.is_boundary[v[k]] || s.site_mark[v[k]] == gen)
        continue;
      s.site_mark[v[k]] = gen;
      s.first_layer.emplace_back(v[k], flag[q]);
    }
  };
  if (ctx_.linear_density || ctx_.options.tet_clipping) {
    for (std::size_t q = 0; q < m; ++q) {
      const std::uint32_t t = tets[q];
      const std::uint32_t v[4] = {ctx_.dt.tet_vertex(t, 0), ctx_.dt.tet_vertex(t, 1),
                                  ctx_.dt.tet_vertex(t, 2), ctx_.dt.tet_vertex(t, 3)};
      report(q, v);
    }
    return true;
  }

  // The pieces of the Voronoi edges around i inside Ω. The circumcentres first, and with
  // them the first-layer reports (every vertex of the star is in one of its finite tets:
  // at most two tets around an edge are infinite; all tets of a non-boundary site carry
  // the same flag, so which one reports it does not matter).
  const double* pi = ctx_.apex(i);  // the cones' apex (Clip3Context::far)
  if (s.chunk.c.size() < m) s.chunk.c.resize(m);
  std::array<double, 3>* cc = s.chunk.c.data();
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t t = tets[q];
    if (ctx_.infinite(t)) continue;
    const std::uint32_t v[4] = {ctx_.dt.tet_vertex(t, 0), ctx_.dt.tet_vertex(t, 1),
                                ctx_.dt.tet_vertex(t, 2), ctx_.dt.tet_vertex(t, 3)};
    report(q, v);
    const double* c = circumcentre(t, v, s.circ);
    cc[q] = {c[0], c[1], c[2]};
  }
  PieceSums sums;
  Moments weighted_sums;
  if (ctx_.callback_density) thread_density_batch().begin(*ctx_.callback_density);
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t t = tets[q];
    if (ctx_.infinite(t)) continue;
    const std::uint32_t v[4] = {ctx_.dt.tet_vertex(t, 0), ctx_.dt.tet_vertex(t, 1),
                                ctx_.dt.tet_vertex(t, 2), ctx_.dt.tet_vertex(t, 3)};
    int li = 0;
    while (v[li] != i) ++li;
    for (int f = 0; f < 4; ++f) {
      if (f == li) continue;
      const std::uint32_t t2 = ctx_.dt.tet_adjacent(t, f);
      const bool infinite2 = ctx_.infinite(t2);
      if (!infinite2 && t2 < t) continue;
      const std::uint32_t q2 = st.pos(t2);
      const std::uint32_t vj = v[kFaceOther[li][f][0]];
      const std::uint32_t vk = v[kFaceOther[li][f][1]];
      inside_pieces(v, f, cc[q].data(), flag[q] != 0, infinite2 ? nullptr : cc[q2].data(),
                    flag[q2] != 0, fx[4 * q + f], [&](const double* a, const double* b) {
                      const Rel u = rel(a, pi), w = rel(b, pi);
                      if (ctx_.weighted) {
                        add_piece<true>(i, vj, vk, u, w, weighted_sums);
                      } else {
                        add_piece<false>(i, vj, vk, u, w, sums);
                      }
                      if (segments) {
                        Segment sj, sk;
                        sj.across = vj;
                        sk.across = vk;
                        for (int c = 0; c < 3; ++c) {
                          sj.a[c] = sk.b[c] = a[c];
                          sj.b[c] = sk.a[c] = b[c];
                        }
                        segments->push_back(sj);
                        segments->push_back(sk);
                      }
                    });
    }
  }
  if (ctx_.callback_density) thread_density_batch().flush();
  if (ctx_.weighted) {
    r.mass += weighted_sums.mass;
    for (int c = 0; c < 3; ++c) r.moment[c] += weighted_sums.moment[c];
    r.energy += weighted_sums.energy;
    r.volume += weighted_sums.volume;
  } else {
    sums.add_to(r);
  }
  return true;
}

template <class Piece>
[[gnu::always_inline]] inline void DelaunayCells::inside_pieces(const std::uint32_t* tv, int f,
                                                                const double* u, bool in1,
                                                                const double* w, bool in2,
                                                                const EdgeCrossings* x,
                                                                Piece&& piece) const {
  const std::uint32_t count = x ? x->count : 0;
  if (count == 0) {
    if (in1 != in2) internal_error("a Voronoi edge with no crossing changes side");
    if (in1) piece(u, w);
    return;
  }
  if (count == 1) {
    if (in1 == in2) internal_error("a Voronoi edge with one crossing keeps its side");
    piece(in1 ? u : x->x, in1 ? x->x : w);
    return;
  }
  thread_local std::vector<SignedSegment> signed_segments;
  multi_crossing_segments(tv, f, u, in1, w, in2, *x, signed_segments);
  for (const SignedSegment& g : signed_segments) {
    for (int r = 0; r < g.times; ++r) piece(g.a, g.b);
    for (int r = 0; r < -g.times; ++r) piece(g.b, g.a);
  }
}

void DelaunayCells::multi_crossing_segments(const std::uint32_t* tv, int f, const double* u,
                                            bool in1, const double* w, bool in2,
                                            const EdgeCrossings& edge,
                                            std::vector<SignedSegment>& segments) const {
  const EdgeCrossings* x = &edge;
  const std::uint32_t count = x->count;
  segments.clear();
  // The edge leaves t along n = (p_s1 - p_s0) x (p_s2 - p_s0) when (s0, s1, s2, opposite) is
  // an even permutation of t's vertices; a crossing with sigma > 0 leaves Ω along n.
  int l0 = 0;
  while (tv[l0] != x->s[0]) ++l0;
  const bool even = tv[kFaceOther[l0][f][0]] == x->s[1];
  int balance = in1 ? 1 : 0;
  for (std::uint32_t k = 0; k < count; ++k) {
    const CrossingPoint& c = rs_.multi_crossings[x->first + k];
    balance += (even ? c.sigma : -c.sigma) > 0 ? -1 : 1;
  }
  if (balance != (in2 ? 1 : 0)) {
    internal_error("the " + std::to_string(count) + " crossings of the Voronoi edge of sites " +
                   std::to_string(x->s[0]) + ", " + std::to_string(x->s[1]) + ", " +
                   std::to_string(x->s[2]) + " do not match the sides of its ends");
  }
  // The crossings in their order along the edge, by floating point: the sum telescopes to
  // the same exact value in any order (inside_pieces' comment), so the order only chooses
  // short segments over long ones that cancel. Between consecutive points, the number of
  // times the segment counts (1 inside; a misordered pair of nearly equal crossings can
  // make it 2 or -1 on the tiny segment between them).
  double dir[3];
  if (w != nullptr) {
    for (int c = 0; c < 3; ++c) dir[c] = w[c] - u[c];
  } else {
    const double* p0 = ctx_.site(x->s[0]);
    const double* p1 = ctx_.site(x->s[1]);
    const double* p2 = ctx_.site(x->s[2]);
    const double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const double e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    const double sign = even ? 1.0 : -1.0;
    dir[0] = sign * (e1[1] * e2[2] - e1[2] * e2[1]);
    dir[1] = sign * (e1[2] * e2[0] - e1[0] * e2[2]);
    dir[2] = sign * (e1[0] * e2[1] - e1[1] * e2[0]);
  }
  constexpr std::uint32_t kMaxSorted = 32;
  std::pair<double, std::uint32_t> sorted[kMaxSorted];
  const std::uint32_t m = std::min(count, kMaxSorted);
  for (std::uint32_t k = 0; k < m; ++k) {
    const double* q = rs_.multi_crossings[x->first + k].x;
    sorted[k] = {(q[0] - u[0]) * dir[0] + (q[1] - u[1]) * dir[1] + (q[2] - u[2]) * dir[2], k};
  }
  std::sort(sorted, sorted + m);
  const auto emit = [&](const double* a, const double* b, int times) {
    if (times != 0) segments.push_back({a, b, times});
  };
  int inside = in1 ? 1 : 0;
  const double* prev = u;
  for (std::uint32_t h = 0; h < count; ++h) {
    // (Beyond kMaxSorted crossings, the rest in triangle order.)
    const std::uint32_t k = h < m ? sorted[h].second : h;
    const CrossingPoint& c = rs_.multi_crossings[x->first + k];
    emit(prev, c.x, inside);
    inside += (even ? c.sigma : -c.sigma) > 0 ? -1 : 1;
    prev = c.x;
  }
  if (w != nullptr) emit(prev, w, inside);
}

std::uint32_t* DelaunayCells::start_chunk(const std::uint32_t* cells, std::uint32_t count,
                                          Scratch& s) const {
  if (s.chunk.slot.size() != ctx_.n) s.chunk.slot.assign(ctx_.n, 0);
  std::uint32_t* slot = s.chunk.slot.data();
  for (std::uint32_t k = 0; k < count; ++k) slot[cells[k]] = k + 1;
  return slot;
}

template <bool kWeighted>
bool DelaunayCells::boundary_chunk(const std::uint32_t* cells, std::uint32_t count, Stars& stars,
                                   Scratch& s, Moments* result) const {
  // As inner_chunk, over the tets with a chunk vertex (infinite ones included), each taken
  // once; then their Voronoi vertices placed inside or outside as in boundary_cell (from
  // infinite tets and single crossings, then across facets with the parity of their
  // crossings), and each Voronoi edge's piece inside the volume given to the chunk
  // vertices of its facet. False, with nothing reported, when a tet cannot be placed.
  // (Read through a local: the loops below store bytes, which may alias rs_'s members.)
  const std::uint8_t* is_boundary = rs_.is_boundary.data();
  Star& st = stars.new_range(ctx_);
  std::uint32_t* slot = start_chunk(cells, count, s);
  const std::uint32_t first = st.first;
  std::uint32_t* mark = st.mark.data();
  std::vector<std::uint32_t>& tets = st.tets;
  tets.clear();
  for (std::uint32_t seed = 0; seed < count; ++seed) {
    const std::uint32_t t0 = ctx_.dt.vertex_tet(cells[seed]);
    if (mark[t0] >= first) continue;
    mark[t0] = first + static_cast<std::uint32_t>(tets.size());
    tets.push_back(t0);
    for (std::size_t q = tets.size() - 1; q < tets.size(); ++q) {
      const std::uint32_t t = tets[q];
      unsigned in_mask = 0;  // the tet's chunk vertices
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t w = ctx_.dt.tet_vertex(t, k);
        in_mask |= w != Delaunay3::kInfinite && slot[w] != 0 ? 1u << k : 0u;
      }
      for (int f = 0; f < 4; ++f) {
        if ((in_mask & ~(1u << f)) == 0) continue;  // no chunk vertex on this facet
        const std::uint32_t t2 = ctx_.dt.tet_adjacent(t, f);
        if (mark[t2] >= first) continue;
        mark[t2] = first + static_cast<std::uint32_t>(tets.size());
        tets.push_back(t2);
        ctx_.dt.prefetch_tet(t2);
      }
    }
  }
  const std::size_t m = tets.size();
  st.next = first + static_cast<std::uint32_t>(m);
  const auto clear_slots = [&] {
    for (std::uint32_t k = 0; k < count; ++k) slot[cells[k]] = 0;
  };
  // The crossings of each facet of a finite tet whose three vertices are boundary sites
  // (looked up once per facet: the parity crosses facets with no chunk vertex too), and
  // the placement.
  std::vector<std::int8_t>& flag = s.flag;
  flag.assign(m, -1);
  std::vector<const EdgeCrossings*>& fx = s.fx;
  fx.assign(4 * m, nullptr);
  std::vector<std::uint8_t>& known = s.known;
  known.assign(4 * m, 0);
  std::vector<std::uint32_t>& queue = s.queue;
  queue.clear();
  const auto place = [&](std::size_t q, int v) {
    if (flag[q] == -1) {
      flag[q] = static_cast<std::int8_t>(v);
      queue.push_back(static_cast<std::uint32_t>(q));
    } else if (flag[q] != v) {
      clear_slots();
      internal_error("Voronoi vertex of tet " + std::to_string(tets[q]) +
                     " placed both inside and outside (cells from " + std::to_string(cells[0]) +
                     ")");
    }
  };
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t t = tets[q];
    const std::uint32_t w[4] = {ctx_.dt.tet_vertex(t, 0), ctx_.dt.tet_vertex(t, 1),
                                ctx_.dt.tet_vertex(t, 2), ctx_.dt.tet_vertex(t, 3)};
    if (w[3] == Delaunay3::kInfinite) {
      place(q, 0);
      continue;
    }
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t a = w[f == 0 ? 1 : 0], b = w[f <= 1 ? 2 : 1], c = w[f <= 2 ? 3 : 2];
      if (!known[4 * q + f]) {
        const EdgeCrossings* x = nullptr;
        if (is_boundary[a] && is_boundary[b] && is_boundary[c]) x = rs_.find_crossings(a, b, c);
        fx[4 * q + f] = x;
        const std::uint32_t t2 = ctx_.dt.tet_adjacent(t, f);
        if (mark[t2] >= first) {
          const std::size_t k2 = 4 * std::size_t{mark[t2] - first} +
                                 static_cast<std::size_t>(ctx_.dt.tet_adjacent_facet(t, f));
          fx[k2] = x;
          known[k2] = 1;
        }
      }
      const EdgeCrossings* x = fx[4 * q + f];
      const std::uint32_t nb_cross = x ? x->count : 0;
      if (ctx_.infinite(ctx_.dt.tet_adjacent(t, f))) {
        place(q, static_cast<int>(nb_cross & 1));
      } else if (nb_cross == 1) {
        int l0 = 0;
        while (w[l0] != x->s[0]) ++l0;
        const bool even = w[kFaceOther[l0][f][0]] == x->s[1];
        place(q, (even ? x->sigma : -x->sigma) > 0 ? 1 : 0);
      }
    }
  }
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const std::uint32_t q = queue[h];
    const std::uint32_t t = tets[q];
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t t2 = ctx_.dt.tet_adjacent(t, f);
      if (mark[t2] < first) continue;  // (a facet with no chunk vertex)
      const EdgeCrossings* x = fx[4 * q + f];
      const int parity = x ? static_cast<int>(x->count & 1) : 0;
      place(mark[t2] - first, flag[q] ^ parity);
    }
  }
  if (queue.size() != m) {
    clear_slots();
    return false;
  }
  // The non-boundary sites of the tets take their flags.
  if (s.site_mark.size() != ctx_.n || s.site_gen == 0xffffffffu) {
    s.site_mark.assign(ctx_.n, 0);
    s.site_gen = 0;
  }
  const std::uint32_t gen = ++s.site_gen;
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t t = tets[q];
    if (ctx_.infinite(t)) continue;
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t v = ctx_.dt.tet_vertex(t, k);
      if (is_boundary[v] || s.site_mark[v] == gen) continue;
      s.site_mark[v] = gen;
      s.first_layer.emplace_back(v, flag[q]);
    }
  }
  // The pieces, each Voronoi edge from its finite tet of larger position (or its only one).
  PieceAcc<kWeighted>* sums;
  if constexpr (kWeighted) {
    s.chunk.moments.assign(count, Moments{});
    sums = s.chunk.moments.data();
    if (ctx_.callback_density) thread_density_batch().begin(*ctx_.callback_density);
  } else {
    s.chunk.sums.assign(count, PieceSums{});
    sums = s.chunk.sums.data();
  }
  if (s.chunk.c.size() < m) s.chunk.c.resize(m);
  std::array<double, 3>* cc = s.chunk.c.data();
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t t = tets[q];
    if (ctx_.infinite(t)) continue;
    const std::uint32_t v[4] = {ctx_.dt.tet_vertex(t, 0), ctx_.dt.tet_vertex(t, 1),
                                ctx_.dt.tet_vertex(t, 2), ctx_.dt.tet_vertex(t, 3)};
    const double* c = circumcentre(t, v, s.circ);
    cc[q] = {c[0], c[1], c[2]};
  }
  for (std::size_t q = 0; q < m; ++q) {
    const std::uint32_t t = tets[q];
    if (ctx_.infinite(t)) continue;
    const std::uint32_t v[4] = {ctx_.dt.tet_vertex(t, 0), ctx_.dt.tet_vertex(t, 1),
                                ctx_.dt.tet_vertex(t, 2), ctx_.dt.tet_vertex(t, 3)};
    unsigned in_mask = 0;
    for (int k = 0; k < 4; ++k) in_mask |= slot[v[k]] != 0 ? 1u << k : 0u;
    for (int f = 0; f < 4; ++f) {
      const unsigned facet_mask = in_mask & ~(1u << f);
      if (facet_mask == 0) continue;
      const std::uint32_t t2 = ctx_.dt.tet_adjacent(t, f);
      const bool infinite2 = ctx_.infinite(t2);
      const std::size_t q2 = mark[t2] - first;
      if (!infinite2 && q2 > q) continue;
      try {
        inside_pieces(v, f, cc[q].data(), flag[q] != 0, infinite2 ? nullptr : cc[q2].data(),
                      flag[q2] != 0, fx[4 * q + f], [&](const double* a, const double* b) {
                        for (int k = 0; k < 4; ++k) {
                          if ((facet_mask >> k & 1u) == 0) continue;
                          const double* px = ctx_.apex(v[k]);
                          add_piece<kWeighted>(v[k], v[kFaceOther[k][f][0]], v[kFaceOther[k][f][1]],
                                               rel(a, px), rel(b, px), sums[slot[v[k]] - 1]);
                        }
                      });
      } catch (...) {
        clear_slots();
        throw;
      }
    }
  }
  if (kWeighted && ctx_.callback_density) {
    try {
      thread_density_batch().flush();
    } catch (...) {
      clear_slots();
      throw;
    }
  }
  for (std::uint32_t k = 0; k < count; ++k) {
    slot[cells[k]] = 0;
    if constexpr (kWeighted) {
      result[k].volume += sums[k].volume;
      result[k].mass += sums[k].mass;
      for (int c = 0; c < 3; ++c) result[k].moment[c] += sums[k].moment[c];
      result[k].energy += sums[k].energy;
    } else {
      sums[k].add_to(result[k]);
    }
  }
  return true;
}

void DelaunayCells::add_piece_numbered(const std::uint32_t* v, std::uint32_t q, int f, int lk,
                                       const std::uint32_t* v2, std::uint32_t q2,
                                       std::uint32_t cell, const double* c, const double* c2,
                                       std::uint32_t* edge, ChunkNodes& nodes) const {
  DensityBatch& batch = thread_density_batch();
  const std::uint64_t epoch = batch.epoch();
  const std::uint32_t i = v[lk];
  const double* px = ctx_.site(i);
  const int lj = kFaceOther[lk][f][0], lkk = kFaceOther[lk][f][1];
  const std::uint32_t vj = v[lj], vk = v[lkk];
  int lk2 = 0, lj2 = 0, lkk2 = 0;  // the same sites in tet q2
  for (int l = 0; l < 4; ++l) {
    lk2 = v2[l] == i ? l : lk2;
    lj2 = v2[l] == vj ? l : lj2;
    lkk2 = v2[l] == vk ? l : lkk2;
  }
  // f_ab from the sites in the order of their ids.
  const auto foot_point = [&](std::uint32_t a, std::uint32_t b, double* p) {
    const double* pa = ctx_.site(std::min(a, b));
    const double* pb = ctx_.site(std::max(a, b));
    for (int k = 0; k < 3; ++k) p[k] = 0.5 * (pa[k] + pb[k]);
  };
  const auto tet = [&](std::uint32_t t, const double* cc) -> ChunkNodes::Tet& {
    ChunkNodes::Tet& r = nodes.tets[t];
    if (r.epoch != epoch) {
      r.epoch = epoch;
      r.vertex = batch.node([&](double* p) {
        for (int k = 0; k < 3; ++k) p[k] = cc[k];
      });
      for (std::uint32_t& e : r.half) e = kNone;
      for (std::uint32_t& e : r.mid) e = kNone;
    }
    return r;
  };
  const auto half = [&](ChunkNodes::Tet& r, int l, const double* cc) {
    std::uint32_t& e = r.half[l];
    if (e == kNone) {
      e = batch.node([&](double* p) {
        for (int k = 0; k < 3; ++k) p[k] = 0.5 * (px[k] + cc[k]);
      });
    }
    return e;
  };
  const auto face_vertex = [&](ChunkNodes::Tet& r, const std::uint32_t* tv, int l, int l2,
                               const double* cc) {
    std::uint32_t& e = r.mid[ChunkNodes::kPair[l][l2]];
    if (e == kNone) {
      e = batch.node([&](double* p) {
        foot_point(tv[l], tv[l2], p);
        for (int k = 0; k < 3; ++k) p[k] = 0.5 * (p[k] + cc[k]);
      });
    }
    return e;
  };
  // The foot's nodes: f_ij and (x + f_ij) / 2.
  const auto feet = [&](std::uint32_t j, std::uint32_t* out) {
    const std::uint32_t a = std::min(i, j), b = std::max(i, j);
    ChunkNodes::Foot& e = nodes.foot(a, b);
    if (e.a != a || e.b != b || e.epoch != epoch) {
      e.a = a;
      e.b = b;
      e.epoch = epoch;
      e.full = batch.node([&](double* p) { foot_point(a, b, p); });
      e.half[0] = e.half[1] = kNone;
    }
    std::uint32_t& h = e.half[i == a ? 0 : 1];
    if (h == kNone) {
      h = batch.node([&](double* p) {
        foot_point(a, b, p);
        for (int k = 0; k < 3; ++k) p[k] = 0.5 * (px[k] + p[k]);
      });
    }
    out[0] = e.full;
    out[1] = h;
  };
  std::uint32_t& site = nodes.site[cell];
  if (site == kNone) {
    site = batch.node([&](double* p) {
      for (int k = 0; k < 3; ++k) p[k] = px[k];
    });
  }
  if (*edge == kNone) {
    *edge = batch.node([&](double* p) {
      for (int k = 0; k < 3; ++k) p[k] = 0.5 * (c[k] + c2[k]);
    });
  }
  ChunkNodes::Tet& tu = tet(q, c);
  ChunkNodes::Tet& tw = tet(q2, c2);
  std::uint32_t fj[2], fk[2];
  feet(vj, fj);
  feet(vk, fk);
  ChunkNodes::Pair p;
  p.cell = cell;
  p.u = 4 * q + static_cast<std::uint32_t>(lk);
  p.w = 4 * q2 + static_cast<std::uint32_t>(lk2);
  p.j = vj;
  p.k = vk;
  std::uint32_t* n = p.node;
  n[0] = site;
  n[1] = fj[0];
  n[2] = fj[1];
  n[3] = fk[0];
  n[4] = fk[1];
  n[5] = tu.vertex;
  n[6] = half(tu, lk, c);
  n[7] = tw.vertex;
  n[8] = half(tw, lk2, c2);
  n[9] = face_vertex(tu, v, lk, lj, c);
  n[10] = face_vertex(tw, v2, lk2, lj2, c2);
  n[11] = face_vertex(tw, v2, lk2, lkk2, c2);
  n[12] = face_vertex(tu, v, lk, lkk, c);
  n[13] = *edge;
  nodes.pairs.push_back(p);
}

void DelaunayCells::integrate_pairs(ChunkNodes& nodes, const Rel* cr, const std::uint32_t* cells,
                                    Moments* sums) const {
  const double* f = thread_density_batch().values();
  for (const ChunkNodes::Pair& p : nodes.pairs) {
    const double* px = ctx_.site(cells[p.cell]);
    const Foot hj = foot(ctx_.site(p.j), px), hk = foot(ctx_.site(p.k), px);
    const double* u = cr[p.u].y;
    const double* w = cr[p.w].y;
    const std::uint32_t* n = p.node;
    // The cones (x; hj, u, w) and (x; hk, w, u) (add_piece), values in P2Weights' order.
    const double f1[10] = {f[n[0]], f[n[1]], f[n[5]], f[n[7]],  f[n[2]],
                           f[n[6]], f[n[8]], f[n[9]], f[n[10]], f[n[13]]};
    const double f2[10] = {f[n[0]], f[n[3]], f[n[7]],  f[n[5]],  f[n[4]],
                           f[n[8]], f[n[6]], f[n[11]], f[n[12]], f[n[13]]};
    add_tet_p2(f1, hj.y, u, w, sums[p.cell]);
    add_tet_p2(f2, hk.y, w, u, sums[p.cell]);
  }
  nodes.pairs.clear();
}

template <bool kWeighted>
void DelaunayCells::inner_chunk(const std::uint32_t* cells, std::uint32_t count, Stars& stars,
                                Scratch& s, Moments* result) const {
  // The tets with a vertex in the chunk, breadth first from each cell's vertex_tet through
  // the facets that have one (every star is connected through such facets), each taken
  // once: its circumcentre, relative to each chunk vertex. A Voronoi edge (a facet with a
  // chunk vertex, between tets at positions q2 < q) is taken when tet q is expanded, for
  // each chunk vertex of the facet. The order is a function of the chunk alone.
  Star& st = stars.new_range(ctx_);
  std::uint32_t* slot = start_chunk(cells, count, s);
  const std::uint32_t first = st.first;
  std::uint32_t* mark = st.mark.data();
  PieceAcc<kWeighted>* sums;
  bool numbered = false;  // numbered P2 nodes (add_piece_numbered)
  if constexpr (kWeighted) {
    s.chunk.moments.assign(count, Moments{});
    sums = s.chunk.moments.data();
    if (ctx_.callback_density) {
      numbered = ctx_.callback_density->rule == Density3::Rule::kQuadratic;
      thread_density_batch().begin(*ctx_.callback_density, numbered);
      if (numbered) {
        s.chunk.nodes.site.assign(count, kNone);
        s.chunk.nodes.pairs.clear();
      }
    }
  } else {
    s.chunk.sums.assign(count, PieceSums{});
    sums = s.chunk.sums.data();
  }
  // st.tets, s.chunk.c and s.chunk.rel serve as fixed buffers (grown by doubling).
  std::vector<std::uint32_t>& tets = st.tets;
  if (tets.size() < 64) tets.resize(64);
  std::uint32_t cap = static_cast<std::uint32_t>(tets.size());
  if (s.chunk.c.size() < cap) s.chunk.c.resize(cap);
  if (s.chunk.rel.size() < 4 * std::size_t{cap}) s.chunk.rel.resize(4 * std::size_t{cap});
  if (numbered && s.chunk.nodes.tets.size() < cap) s.chunk.nodes.tets.resize(cap);
  std::uint32_t* tp = tets.data();
  std::array<double, 3>* cc = s.chunk.c.data();
  Rel* cr = s.chunk.rel.data();
  std::uint32_t nb_tets = 0;
  const auto room_for = [&](std::uint32_t extra) {
    if (nb_tets + extra <= cap) return;
    cap *= 2;
    tets.resize(cap);
    s.chunk.c.resize(cap);
    s.chunk.rel.resize(4 * std::size_t{cap});
    if (numbered) s.chunk.nodes.tets.resize(cap);
    tp = tets.data();
    cc = s.chunk.c.data();
    cr = s.chunk.rel.data();
  };
  for (std::uint32_t seed = 0; seed < count; ++seed) {
    const std::uint32_t t0 = ctx_.dt.vertex_tet(cells[seed]);
    if (mark[t0] >= first) continue;
    room_for(1);
    mark[t0] = first + nb_tets;
    tp[nb_tets++] = t0;
    for (std::uint32_t q = nb_tets - 1; q < nb_tets; ++q) {
      const std::uint32_t t = tp[q];
      // The sites of the next tet in the queue (its record was prefetched when it was found).
      if (q + 1 < nb_tets) {
        const std::uint32_t tn = tp[q + 1];
        for (int k = 0; k < 4; ++k) {
          const std::uint32_t w = ctx_.dt.tet_vertex(tn, k);
          if (w != Delaunay3::kInfinite) __builtin_prefetch(ctx_.site(w));
          __builtin_prefetch(mark + ctx_.dt.tet_adjacent(tn, k));
        }
      }
      const std::uint32_t v[4] = {ctx_.dt.tet_vertex(t, 0), ctx_.dt.tet_vertex(t, 1),
                                  ctx_.dt.tet_vertex(t, 2), ctx_.dt.tet_vertex(t, 3)};
      if (v[3] == Delaunay3::kInfinite) {  // (an infinite tet has kInfinite as vertex 3)
        const std::uint32_t i = slot[v[0]] != 0 ? v[0] : slot[v[1]] != 0 ? v[1] : v[2];
        internal_error("inner cell " + std::to_string(i) + " is unbounded");
      }
      std::uint32_t in[4];
      unsigned in_mask = 0;
      for (int k = 0; k < 4; ++k) {
        in[k] = slot[v[k]];
        in_mask |= in[k] != 0 ? 1u << k : 0u;
      }
      const double* c = circumcentre(t, v, s.circ);
      cc[q] = {c[0], c[1], c[2]};
      for (int k = 0; k < 4; ++k) {
        if (in[k] != 0) cr[4 * std::size_t{q} + k] = rel(c, ctx_.site(v[k]));
      }
      room_for(4);
      for (int f = 0; f < 4; ++f) {
        const unsigned facet_mask = in_mask & ~(1u << f);  // the facet's chunk vertices
        if (facet_mask == 0) continue;
        const std::uint32_t t2 = ctx_.dt.tet_adjacent(t, f);
        const std::uint32_t mk = mark[t2];
        if (mk < first) {
          mark[t2] = first + nb_tets;
          tp[nb_tets++] = t2;
          ctx_.dt.prefetch_tet(t2);
          s.circ.prefetch(t2);
        } else if (mk - first < q) {
          const double* c2 = cc[mk - first].data();
          std::uint32_t edge = kNone;  // (numbered)
          for (int k = 0; k < 4; ++k) {
            if ((facet_mask >> k & 1u) == 0) continue;
            const double* px = ctx_.site(v[k]);
            if constexpr (kWeighted) {
              if (numbered) {
                const std::uint32_t v2[4] = {ctx_.dt.tet_vertex(t2, 0), ctx_.dt.tet_vertex(t2, 1),
                                             ctx_.dt.tet_vertex(t2, 2), ctx_.dt.tet_vertex(t2, 3)};
                add_piece_numbered(v, q, f, k, v2, mk - first, in[k] - 1, cc[q].data(), c2, &edge,
                                   s.chunk.nodes);
                DensityBatch& batch = thread_density_batch();
                if (batch.staged_full()) {
                  batch.evaluate_staged();
                  integrate_pairs(s.chunk.nodes, cr, cells, sums);
                }
                continue;
              }
            }
            const std::uint32_t vj = v[kFaceOther[k][f][0]], vk = v[kFaceOther[k][f][1]];
            add_piece<kWeighted>(v[k], vj, vk, cr[4 * std::size_t{q} + k], rel(c2, px),
                                 sums[in[k] - 1]);
          }
        }
      }
    }
  }
  st.next = first + nb_tets;
  if constexpr (kWeighted) {
    if (numbered) {
      thread_density_batch().evaluate_staged();
      integrate_pairs(s.chunk.nodes, cr, cells, sums);
    } else if (ctx_.callback_density) {
      thread_density_batch().flush();
    }
  }
  for (std::uint32_t k = 0; k < count; ++k) {
    slot[cells[k]] = 0;
    if constexpr (kWeighted) {
      result[k] = sums[k];
    } else {
      result[k] = Moments{};
      sums[k].add_to(result[k]);
    }
  }
}

template bool DelaunayCells::boundary_chunk<false>(const std::uint32_t*, std::uint32_t, Stars&,
                                                   Scratch&, Moments*) const;
template bool DelaunayCells::boundary_chunk<true>(const std::uint32_t*, std::uint32_t, Stars&,
                                                  Scratch&, Moments*) const;
template void DelaunayCells::inner_chunk<false>(const std::uint32_t*, std::uint32_t, Stars&,
                                                Scratch&, Moments*) const;
template void DelaunayCells::inner_chunk<true>(const std::uint32_t*, std::uint32_t, Stars&,
                                               Scratch&, Moments*) const;

void DelaunayCells::global_flags(std::vector<std::int8_t>& flag) const {
  const std::uint32_t slots = ctx_.dt.nb_tet_slots();
  flag.assign(slots, -1);
  std::vector<std::uint32_t> queue;
  for (std::uint32_t t = 0; t < slots; ++t) {
    if (!ctx_.dt.is_free(t) && ctx_.infinite(t)) {
      flag[t] = 0;
      queue.push_back(t);
    }
  }
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const std::uint32_t t = queue[h];
    for (int f = 0; f < 4; ++f) {
      std::uint32_t w[3];
      int q = 0;
      bool between_boundary_cells = true;
      for (int k = 0; k < 4; ++k) {
        if (k == f) continue;
        w[q] = ctx_.dt.tet_vertex(t, k);
        between_boundary_cells =
            between_boundary_cells && w[q] != Delaunay3::kInfinite && rs_.is_boundary[w[q]];
        ++q;
      }
      const EdgeCrossings* x =
          between_boundary_cells ? rs_.find_crossings(w[0], w[1], w[2]) : nullptr;
      const auto want =
          static_cast<std::int8_t>(flag[t] ^ (x ? static_cast<int>(x->count & 1) : 0));
      const std::uint32_t t2 = ctx_.dt.tet_adjacent(t, f);
      if (flag[t2] == -1) {
        flag[t2] = want;
        queue.push_back(t2);
      } else if (flag[t2] != want) {
        internal_error("the crossings of the Voronoi edges with the surface are inconsistent");
      }
    }
  }
}

void DelaunayCells::decide_status(
    const std::vector<std::pair<std::uint32_t, std::int8_t>>& first_layer, Stars& stars) {
  status_.assign(ctx_.n, -1);
  std::vector<std::uint32_t> queue;
  for (const auto& [v, fl] : first_layer) {
    if (status_[v] == -1) {
      status_[v] = fl;
      if (fl == 0) queue.push_back(v);
    } else if (status_[v] != fl) {
      internal_error("site " + std::to_string(v) + " placed both inside and outside");
    }
  }
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const NeighborList nb = stars.neighbors(ctx_, queue[h]);
    for (std::uint32_t q = 0; q < nb.count; ++q) {
      const std::uint32_t w = nb.id[q];
      if (rs_.is_boundary[w]) continue;
      if (status_[w] == -1) {
        status_[w] = 0;
        queue.push_back(w);
      } else if (status_[w] == 1) {
        internal_error("neighbouring cells " + std::to_string(queue[h]) + " and " +
                       std::to_string(w) + " placed outside and inside");
      }
    }
  }
  for (std::uint32_t v = 0; v < ctx_.n; ++v) {
    if (status_[v] == -1 && !rs_.is_boundary[v] && ctx_.dt.vertex_tet(v) != Delaunay3::kNoTet)
      status_[v] = 1;
  }
}

}  // namespace clip3

}  // namespace voroclip
