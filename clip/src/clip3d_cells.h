// The cells of the 3D clipped Voronoi diagram straight from the Delaunay triangulation
// (clip3d_cells.cpp; Yan et al. 2011, sec. 4, with the boundary cells integrated by the
// divergence theorem): DelaunayCells reads the restricted surface (clip3d_surface.h) and
// integrates, places and exports the cells.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "clip3d_internal.h"
#include "clip3d_surface.h"

namespace voroclip {

namespace clip3 {

// A point relative to a site: y = (x - p_i) and |y|^2.
struct Rel {
  double y[3], yy;
};
inline Rel rel(const double* x, const double* pi) {
  Rel r;
  for (int k = 0; k < 3; ++k) r.y[k] = x[k] - pi[k];
  r.yy = (r.y[0] * r.y[0] + r.y[1] * r.y[1]) + r.y[2] * r.y[2];
  return r;
}

// Sums over the Voronoi edge pieces of a cell, scaled: volume 6 V, first moment 24 M,
// energy 60 E (see add_edge_piece).
struct PieceSums {
  double v = 0, m[3] = {0, 0, 0}, e = 0;
  void add_to(Moments& r) const {
    r.volume += v * (1.0 / 6);
    for (int k = 0; k < 3; ++k) r.moment[k] += m[k] * (1.0 / 24);
    r.energy += e * (1.0 / 60);
  }
};

// The foot of bisector(i, j) seen from p_i: h = (p_j - p_i) / 2 and hh3 = 3 |h|^2. Every
// point y of the bisector has h . y = |h|^2 (add_edge_piece).
struct Foot {
  double y[3], hh3;
};
inline Foot foot(const double* pj, const double* pi) {
  Foot f;
  for (int k = 0; k < 3; ++k) f.y[k] = 0.5 * (pj[k] - pi[k]);
  f.hh3 = 3 * ((f.y[0] * f.y[0] + f.y[1] * f.y[1]) + f.y[2] * f.y[2]);
  return f;
}

// The feet of a cell's neighbours, direct-mapped by site id (a neighbour is in about six
// star tets of the cell; a slot holds the last site mapped to it). Per cell, on the stack.
class FootCache {
 public:
  static constexpr std::uint32_t kSlots = 64;
  FootCache() {
    for (std::uint32_t& s : site_) s = kNone;
  }
  // The foot of site v (at pv) seen from pi.
  const Foot& get(std::uint32_t v, const double* pv, const double* pi) {
    const std::uint32_t slot = v & (kSlots - 1);
    if (site_[slot] != v) {
      site_[slot] = v;
      foot_[slot] = foot(pv, pi);
    }
    return foot_[slot];
  }

 private:
  std::uint32_t site_[kSlots];
  Foot foot_[kSlots];
};

// A piece [P, Q] of the Voronoi edge dual to Delaunay triangle (i, j, k), P -> Q running
// counter-clockwise around p_j - p_i (so clockwise around p_k - p_i), with u = P - p_i,
// w = Q - p_i (Rel: with their squared norms) and the feet hj, hk of bisectors (i, j) and
// (i, k). It bounds the facets of cell i on those bisectors: its share of the cones from
// p_i over them is
//   cone(hj, u, w) - cone(hk, u, w)
// (add_cone, outward: the facet on bisector(i, j) is counter-clockwise around its outward
// normal p_j - p_i). With a = h . (u x w), s = u + w, q = |u|^2 + |w|^2 + u . w, a cone has
// volume a / 6, moment a (h + s) / 24 and energy a (|h|^2 + h . s + q) / 60, where
// h . s = 2 |h|^2 since u and w lie on the bisector (the piece lies on both): energy
// a (3 |h|^2 + q) / 60.
inline void add_edge_piece(const Foot& hj, const Foot& hk, const Rel& u, const Rel& w,
                           PieceSums& r) {
  const double a0 = u.y[0], a1 = u.y[1], a2 = u.y[2];
  const double b0 = w.y[0], b1 = w.y[1], b2 = w.y[2];
  const double c0 = a1 * b2 - a2 * b1, c1 = a2 * b0 - a0 * b2, c2 = a0 * b1 - a1 * b0;
  const double s0 = a0 + b0, s1 = a1 + b1, s2 = a2 + b2;
  const double q = (u.yy + w.yy) + ((a0 * b0 + a1 * b1) + a2 * b2);
  const double j0 = hj.y[0], j1 = hj.y[1], j2 = hj.y[2];
  const double k0 = hk.y[0], k1 = hk.y[1], k2 = hk.y[2];
  const double aj = (j0 * c0 + j1 * c1) + j2 * c2;
  const double ak = (k0 * c0 + k1 * c1) + k2 * c2;
  const double d = aj - ak;
  r.v += d;
  r.m[0] += (aj * j0 - ak * k0) + d * s0;
  r.m[1] += (aj * j1 - ak * k1) + d * s1;
  r.m[2] += (aj * j2 - ak * k2) + d * s2;
  r.e += (aj * hj.hh3 - ak * hk.hh3) + d * q;
}

// Circumcentres of the Delaunay tets one thread's cells have met, direct-mapped by tet
// slot. Cells go in Hilbert order of their sites, so a tet's four cells mostly come close
// together and its circumcentre is computed about once, from sites the cells read anyway:
// this replaced a pass over all tets into a 24-byte-per-tet array (156 MB at 10^6 sites)
// whose random reads of the sites cost more than the cells themselves.
class CircumcentreCache {
 public:
  struct Entry {
    std::uint32_t tet;
    double x[3];
  };
  static constexpr std::uint32_t kSlots = std::uint32_t{1} << 15;  // 1 MB
  // The entry for tet t (its x is valid when entry.tet == t).
  Entry& entry(std::uint32_t t) { return entries_[t & (kSlots - 1)]; }
  void prefetch(std::uint32_t t) const { __builtin_prefetch(&entries_[t & (kSlots - 1)]); }

 private:
  std::vector<Entry> entries_ = std::vector<Entry>(kSlots, Entry{kNone, {0, 0, 0}});
};

// The P2 nodes of an inner chunk's cones under Density3::Rule::kQuadratic, numbered in the
// thread's DensityBatch (its numbered nodes) from what defines them, so that the cells of a
// chunk share them (about 1.4 nodes per cone, against 3.3 found by their bits): a Voronoi
// vertex (chunk tet q: its circumcentre c, shared by 4 cells); the foot of bisector(i, j)
// (the midpoint f_ij of the sites, 2 cells); per tet and pair of its vertices, the midpoint
// (f_ij + c) / 2 (the 2 cones of face (i, j) at c, in cells i and j); per Voronoi edge,
// the midpoint of its circumcentres (its 2 cones in each of its 3 cells). Per cell i (site
// x): x, and the midpoints (x + c) / 2 and (x + f_ij) / 2. Each is computed from the same
// operands by every cone that has it (the circumcentres' bits, the sites in the order of
// their ids), so the same bits. A position is valid while its epoch is the batch's (a
// flush starts a new one).
struct ChunkNodes {
  struct Tet {
    std::uint64_t epoch;
    std::uint32_t vertex;   // c
    std::uint32_t half[4];  // [l]: (x + c) / 2 for the cell of local vertex l
    std::uint32_t mid[6];   // [kPair[l][l2]]: (f + c) / 2 for local vertices l, l2
  };
  static constexpr int kPair[4][4] = {{-1, 0, 1, 2}, {0, -1, 3, 4}, {1, 3, -1, 5}, {2, 4, 5, -1}};
  struct Foot {
    std::uint64_t epoch;
    std::uint32_t a, b;           // sites a < b
    std::uint32_t full, half[2];  // f_ab; (p_a + f_ab) / 2, (p_b + f_ab) / 2
  };
  // The feet: direct-mapped by (a, b) (a slot keeps the last pair; a pair pushed out is
  // pushed again, as a new node of the same bits).
  static constexpr std::uint32_t kFootSlots = 4096;
  Foot& foot(std::uint32_t a, std::uint32_t b) {
    return feet[(a * 0x9E3779B1u ^ b * 0x85EBCA77u) >> 20];  // the top 12 bits: kFootSlots
  }
  // A piece's two cones in cell `cell` (chunk slot) with neighbours j, k (sites): u, w
  // the positions of the piece's ends relative to the site in the chunk's Rel array, and
  // the nodes x, f_j, (x + f_j) / 2, f_k, (x + f_k) / 2, c_u, (x + c_u) / 2, c_w,
  // (x + c_w) / 2, (f_j + c_u) / 2, (f_j + c_w) / 2, (f_k + c_w) / 2, (f_k + c_u) / 2,
  // (c_u + c_w) / 2. Integrated (integrate_pairs) once their nodes are evaluated.
  struct Pair {
    std::uint32_t cell, u, w, j, k;
    std::uint32_t node[14];
  };
  std::vector<Tet> tets;            // per chunk tet
  std::vector<std::uint32_t> site;  // per chunk cell: its node (kNone: not yet)
  std::vector<Pair> pairs;
  std::vector<Foot> feet = std::vector<Foot>(kFootSlots, Foot{0, kNone, kNone, 0, {0, 0}});
};

// Local numbering of the Voronoi edges around a tet's vertex: for vertex li of a positive
// tet (Delaunay3) and a facet f != li, kFaceOther[li][f] = {lj, lk}, the other two vertices
// of facet f, so that (li, lj, lk, f) is an even permutation of (0, 1, 2, 3). Then the
// Voronoi edge dual to that facet, from this tet's circumcentre to the next tet's across
// f, runs counter-clockwise around p_lj - p_li (clip3d_cells.cpp).
extern const std::int8_t kFaceOther[4][4][2];
// Inner and boundary cells from the Delaunay triangulation, with the restricted surface
// (RestrictedSurface) for the boundary cells. Parallel loops (clip3d.cpp) give each thread
// a Scratch of its own and the thread's Stars.
class DelaunayCells {
 public:
  // One thread's scratch.
  struct Scratch {
    CircumcentreCache circ;
    // The placement of Voronoi vertices (boundary_cell, boundary_chunk): per tet of the
    // star or chunk, its flag; per tet and facet, the crossings of its Voronoi edge and
    // whether they are known (looked up from the tet across); the search's queue.
    std::vector<std::int8_t> flag;
    std::vector<const EdgeCrossings*> fx;
    std::vector<std::uint8_t> known;
    std::vector<std::uint32_t> queue;
    // Chunks: per site, its position in the chunk + 1 (0: not in it); per tet, its
    // circumcentre and that relative to each chunk vertex; per cell, its sums and its
    // moments (weighted).
    struct Chunk {
      std::vector<std::uint32_t> slot;
      std::vector<std::array<double, 3>> c;
      std::vector<Rel> rel;
      std::vector<PieceSums> sums;
      std::vector<Moments> moments;
      ChunkNodes nodes;  // weighted, kQuadratic (add_piece_numbered)
    } chunk;
    // (site, 0/1) for the non-boundary sites of the stars of boundary cells (decide_status),
    // each site once per cell or chunk (site_mark: the generation that reported it).
    std::vector<std::pair<std::uint32_t, std::int8_t>> first_layer;
    std::vector<std::uint32_t> site_mark;
    std::uint32_t site_gen = 0;
    std::vector<std::uint8_t> edge_done;  // voronoi_facets: per star tet and vertex
    // The results of a chunk, for the caller (clip3d.cpp).
    std::vector<Moments> results;
  };
  // A segment of the boundary of a cell's face on bisector(cell, across), for export.
  struct Segment {
    std::uint32_t across;
    double a[3], b[3];
  };

  DelaunayCells(const Clip3Context& ctx, const RestrictedSurface& rs) : ctx_(ctx), rs_(rs) {}

  // Boundary cell i: its Voronoi vertices placed inside or outside the volume (from its
  // own crossings, or from `global_flag` when given) and, unless it is clipped tet by tet,
  // its integrals added to r. Appends (site, 0/1) for the non-boundary sites of its star.
  // False when no Voronoi vertex of its star could be placed from its own crossings.
  // With `segments`, also the boundary segments of its faces on bisectors: each Voronoi
  // edge part, counter-clockwise around p_j - p_i for the face on bisector(i, j).
  bool boundary_cell(std::uint32_t i, const std::int8_t* global_flag, Stars& stars, Scratch& s,
                     Moments& r, std::vector<Segment>* segments = nullptr) const;
  // The boundary cells cells[0, count) (consecutive in Hilbert order, none clipped tet by
  // tet for its integrals) at once: result[k] (holding cells[k]'s surface share) gets the
  // rest. False when a Voronoi vertex could not be placed (then nothing is changed).
  template <bool kWeighted>
  bool boundary_chunk(const std::uint32_t* cells, std::uint32_t count, Stars& stars, Scratch& s,
                      Moments* result) const;
  // The inner cells cells[0, count) (consecutive in Hilbert order) at once: result[k] for
  // cells[k].
  template <bool kWeighted>
  void inner_chunk(const std::uint32_t* cells, std::uint32_t count, Stars& stars, Scratch& s,
                   Moments* result) const;
  // The Voronoi facets of inner cell c (keep_geometry), appended to res as one piece
  // (numbered `piece`), facing inwards.
  void voronoi_facets(std::uint32_t c, std::uint32_t piece, Stars& stars, Scratch& s,
                      CellOut& res) const;
  // The faces of boundary cell i from the surface (keep_geometry), appended to res as one
  // piece: its restricted polygons (`surface`: SurfaceRvd::compute's) and, per bisector,
  // the loops that bound its face there, all facing inwards. `flag`: the global flags
  // (global_flags).
  void boundary_faces(std::uint32_t i, std::uint32_t piece, const std::int8_t* flag,
                      const ClippedVoronoi3::Polygons& surface, Stars& stars, Scratch& s,
                      std::vector<Segment>& segments, CellOut& res) const;
  // Inside (1) / outside (0) for every Voronoi vertex (tet slot), by a breadth-first
  // search from the infinite tets, flipping with the parity of the crossings.
  void global_flags(std::vector<std::int8_t>& flag) const;
  // Every site inside (1) or outside (0) the volume, or -1 (boundary cells, and sites with
  // no cell), from the boundary cells' first_layer reports.
  void decide_status(const std::vector<std::pair<std::uint32_t, std::int8_t>>& first_layer,
                     Stars& stars);
  const std::vector<std::int8_t>& status() const { return status_; }

 private:
  // The circumcentre of finite tet t with vertices v[0..3] (as stored), through the cache:
  // Clip3Context::voronoi_point's bits.
  const double* circumcentre(std::uint32_t t, const std::uint32_t* v,
                             CircumcentreCache& cache) const {
    CircumcentreCache::Entry& e = cache.entry(t);
    if (e.tet != t) {
      std::uint32_t sorted[4] = {v[0], v[1], v[2], v[3]};
      sort4(sorted);
      ctx_.voronoi_point(sorted, e.x);
      e.tet = t;
    }
    return e.x;
  }
  // A chunk's start: s.chunk.slot[c] = k + 1 for c = cells[k] (the chunk functions clear
  // it). Returns s.chunk.slot's data.
  std::uint32_t* start_chunk(const std::uint32_t* cells, std::uint32_t count, Scratch& s) const;
  // A new generation of s.site_mark.
  std::uint32_t new_site_generation(Scratch& s) const;
  // The parts inside the volume of the Voronoi edge dual to facet f of tet t (vertices
  // tv[0..3]): from its circumcentre u (inside when in1) to the circumcentre w of the tet
  // across f (nullptr when infinite; inside when in2), with the edge's crossings x
  // (nullptr: none). Calls piece(a, b) for signed segments [a, b] whose sum is the inside
  // part: with crossings q_k, each entering (+1) or leaving (-1) the volume as the edge runs
  // from u to w, it is [u, w] if in1, plus [q_k, w] for an entering and [w, q_k] for a
  // leaving crossing; towards infinity, [q_k, u] or [u, q_k] (the segments' integrals are
  // additive along the line, so no order of the crossings is needed).
  template <class Piece>
  void inside_pieces(const std::uint32_t* tv, int f, const double* u, bool in1, const double* w,
                     bool in2, const EdgeCrossings* x, Piece&& piece) const;
  // inside_pieces for an edge crossed twice or more (out of line: rare): the segments, each
  // to be counted `times` times (negative: reversed).
  struct SignedSegment {
    const double* a;
    const double* b;
    int times;
  };
  void multi_crossing_segments(const std::uint32_t* tv, int f, const double* u, bool in1,
                               const double* w, bool in2, const EdgeCrossings& x,
                               std::vector<SignedSegment>& segments) const;
  // Cell i's (site px) share of the segment [a, b] of the Voronoi edge of sites i, vj, vk
  // (kFaceOther order: pj, pk): add_edge_piece, or the same cones weighted by the density.
  template <bool kWeighted>
  using PieceAcc = std::conditional_t<kWeighted, Moments, PieceSums>;
  // The piece's share of cell x's cones from px = ctx_.apex(x) (u, w relative to it), over
  // its facets on bisectors (x, j) and (x, k).
  template <bool kWeighted>
  void add_piece(std::uint32_t x, std::uint32_t j, std::uint32_t k, const Rel& u, const Rel& w,
                 PieceAcc<kWeighted>& acc) const {
    const Foot hj = foot_of(x, j), hk = foot_of(x, k);
    if constexpr (kWeighted) {
      // Deferred to the unit's DensityBatch::flush (thread_density_batch).
      const double* px = ctx_.apex(x);
      DensityBatch& batch = thread_density_batch();
      batch.add(px, hj.y, u.y, w.y, acc);
      batch.add(px, hk.y, w.y, u.y, acc);
    } else {
      add_edge_piece(hj, hk, u, w, acc);
    }
  }
  // The foot of bisector(x, j) seen from ctx_.apex(x) (foot() for a site that is not far).
  Foot foot_of(std::uint32_t x, std::uint32_t j) const {
    if (!ctx_.far(x)) return foot(ctx_.site(j), ctx_.site(x));
    Foot f;
    ctx_.foot(x, j, f.y);
    f.hh3 = 3 * ((f.y[0] * f.y[0] + f.y[1] * f.y[1]) + f.y[2] * f.y[2]);
    return f;
  }

  // add_piece<true> for an inner chunk under Density3::Rule::kQuadratic, with numbered
  // nodes (ChunkNodes): the Voronoi edge dual to facet f of chunk tet q (vertices v, its
  // circumcentre c) to chunk tet q2 (vertices v2, circumcentre c2), for the cell of its
  // vertex lk (chunk slot `cell`): its pair of cones recorded in nodes.pairs. `edge`: the
  // position of the edge's midpoint node, set by the first cell of the edge to push it
  // (start with kNone).
  void add_piece_numbered(const std::uint32_t* v, std::uint32_t q, int f, int lk,
                          const std::uint32_t* v2, std::uint32_t q2, std::uint32_t cell,
                          const double* c, const double* c2, std::uint32_t* edge,
                          ChunkNodes& nodes) const;
  // The recorded pairs' cones integrated (add_tet_p2, as add_piece<true>'s cones, in the
  // order recorded) into sums[cell], their nodes evaluated (the thread's DensityBatch's
  // values); cr: the chunk's Rel array, cells: the chunk's cells. Clears nodes.pairs.
  void integrate_pairs(ChunkNodes& nodes, const Rel* cr, const std::uint32_t* cells,
                       Moments* sums) const;

  Clip3Context ctx_;
  const RestrictedSurface& rs_;
  std::vector<std::int8_t> status_;  // per site (decide_status)
};

}  // namespace clip3

}  // namespace voroclip
