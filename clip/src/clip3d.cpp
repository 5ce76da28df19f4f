// The 3D clipped Voronoi diagram: Yan, Wang, Lévy & Liu, "Efficient computation of
// clipped Voronoi diagram for mesh generation", CAD 2011, section 4, with the boundary
// cells integrated by the divergence theorem instead of tet by tet.
//
// 1. Restricted surface (sec. 4.1; clip3d_surface.cpp): the cells of the boundary
//    vertices, then every boundary triangle clipped by the cells it meets, in parallel over
//    triangles. Cells with a non-empty restricted polygon are the boundary cells. Each
//    polygon gives its cell the cones over itself and over its edges on bisectors, and its
//    vertices where a Voronoi edge crosses the surface.
// 2. Boundary cells (clip3d_cells.cpp), in parallel, by chunks of consecutive cells in
//    Hilbert order (boundary_chunk): their Voronoi vertices are placed inside or outside the
//    volume from the crossings (exact, combinatorial), and the pieces of their Voronoi edges
//    inside the volume complete the boundary of cell ∩ volume, whose cones from the site
//    give volume, centroid and energy. A Voronoi edge that crosses the surface more than
//    once gives its inside parts as signed segments. Every boundary cell is clipped tet by
//    tet instead (sec. 4.2; clip3d_kernel.cpp) under tet_clipping or a density linear per
//    tet.
// 3. Other cells are wholly inside or outside; boundary cells decide their neighbours,
//    which spread it (clip3d_cells.cpp). Inner cells are the cones from the site over their
//    Voronoi facets, from the circumcentres of the Delaunay tets: per Delaunay facet around
//    the site, one Voronoi edge, two triangles (clip3d_cells.h, add_edge_piece). They go
//    in fixed chunks of consecutive cells in Hilbert order, each chunk's tets taken once
//    (inner_chunk). Under a density linear per tet inner cells are clipped tet by tet,
//    layer after layer from the boundary cells.
// Every loop writes per-triangle or per-cell slots and every reduction runs in index
// order: the result does not depend on the thread count.
//
// Units (clip3d_internal.h): a read-only Clip3Context; SurfaceRvd (step 1) leaves a
// RestrictedSurface that DelaunayCells (steps 2 and 3) reads; ConvexCell clips cells tet by
// tet. Each has its own per-thread scratch; run() below orchestrates them.
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "clip3d_cells.h"
#include "clip3d_internal.h"
#include "clip3d_kernel.h"
#include "clip3d_surface.h"

namespace voroclip {

using namespace clip3;

namespace {

constexpr std::size_t kInnerChunk = 1024;    // inner cells per chunk (run)
constexpr std::size_t kBoundaryChunk = 512;  // boundary cells per chunk (run)

}  // namespace

// One ClippedVoronoi3::compute(): the context, and where the results go (friend of
// ClippedVoronoi3).
struct Clip3Impl {
  Clip3Impl(const Domain3& d, const Delaunay3& t, const Clip3Options& o, ClippedVoronoi3& r,
            const std::uint32_t* input)
      : poll(o.progress, "clip3d"), ctx(d, t, o, &poll), out(r), input_index(input) {}

  detail::ClipPoll poll;  // progress and cancel (clip_poll.h)
  const Clip3Context ctx;
  ClippedVoronoi3& out;
  // Where cell i goes in the output (compute(domain, sites, n)), or nullptr: cell i.
  const std::uint32_t* input_index;

  void run();
};

void Clip3Impl::run() {
  using Clock = std::chrono::steady_clock;
  const std::uint32_t n = ctx.n;
  const Clip3Options& options = ctx.options;
  const bool weighted = ctx.weighted, linear_density = ctx.linear_density;
  out.surface_ = {};
  out.faces_ = {};
  out.surface_.polygon_begin.push_back(0);
  out.faces_.polygon_begin.push_back(0);
  // Per thread: its traversals of the triangulation (the surface pass's neighbour lists and
  // stars serve the cells again), the cells' scratch, a convex-cell kernel.
  tbb::enumerable_thread_specific<Stars> stars;
  tbb::enumerable_thread_specific<DelaunayCells::Scratch> cell_scratch;
  tbb::enumerable_thread_specific<ConvexCell> kernels([this] { return ConvexCell(ctx); });

  const auto t0 = Clock::now();
  poll.phase("surface", ctx.surface.nb_triangles());
  const RestrictedSurface rs =
      SurfaceRvd(ctx).compute(stars, ctx.keep_surface ? &out.surface_ : nullptr);
  const auto t1 = Clock::now();
  out.seconds_[0] = std::chrono::duration<double>(t1 - t0).count();

  // Cells in the order of their sites along a Hilbert curve: consecutive cells share most
  // of their Delaunay tets, which then come from cache whatever the tets' slot numbering
  // (the zoned Delaunay3 scatters neighbouring tets). The order depends on the input alone.
  // Under input_index the sites are numbered along it already (compute(domain, sites, n)
  // sorted them): index order is that order, and the same as here for sites in that order.
  std::vector<std::uint32_t> curve;
  if (!input_index) {
    curve.resize(n);
    std::iota(curve.begin(), curve.end(), 0u);
    hilbert_sort(ctx.site(0), 3, curve.data(), curve.data() + n);
  }
  const auto spatial = [&](auto&& take, std::vector<std::uint32_t>& order) {
    order.clear();
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t i = input_index ? k : curve[k];
      if (take(i)) order.push_back(i);
    }
  };

  // ---- Boundary cells (their circumcentres, like those of the inner cells, through the
  // per-thread caches: DelaunayCells::Scratch::circ).
  DelaunayCells dcells(ctx, rs);
  const std::size_t nb_boundary = rs.boundary_cells.size();
  poll.phase("boundary cells", nb_boundary);
  std::vector<std::uint32_t> order;
  spatial([&](std::uint32_t i) { return rs.is_boundary[i] != 0; }, order);
  std::vector<Moments> boundary_moments(nb_boundary);
  std::vector<std::uint8_t> unplaced(nb_boundary, 0);
  const auto one_cell = [&](std::uint32_t i, Stars& w, DelaunayCells::Scratch& s) {
    const std::uint32_t q = rs.boundary_slot[i];
    Moments r = rs.surface_moments[q];
    if (dcells.boundary_cell(i, nullptr, w, s, r)) {
      boundary_moments[q] = r;
    } else {
      unplaced[q] = 1;
    }
  };
  if (linear_density || options.tet_clipping) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 16), [&](const auto& range) {
      if (!poll.running()) return;
      Stars& w = stars.local();
      DelaunayCells::Scratch& s = cell_scratch.local();
      for (std::size_t h = range.begin(); h != range.end(); ++h) {
        one_cell(order[h], w, s);
      }
      poll.chunk(range.size());
    });
  } else {
    // In chunks as the inner cells (below); a chunk whose Voronoi vertices cannot all be
    // placed goes cell by cell (as every cell goes under a non-constant density or
    // tet_clipping, whose boundary cells need no pieces).
    const std::size_t nb_chunks = (order.size() + kBoundaryChunk - 1) / kBoundaryChunk;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb_chunks, 1), [&](const auto& range) {
      Stars& w = stars.local();
      DelaunayCells::Scratch& s = cell_scratch.local();
      s.results.resize(std::max(s.results.size(), kBoundaryChunk));
      for (std::size_t h = range.begin(); h != range.end(); ++h) {
        if (!poll.running()) return;
        const std::size_t begin = h * kBoundaryChunk;
        const std::size_t end = std::min(order.size(), begin + kBoundaryChunk);
        for (std::size_t k = begin; k < end; ++k) {
          s.results[k - begin] = rs.surface_moments[rs.boundary_slot[order[k]]];
        }
        const auto count = static_cast<std::uint32_t>(end - begin);
        const bool placed =
            weighted
                ? dcells.boundary_chunk<true>(order.data() + begin, count, w, s, s.results.data())
                : dcells.boundary_chunk<false>(order.data() + begin, count, w, s, s.results.data());
        if (placed) {
          for (std::size_t k = begin; k < end; ++k) {
            boundary_moments[rs.boundary_slot[order[k]]] = s.results[k - begin];
          }
        } else {
          for (std::size_t k = begin; k < end; ++k) one_cell(order[k], w, s);
        }
        poll.chunk(end - begin);
      }
    });
  }
  poll.check();
  std::vector<std::int8_t> global_flag;  // per tet slot, when a cell needs it
  if (std::find(unplaced.begin(), unplaced.end(), 1) != unplaced.end()) {
    dcells.global_flags(global_flag);
    Stars& w = stars.local();
    DelaunayCells::Scratch& s = cell_scratch.local();
    for (std::size_t q = 0; q < nb_boundary; ++q) {
      if (!unplaced[q]) continue;
      Moments r = rs.surface_moments[q];
      dcells.boundary_cell(rs.boundary_cells[q], global_flag.data(), w, s, r);
      boundary_moments[q] = r;
    }
  }
  // Tet by tet: every boundary cell under tet_clipping or a density linear per tet.
  const bool clip_all = linear_density || options.tet_clipping;
  std::vector<std::uint32_t> clipped;  // boundary slots
  std::uint32_t nb_multi = 0;
  for (std::size_t q = 0; q < nb_boundary; ++q) {
    nb_multi += rs.multi_crossed[rs.boundary_cells[q]] != 0 ? 1 : 0;
    if (clip_all) clipped.push_back(static_cast<std::uint32_t>(q));
  }
  std::vector<CellOut> clip_out(clipped.size());
  // Under a non-constant density: per clipped cell, (neighbour, tet) seeds of inner cells.
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> seeds_out(
      linear_density ? clipped.size() : 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, clipped.size(), 4), [&](const auto& range) {
    if (!poll.running()) return;
    ConvexCell& kernel = kernels.local();
    std::vector<std::uint32_t> seeds;  // the tets of the cell's boundary triangles
    for (std::size_t h = range.begin(); h != range.end(); ++h) {
      const std::uint32_t q = clipped[h];
      seeds.clear();
      for (std::uint32_t k = rs.cell_tri_begin[q]; k < rs.cell_tri_begin[q + 1]; ++k) {
        seeds.push_back(ctx.domain.boundary_tet(rs.cell_tris[k]));
      }
      kernel.clip_cell(rs.boundary_cells[q], seeds.data(), seeds.size(), clip_out[h],
                       linear_density ? &seeds_out[h] : nullptr);
      boundary_moments[q] = clip_out[h];
    }
    poll.chunk(0);  // counted above
  });
  poll.check();
  const auto t2 = Clock::now();
  out.seconds_[1] = std::chrono::duration<double>(t2 - t1).count();

  // ---- Other cells.
  std::vector<std::pair<std::uint32_t, std::int8_t>> first_layer;
  for (const DelaunayCells::Scratch& s : cell_scratch) {
    first_layer.insert(first_layer.end(), s.first_layer.begin(), s.first_layer.end());
  }
  dcells.decide_status(first_layer, stars.local());
  const std::vector<std::int8_t>& status = dcells.status();
  poll.phase("inner cells", n - nb_boundary);
  // Every entry is written below (Cell leaves its fields alone). Under input_index the
  // cells go in this order first and move to their input slots at the end
  // (to_input_indices): writing each to its input slot as it is finished, in random
  // order, cost 0.13 s of CPU at 10^6 sites (the stores' cache misses).
  std::vector<ClippedVoronoi3::Cell>& cells = input_index ? out.ranked_cells_ : out.cells_;
  cells.resize(n);
  // A cell's output from its integrals (r: none for a cell outside the volume).
  const auto write_cell = [&](std::uint32_t i, const Moments* r) {
    ClippedVoronoi3::Cell& cell = cells[i];
    const double* p = ctx.site(i);
    const double* origin = p;  // of the first moment: the apex of the cones
    Moments far_r;
    if (r && ctx.far(i)) {
      // Integrated from the apex a (Clip3Context::far): the energy moved to the site,
      // ∫|x - p|^2 = ∫|x - a|^2 + 2 (a - p).∫(x - a) + |a - p|^2 ∫1.
      far_r = *r;
      origin = ctx.apex(i);
      const double d[3] = {origin[0] - p[0], origin[1] - p[1], origin[2] - p[2]};
      const double m = weighted ? r->mass : r->volume;
      far_r.energy = r->energy +
                     2 * ((d[0] * r->moment[0] + d[1] * r->moment[1]) + d[2] * r->moment[2]) +
                     ((d[0] * d[0] + d[1] * d[1]) + d[2] * d[2]) * m;
      r = &far_r;
    }
    cell.volume = r ? r->volume : 0;
    if (weighted) {
      cell.mass = r ? r->mass : 0;
      cell.energy = r ? r->energy : 0;
    } else {
      cell.mass = options.density.value * cell.volume;
      cell.energy = r ? options.density.value * r->energy : 0;
    }
    const double m = weighted ? cell.mass : cell.volume;
    for (int c = 0; c < 3; ++c) {
      cell.centroid[c] = r && m > 0 ? origin[c] + r->moment[c] / m : p[c];
    }
    cell.surface_area = rs.surface_area[i];
    cell.boundary = rs.is_boundary[i];
  };
  // Inner cells write their outputs as they go (constant density); the other cells after.
  const auto written_inner = [&](std::uint32_t i) {
    return !linear_density && !rs.is_boundary[i] && status[i] == 1;
  };
  std::vector<std::uint32_t> inner_slot(linear_density ? n : 0, kNone);
  std::vector<CellOut> inner_out;
  if (linear_density) {
    // Layer after layer from the boundary cells, each seeded by the faces the previous one
    // has on their bisectors (seeds sorted: the order of everything is a function of the
    // input).
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pending;
    for (const auto& v : seeds_out) pending.insert(pending.end(), v.begin(), v.end());
    std::vector<std::uint8_t> done(rs.is_boundary);
    for (;;) {
      std::sort(pending.begin(), pending.end());
      pending.erase(std::unique(pending.begin(), pending.end()), pending.end());
      std::vector<std::uint32_t> layer, begin, seed_tets;
      for (std::size_t k = 0; k < pending.size();) {
        const std::uint32_t c = pending[k].first;
        std::size_t e = k;
        while (e < pending.size() && pending[e].first == c) ++e;
        if (!done[c] && status[c] == 1) {
          done[c] = 1;
          layer.push_back(c);
          begin.push_back(static_cast<std::uint32_t>(seed_tets.size()));
          for (std::size_t q = k; q < e; ++q) seed_tets.push_back(pending[q].second);
        }
        k = e;
      }
      if (layer.empty()) break;
      begin.push_back(static_cast<std::uint32_t>(seed_tets.size()));
      const std::size_t base = inner_out.size();
      inner_out.resize(base + layer.size());
      std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> next(layer.size());
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, layer.size(), 4), [&](const auto& range) {
            if (!poll.running()) return;
            ConvexCell& kernel = kernels.local();
            for (std::size_t q = range.begin(); q != range.end(); ++q) {
              kernel.clip_cell(layer[q], seed_tets.data() + begin[q], begin[q + 1] - begin[q],
                               inner_out[base + q], &next[q]);
            }
            poll.chunk(range.size());
          });
      poll.check();
      for (std::size_t q = 0; q < layer.size(); ++q) {
        inner_slot[layer[q]] = static_cast<std::uint32_t>(base + q);
      }
      pending.clear();
      for (const auto& v : next) pending.insert(pending.end(), v.begin(), v.end());
    }
  } else {
    spatial(written_inner, order);
    // Chunks of kInnerChunk cells: fixed (the sums' order is a function of the chunk), each
    // chunk's tets taken once instead of once per vertex. Against one star per cell
    // (measured on the 2.0 GHz EPYC host, sphere-fine): inner cells 0.0214 -> 0.017 s at
    // 10^4 sites on one thread, 0.131 -> 0.101 s at 10^5 on two; 1024 cells (about 10^4
    // tets) did better than 512 or 2048 overall, 8192 overflow the 512 KiB L2.
    const std::size_t nb_chunks = (order.size() + kInnerChunk - 1) / kInnerChunk;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb_chunks, 1), [&](const auto& range) {
      Stars& w = stars.local();
      DelaunayCells::Scratch& s = cell_scratch.local();
      s.results.resize(kInnerChunk);
      for (std::size_t h = range.begin(); h != range.end(); ++h) {
        if (!poll.running()) return;
        const std::size_t begin = h * kInnerChunk;
        const std::size_t end = std::min(order.size(), begin + kInnerChunk);
        if (weighted) {
          dcells.inner_chunk<true>(order.data() + begin, static_cast<std::uint32_t>(end - begin), w,
                                   s, s.results.data());
        } else {
          dcells.inner_chunk<false>(order.data() + begin, static_cast<std::uint32_t>(end - begin),
                                    w, s, s.results.data());
        }
        for (std::size_t q = begin; q < end; ++q) write_cell(order[q], &s.results[q - begin]);
        poll.chunk(end - begin);
      }
    });
    poll.check();
  }

  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 1024), [&](const auto& range) {
    for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
      if (written_inner(i)) continue;
      const Moments* r = nullptr;
      if (rs.is_boundary[i]) {
        r = &boundary_moments[rs.boundary_slot[i]];
      } else if (linear_density && inner_slot[i] != kNone) {
        r = &inner_out[inner_slot[i]];
      }
      write_cell(i, r);
    }
  });
  const auto t3 = Clock::now();
  out.seconds_[2] = std::chrono::duration<double>(t3 - t2).count();

  out.nb_boundary_ = static_cast<std::uint32_t>(nb_boundary);
  out.nb_multi_crossing_ = nb_multi;
  if (!input_index) out.sum_totals();
  out.nb_pairs_ = 0;
  for (const CellOut& c : clip_out) out.nb_pairs_ += c.pairs;
  for (const CellOut& c : inner_out) out.nb_pairs_ += c.pairs;
  if (options.keep_geometry) {
    poll.phase("geometry", n);
    // The boundary cells' faces from the surface (unless clipped tet by tet), then the inner
    // cells' Voronoi facets; cells in Hilbert order of their sites, by fixed chunks (a
    // chunk's faces in one CellOut, piece = the cell's place in the chunk).
    std::vector<std::uint32_t> border;
    if (!clip_all) spatial([&](std::uint32_t i) { return rs.is_boundary[i] != 0; }, border);
    // The Voronoi vertices placed by the search from the infinite tets: a cell alone may not
    // place its own (its chunk did).
    if (!border.empty() && global_flag.empty()) dcells.global_flags(global_flag);
    const std::size_t nb_border_chunks = (border.size() + kInnerChunk - 1) / kInnerChunk;
    std::vector<CellOut> border_faces(nb_border_chunks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb_border_chunks, 1),
                      [&](const auto& range) {
                        Stars& w = stars.local();
                        DelaunayCells::Scratch& s = cell_scratch.local();
                        std::vector<DelaunayCells::Segment> segments;
                        for (std::size_t h = range.begin(); h != range.end(); ++h) {
                          if (!poll.running()) return;
                          const std::size_t begin = h * kInnerChunk;
                          const std::size_t end = std::min(border.size(), begin + kInnerChunk);
                          for (std::size_t k = begin; k < end; ++k) {
                            dcells.boundary_faces(border[k], static_cast<std::uint32_t>(k - begin),
                                                  global_flag.data(), out.surface_, w, s, segments,
                                                  border_faces[h]);
                          }
                          poll.chunk(end - begin);
                        }
                      });
    poll.check();
    spatial([&](std::uint32_t i) { return !rs.is_boundary[i] && status[i] == 1; }, order);
    const std::size_t nb_chunks = (order.size() + kInnerChunk - 1) / kInnerChunk;
    std::vector<CellOut> facets(nb_chunks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb_chunks, 1), [&](const auto& range) {
      Stars& w = stars.local();
      DelaunayCells::Scratch& s = cell_scratch.local();
      for (std::size_t h = range.begin(); h != range.end(); ++h) {
        if (!poll.running()) return;
        const std::size_t begin = h * kInnerChunk;
        const std::size_t end = std::min(order.size(), begin + kInnerChunk);
        for (std::size_t k = begin; k < end; ++k) {
          dcells.voronoi_facets(order[k], static_cast<std::uint32_t>(k - begin), w, s, facets[h]);
        }
        poll.chunk(end - begin);
      }
    });
    poll.check();
    std::uint32_t pieces = 0;
    // A CellOut's faces; site_of(face_piece) is the cell of a piece.
    const auto append = [&](const CellOut& c, auto&& site_of) {
      const auto base = static_cast<std::uint32_t>(out.faces_.xyz.size() / 3);
      out.faces_.xyz.insert(out.faces_.xyz.end(), c.face_xyz.begin(), c.face_xyz.end());
      std::uint32_t last = kNone;
      for (std::size_t f = 1; f < c.face_begin.size(); ++f) {
        if (c.face_piece[f - 1] != last) {
          last = c.face_piece[f - 1];
          ++pieces;
        }
        out.faces_.site.push_back(site_of(last));
        out.faces_.piece.push_back(pieces - 1);
        out.faces_.across.push_back(c.face_across[f - 1]);
        out.faces_.polygon_begin.push_back(base + c.face_begin[f]);
      }
    };
    for (std::size_t h = 0; h < clipped.size(); ++h) {
      append(clip_out[h], [&](std::uint32_t) { return rs.boundary_cells[clipped[h]]; });
    }
    for (std::size_t h = 0; h < nb_border_chunks; ++h) {
      append(border_faces[h], [&](std::uint32_t piece) { return border[h * kInnerChunk + piece]; });
    }
    for (std::size_t h = 0; h < nb_chunks; ++h) {
      append(facets[h], [&](std::uint32_t piece) { return order[h * kInnerChunk + piece]; });
    }
  }
}

ClippedVoronoi3::Polygons ClippedVoronoi3::cell_boundaries() const {
  const Polygons& f = faces_;
  Polygons out;
  out.polygon_begin.push_back(0);
  const auto point = [&](std::uint32_t v) { return &f.xyz[3 * std::size_t{v}]; };
  const auto emit_face = [&](std::size_t k) {
    out.site.push_back(f.site[k]);
    out.across.push_back(f.across[k]);
    out.xyz.insert(out.xyz.end(), point(f.polygon_begin[k]), point(f.polygon_begin[k + 1]));
    out.polygon_begin.push_back(static_cast<std::uint32_t>(out.xyz.size() / 3));
  };
  // Twice the area vector of points pts[0, m) (Newell).
  const auto newell = [](const double* const* pts, std::size_t m, double* nrm) {
    nrm[0] = nrm[1] = nrm[2] = 0;
    for (std::size_t v = 0; v < m; ++v) {
      const double* p = pts[v];
      const double* q = pts[v + 1 == m ? 0 : v + 1];
      nrm[0] += (p[1] - q[1]) * (p[2] + q[2]);
      nrm[1] += (p[2] - q[2]) * (p[0] + q[0]);
      nrm[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
  };
  std::vector<std::uint32_t> group;  // the pieces of one face
  // Per point of the group (in order): its coordinates' bits and place, sorted.
  std::vector<std::pair<std::array<std::uint64_t, 3>, std::uint32_t>> keys;
  std::vector<std::uint32_t> at, id_of_point, id_point;  // per point: xyz index, id; per id
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges, kept;
  std::vector<std::uint32_t> next, nb_in, loop, loop_begin;
  std::vector<std::uint8_t> seen;
  std::vector<const double*> loop_pts;
  std::vector<std::uint8_t> emitted;
  // Joins the pieces in `group` (faces of one cell on one bisector); false when they do
  // not make simple outer loops (nothing emitted then).
  const auto join = [&]() {
    // Points of equal coordinates (bits) get one id; ids in the order of the coordinates.
    keys.clear();
    at.clear();
    for (const std::uint32_t k : group) {
      for (std::uint32_t v = f.polygon_begin[k]; v < f.polygon_begin[k + 1]; ++v) {
        std::array<std::uint64_t, 3> key;
        std::memcpy(key.data(), point(v), sizeof key);
        keys.emplace_back(key, static_cast<std::uint32_t>(at.size()));
        at.push_back(v);
      }
    }
    std::sort(keys.begin(), keys.end());
    id_of_point.assign(keys.size(), 0);
    id_point.clear();
    for (std::size_t r = 0; r < keys.size(); ++r) {
      if (r == 0 || keys[r].first != keys[r - 1].first) id_point.push_back(at[keys[r].second]);
      id_of_point[keys[r].second] = static_cast<std::uint32_t>(id_point.size() - 1);
    }
    // Directed edges; those met in both directions are inside the face.
    edges.clear();
    std::size_t base = 0;
    for (const std::uint32_t k : group) {
      const std::size_t m = f.polygon_begin[k + 1] - f.polygon_begin[k];
      for (std::size_t v = 0; v < m; ++v) {
        const std::uint32_t a = id_of_point[base + v], b = id_of_point[base + (v + 1) % m];
        if (a != b) edges.emplace_back(a, b);
      }
      base += m;
    }
    std::sort(edges.begin(), edges.end());
    if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
    kept.clear();
    for (const auto& e : edges) {
      if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(e.second, e.first))) {
        kept.push_back(e);
      }
    }
    const std::size_t nb_ids = id_point.size();
    next.assign(nb_ids, kNone);
    nb_in.assign(nb_ids, 0);
    for (const auto& e : kept) {
      if (next[e.first] != kNone) return false;
      next[e.first] = e.second;
      if (++nb_in[e.second] > 1) return false;
    }
    // The loops, each from its smallest id; each must turn as the pieces do (else a hole).
    double total[3] = {0, 0, 0}, nrm[3];
    for (const std::uint32_t k : group) {
      loop_pts.clear();
      for (std::uint32_t v = f.polygon_begin[k]; v < f.polygon_begin[k + 1]; ++v) {
        loop_pts.push_back(point(v));
      }
      newell(loop_pts.data(), loop_pts.size(), nrm);
      for (int c = 0; c < 3; ++c) total[c] += nrm[c];
    }
    loop.clear();
    loop_begin.assign(1, 0);
    seen.assign(nb_ids, 0);
    for (const auto& e : kept) {
      if (seen[e.first]) continue;
      std::uint32_t v = e.first;
      do {
        if (next[v] == kNone || seen[v]) return false;
        seen[v] = 1;
        loop.push_back(v);
        v = next[v];
      } while (v != e.first);
      loop_pts.clear();
      for (std::size_t q = loop_begin.back(); q < loop.size(); ++q) {
        loop_pts.push_back(point(id_point[loop[q]]));
      }
      if (loop_pts.size() < 3) return false;
      newell(loop_pts.data(), loop_pts.size(), nrm);
      if (!(nrm[0] * total[0] + nrm[1] * total[1] + nrm[2] * total[2] > 0)) return false;
      loop_begin.push_back(static_cast<std::uint32_t>(loop.size()));
    }
    for (std::size_t l = 0; l + 1 < loop_begin.size(); ++l) {
      out.site.push_back(f.site[group[0]]);
      out.across.push_back(f.across[group[0]]);
      for (std::uint32_t q = loop_begin[l]; q < loop_begin[l + 1]; ++q) {
        const double* x = point(id_point[loop[q]]);
        out.xyz.insert(out.xyz.end(), x, x + 3);
      }
      out.polygon_begin.push_back(static_cast<std::uint32_t>(out.xyz.size() / 3));
    }
    return true;
  };
  const std::size_t nb = f.site.size();
  emitted.assign(nb, 0);
  for (std::size_t k0 = 0; k0 < nb;) {
    std::size_t k1 = k0;
    while (k1 < nb && f.site[k1] == f.site[k0]) ++k1;
    for (std::size_t k = k0; k < k1; ++k) {
      if (emitted[k] || f.across[k] == kInterior) continue;
      if (f.across[k] == kSurface) {
        emit_face(k);
        continue;
      }
      group.clear();
      for (std::size_t h = k; h < k1; ++h) {
        if (f.across[h] == f.across[k]) {
          group.push_back(static_cast<std::uint32_t>(h));
          emitted[h] = 1;
        }
      }
      if (group.size() == 1 || !join()) {
        for (const std::uint32_t h : group) emit_face(h);
      }
    }
    k0 = k1;
  }
  return out;
}

void ClippedVoronoi3::compute(const Domain3& domain, const Delaunay3& dt,
                              const Clip3Options& options) {
  compute_impl(domain, dt, options, nullptr);
}

namespace {

// The dimension of the affine hull of the sites (0: one point, 1: a line, 2: a plane, 3),
// decided exactly, and the first sites that span it (as Delaunay3::initial_tetrahedron).
int affine_dimension(const double* sites, std::uint32_t n, std::uint32_t chosen[3]) {
  const auto point = [&](std::uint32_t i) { return sites + 3 * std::size_t{i}; };
  const auto same = [](const double* a, const double* b) {
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
  };
  chosen[0] = 0;
  std::uint32_t i = 1;
  while (i < n && same(point(i), point(0))) ++i;
  if (i == n) return 0;
  chosen[1] = i;
  for (++i; i < n && collinear3d(point(chosen[0]), point(chosen[1]), point(i)); ++i) {
  }
  if (i == n) return 1;
  chosen[2] = i;
  for (++i; i < n; ++i) {
    if (orient3d(point(chosen[0]), point(chosen[1]), point(chosen[2]), point(i)) != Sign::zero) {
      return 3;
    }
  }
  return 2;
}

void normalize(double* v) {
  const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  v[0] /= l;
  v[1] /= l;
  v[2] /= l;
}

void cross(const double* a, const double* b, double* c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

}  // namespace

void ClippedVoronoi3::compute(const Domain3& domain, const double* sites, std::uint32_t n,
                              const Clip3Options& options) {
  cells_.clear();
  nb_auxiliary_ = 0;
  seconds_delaunay_ = 0;
  if (n == 0) throw Error("clip3d: no sites");
  const auto t0 = std::chrono::steady_clock::now();
  double lo[3], hi[3];
  const std::uint32_t bad = finite_bounding_box(sites, n, 3, lo, hi);
  if (bad < n) {  // named by input index (the sort renumbers)
    const double* p = sites + 3 * std::size_t{bad};
    throw Error("clip3d: site " + std::to_string(bad) +
                " (from 0, in input order) has a non-finite coordinate (" + std::to_string(p[0]) +
                ", " + std::to_string(p[1]) + ", " + std::to_string(p[2]) + ")");
  }
  std::uint32_t chosen[3] = {0, 0, 0};
  const int dimension = affine_dimension(sites, n, chosen);
  if (dimension < 3 && domain.surface().nb_triangles() > 0) {
    // Fewer than 4 affinely independent sites: the clipped diagram is still well defined
    // (one site: the whole domain; sites on a line: slabs; in a plane: prisms). It is
    // computed as that of the sites and 2 (plane) or 4 (line, point) auxiliary sites far
    // off their hull, at distance L >= 4 D from the centre c of the bounding box B of the
    // domain and the sites (diagonal D): a point x of the domain is within D of every
    // site, and at least L - D/2 > D from an auxiliary site, so the auxiliary cells miss
    // the domain and every cell of a site is what it is without them, exactly (the
    // predicates decide on the sites as given; the auxiliary coordinates are only
    // required to be far, not exact). Their cells are dropped from the result.
    double blo[3], bhi[3];
    for (int k = 0; k < 3; ++k) {
      blo[k] = std::min(lo[k], domain.bbox_lo()[k]);
      bhi[k] = std::max(hi[k], domain.bbox_hi()[k]);
    }
    const double c[3] = {0.5 * (blo[0] + bhi[0]), 0.5 * (blo[1] + bhi[1]), 0.5 * (blo[2] + bhi[2])};
    double diagonal =
        std::sqrt((bhi[0] - blo[0]) * (bhi[0] - blo[0]) + (bhi[1] - blo[1]) * (bhi[1] - blo[1]) +
                  (bhi[2] - blo[2]) * (bhi[2] - blo[2]));
    // Sites beyond 1e154: the squares overflow (hypot does not; the same value otherwise).
    if (!std::isfinite(diagonal))
      diagonal = std::hypot(bhi[0] - blo[0], bhi[1] - blo[1], bhi[2] - blo[2]);
    const double far = std::ldexp(1.0, std::ilogb(std::max(diagonal, 1e-300)) + 3);  // >= 4 D
    std::vector<std::array<double, 3>> directions;
    const auto point = [&](std::uint32_t i) { return sites + 3 * std::size_t{i}; };
    if (dimension == 2) {
      const double* a = point(chosen[0]);
      const double u[3] = {point(chosen[1])[0] - a[0], point(chosen[1])[1] - a[1],
                           point(chosen[1])[2] - a[2]};
      const double v[3] = {point(chosen[2])[0] - a[0], point(chosen[2])[1] - a[1],
                           point(chosen[2])[2] - a[2]};
      std::array<double, 3> normal;
      cross(u, v, normal.data());
      normalize(normal.data());
      directions = {normal, {-normal[0], -normal[1], -normal[2]}};
    } else {
      // Two directions across the line (or any two for a point), both ways.
      double d[3] = {1, 0, 0};
      if (dimension == 1) {
        for (int k = 0; k < 3; ++k) d[k] = point(chosen[1])[k] - point(chosen[0])[k];
      }
      normalize(d);
      int axis = 0;  // the axis least along d
      for (int k = 1; k < 3; ++k) {
        if (std::fabs(d[k]) < std::fabs(d[axis])) axis = k;
      }
      double e[3] = {0, 0, 0};
      e[axis] = 1;
      std::array<double, 3> u, w;
      cross(d, e, u.data());
      normalize(u.data());
      cross(d, u.data(), w.data());
      normalize(w.data());
      directions = {u, w, {-u[0], -u[1], -u[2]}, {-w[0], -w[1], -w[2]}};
      if (dimension == 0) directions[2] = {d[0], d[1], d[2]};  // not coplanar with u, w
    }
    std::vector<double> extended(sites, sites + 3 * std::size_t{n});
    for (const auto& dir : directions) {
      for (int k = 0; k < 3; ++k) extended.push_back(c[k] + far * dir[static_cast<std::size_t>(k)]);
    }
    const auto k = static_cast<std::uint32_t>(directions.size());
    compute(domain, extended.data(), n + k, options);
    drop_auxiliary_sites(n, k);
    return;
  }
  // The sites along a Hilbert curve: the cells' order (Clip3Impl::run) and, presorted, the
  // Delaunay's BRIO rounds (which then need no sort of their own).
  site_order_.resize(n);
  std::iota(site_order_.begin(), site_order_.end(), 0u);
  hilbert_sort(sites, 3, site_order_.data(), site_order_.data() + n);
  sorted_sites_.resize(3 * std::size_t{n});
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 8192), [&](const auto& range) {
    for (std::uint32_t k = range.begin(); k != range.end(); ++k) {
      const double* p = sites + 3 * std::size_t{site_order_[k]};
      double* q = sorted_sites_.data() + 3 * std::size_t{k};
      q[0] = p[0];
      q[1] = p[1];
      q[2] = p[2];
    }
  });
  detail::ClipPoll(options.progress, "clip3d").phase("delaunay", n);
  Delaunay3Options delaunay = options.delaunay;
  delaunay.presorted = true;
  dt_.set_options(delaunay);
  dt_.build(sorted_sites_.data(), n);
  seconds_delaunay_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  compute_impl(domain, dt_, options, site_order_.data());
  to_input_indices();
}

void ClippedVoronoi3::drop_auxiliary_sites(std::uint32_t n, std::uint32_t k) {
  // Their cells are empty (outside the domain, see compute): nothing else refers to them
  // but the triangulation and site_order(), which keep them.
  for (std::uint32_t i = n; i < n + k; ++i) {
    if (cells_[i].volume != 0 || cells_[i].boundary != 0) {
      throw Error("clip3d: internal error: an auxiliary site's cell meets the domain");
    }
  }
  cells_.resize(n);
  if (!surface_.site_begin.empty()) surface_.site_begin.resize(std::size_t{n} + 1);
  nb_auxiliary_ = k;
  sum_totals();
}

void ClippedVoronoi3::sum_totals() {
  total_volume_ = total_mass_ = total_energy_ = total_surface_area_ = 0;
  for (const Cell& c : cells_) {
    total_volume_ += c.volume;
    total_mass_ += c.mass;
    total_energy_ += c.energy;
    total_surface_area_ += c.surface_area;
  }
}

void ClippedVoronoi3::to_input_indices() {
  const std::uint32_t* input_index = site_order_.data();
  const auto n = static_cast<std::uint32_t>(ranked_cells_.size());
  // Scattered to their input slots in parallel (every slot written once: input_index is a
  // permutation).
  cells_.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 4096), [&](const auto& range) {
    for (std::uint32_t k = range.begin(); k != range.end(); ++k) {
      cells_[input_index[k]] = ranked_cells_[k];
    }
  });
  sum_totals();
  // Symbolic vertices: their sites mapped, each list sorted again.
  const auto map_vertex = [&](ClipVertex3& v) {
    int ns = 0;
    while (ns < 3 && v.site[ns] != ClipVertex3::kNone) {
      v.site[ns] = input_index[v.site[ns]];
      ++ns;
    }
    std::sort(v.site, v.site + ns);
  };
  for (std::uint32_t& c : faces_.site) c = input_index[c];
  for (std::uint32_t& c : faces_.across) {
    if (c != kSurface && c != kInterior) c = input_index[c];
  }
  if (surface_.site_begin.empty()) return;
  std::vector<std::uint32_t> rank(n);
  for (std::uint32_t k = 0; k < n; ++k) rank[input_index[k]] = k;
  // The restricted surface: per cell, its polygons, cells in input order.
  Polygons s;
  s.polygon_begin.assign(1, 0);
  s.site_begin.assign(1, 0);
  s.site.reserve(surface_.site.size());
  s.triangle.reserve(surface_.triangle.size());
  s.vertices.reserve(surface_.vertices.size());
  s.xyz.reserve(surface_.xyz.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t k = rank[i];
    for (std::uint32_t p = surface_.site_begin[k]; p < surface_.site_begin[k + 1]; ++p) {
      s.site.push_back(i);
      s.triangle.push_back(surface_.triangle[p]);
      const std::uint32_t b = surface_.polygon_begin[p], e = surface_.polygon_begin[p + 1];
      for (std::uint32_t v = b; v < e; ++v) {
        s.vertices.push_back(surface_.vertices[v]);
        map_vertex(s.vertices.back());
      }
      s.xyz.insert(s.xyz.end(), surface_.xyz.begin() + 3 * std::size_t{b},
                   surface_.xyz.begin() + 3 * std::size_t{e});
      s.polygon_begin.push_back(static_cast<std::uint32_t>(s.vertices.size()));
    }
    s.site_begin.push_back(static_cast<std::uint32_t>(s.site.size()));
  }
  surface_ = std::move(s);
}

void ClippedVoronoi3::compute_impl(const Domain3& domain, const Delaunay3& dt,
                                   const Clip3Options& options, const std::uint32_t* input_index) {
  cells_.clear();  // keeps the capacity: a repeated compute resizes without allocating
  if (domain.surface().nb_triangles() == 0) throw Error("clip3d: the domain has no boundary");
  if (dt.nb_points() == 0) throw Error("clip3d: no sites");
  const Density3& rho = options.density;
  switch (rho.kind) {
    case Density3::Kind::kConstant:
      if (!(rho.value > 0) || !std::isfinite(rho.value)) {
        throw Error("clip3d: the density must be finite and positive");
      }
      break;
    case Density3::Kind::kCallback:
      if (!rho.callback) throw Error("clip3d: the density function is empty");
      break;
    case Density3::Kind::kVertexLinear:
      if (!domain.has_tets()) {
        throw Error("clip3d: a density linear per tet needs a domain with a tetrahedral mesh (" +
                    domain.source() + " is a surface); give the density as a function instead");
      }
      if (rho.vertex_values.size() != domain.nb_vertices()) {
        throw Error("clip3d: the density has " + std::to_string(rho.vertex_values.size()) +
                    " vertex values for " + std::to_string(domain.nb_vertices()) +
                    " domain vertices");
      }
      for (std::size_t v = 0; v < rho.vertex_values.size(); ++v) {
        if (!(rho.vertex_values[v] >= 0) || !std::isfinite(rho.vertex_values[v])) {
          throw Error("clip3d: the density's value at vertex " + std::to_string(v) + " (from 0)" +
                      " is negative or not finite");
        }
      }
      break;
  }
  if (options.tet_clipping && !domain.has_tets()) {
    throw Error("clip3d: tet_clipping needs a domain with a tetrahedral mesh (" + domain.source() +
                " is a surface)");
  }
  Clip3Impl impl(domain, dt, options, *this, input_index);
  try {
    impl.run();
  } catch (...) {
    // The cells may be partly written (their fields are left uninitialized until then).
    cells_.clear();
    throw;
  }
}

}  // namespace voroclip
