// Tables of cells of a clipped Voronoi diagram (clip.h, "Tables of cells"): the per-cell
// values and the pairs of neighbouring cells with the measure of what they share, read
// from the cells' geometry (keep_geometry). The CSV/JSON formatting is core's
// (cell_table_io.cpp).
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <utility>
#include <vector>

#include "voroclip/clip.h"

namespace voroclip {

namespace {

// The sites that define a symbolic vertex (sorted, at most 3; a domain vertex has none).
int defining_sites(const ClipVertex2& v, std::uint32_t* out) {
  switch (v.kind) {
    case ClipVertex2::Kind::kDomainVertex:
      return 0;
    case ClipVertex2::Kind::kEdgeBisector:
      out[0] = v.b;
      out[1] = v.c;
      return 2;
    case ClipVertex2::Kind::kVoronoi:
      out[0] = v.a;
      out[1] = v.b;
      out[2] = v.c;
      return 3;
  }
  return 0;
}

// Appends cell i's rows (i < j) from its (j, measure) entries, merged by j; returns the
// number of distinct neighbours.
template <typename Measure>
std::uint32_t merge_rows(std::uint32_t i, std::vector<std::pair<std::uint32_t, Measure>>& entries,
                         NeighborTable& table, double (*norm)(const Measure&),
                         void (*add)(Measure&, const Measure&)) {
  std::stable_sort(entries.begin(), entries.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::uint32_t count = 0;
  for (std::size_t k = 0; k < entries.size();) {
    Measure sum = entries[k].second;
    std::size_t l = k + 1;
    for (; l < entries.size() && entries[l].first == entries[k].first; ++l) {
      add(sum, entries[l].second);
    }
    ++count;
    if (i < entries[k].first) {
      table.pairs.push_back(i);
      table.pairs.push_back(entries[k].first);
      table.measure.push_back(norm(sum));
    }
    k = l;
  }
  return count;
}

// The rows are sorted by (site_a, site_b): cells are visited in index order and each
// cell's rows in neighbour order.
void check_sorted([[maybe_unused]] const NeighborTable& t) {
  for (std::uint32_t r = 1; r < t.nb_pairs(); ++r) {
    assert(std::make_pair(t.pairs[2 * r - 2], t.pairs[2 * r - 1]) <
           std::make_pair(t.pairs[2 * r], t.pairs[2 * r + 1]));
  }
}

}  // namespace

NeighborTable cell_neighbors(const ClippedVoronoi2& cv) {
  if (cv.nb_sites() > 0 && !cv.has_geometry()) {
    throw Error("cell_neighbors: the diagram was computed without keep_geometry");
  }
  NeighborTable table;
  table.dimension = 2;
  const std::vector<ClipVertex2>& vertices = cv.vertices();
  const std::vector<double>& xy = cv.vertex_coords();
  std::vector<std::pair<std::uint32_t, double>> entries;
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) {
    entries.clear();
    for (std::uint32_t r = cv.cell_ring_begin(i); r < cv.cell_ring_begin(i + 1); ++r) {
      const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
      for (std::uint32_t k = b; k < e; ++k) {
        const std::uint32_t l = k + 1 == e ? b : k + 1;
        std::uint32_t su[3], sv[3];
        const int nu = defining_sites(vertices[k], su);
        const int nv = defining_sites(vertices[l], sv);
        // The sites other than i that define both ends: exactly one, j, when the edge lies
        // on bisector(i, j); none on the domain's boundary.
        std::uint32_t j = 0;
        int common = 0;
        for (int p = 0; p < nu; ++p) {
          if (su[p] == i) continue;
          for (int q = 0; q < nv; ++q) {
            if (sv[q] == su[p]) {
              j = su[p];
              ++common;
            }
          }
        }
        if (common != 1) continue;
        entries.emplace_back(j,
                             std::hypot(xy[2 * std::size_t{l}] - xy[2 * std::size_t{k}],
                                        xy[2 * std::size_t{l} + 1] - xy[2 * std::size_t{k} + 1]));
      }
    }
    merge_rows<double>(
        i, entries, table, [](const double& x) { return x; },
        [](double& a, const double& b) { a += b; });
  }
  check_sorted(table);
  return table;
}

NeighborTable cell_neighbors(const ClippedVoronoi3& cv) {
  const ClippedVoronoi3::Polygons& f = cv.cell_faces();
  if (cv.nb_sites() > 0 && f.polygon_begin.empty()) {
    throw Error("cell_neighbors: the diagram was computed without keep_geometry");
  }
  NeighborTable table;
  table.dimension = 3;
  using Vec = std::array<double, 3>;
  // Per cell its faces on bisectors; faces are grouped by cell in cell_faces(), but not in
  // index order, so they are bucketed first.
  std::vector<std::uint32_t> begin(cv.nb_sites() + 1, 0), order;
  const std::size_t nf = f.site.size();
  for (std::size_t k = 0; k < nf; ++k) ++begin[f.site[k] + 1];
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) begin[i + 1] += begin[i];
  order.resize(nf);
  {
    std::vector<std::uint32_t> next(begin.begin(), begin.end() - 1);
    for (std::size_t k = 0; k < nf; ++k) order[next[f.site[k]]++] = static_cast<std::uint32_t>(k);
  }
  std::vector<std::pair<std::uint32_t, Vec>> entries;
  for (std::uint32_t i = 0; i < cv.nb_sites(); ++i) {
    entries.clear();
    for (std::uint32_t o = begin[i]; o < begin[i + 1]; ++o) {
      const std::uint32_t k = order[o];
      const std::uint32_t j = f.across[k];
      if (j == ClippedVoronoi3::kSurface || j == ClippedVoronoi3::kInterior) continue;
      // Twice the vector area (Newell), from the polygon's first point.
      const std::uint32_t b = f.polygon_begin[k], e = f.polygon_begin[k + 1];
      const double* p0 = &f.xyz[3 * std::size_t{b}];
      Vec a = {0, 0, 0};
      for (std::uint32_t v = b + 1; v + 1 < e; ++v) {
        const double* p = &f.xyz[3 * std::size_t{v}];
        const double* q = &f.xyz[3 * std::size_t{v} + 3];
        const double u[3] = {p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]};
        const double w[3] = {q[0] - p0[0], q[1] - p0[1], q[2] - p0[2]};
        a[0] += u[1] * w[2] - u[2] * w[1];
        a[1] += u[2] * w[0] - u[0] * w[2];
        a[2] += u[0] * w[1] - u[1] * w[0];
      }
      entries.emplace_back(j, a);
    }
    merge_rows<Vec>(
        i, entries, table,
        [](const Vec& a) { return 0.5 * std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); },
        [](Vec& a, const Vec& b) {
          a[0] += b[0];
          a[1] += b[1];
          a[2] += b[2];
        });
  }
  check_sorted(table);
  return table;
}

namespace {

std::vector<std::uint32_t> neighbor_counts(const NeighborTable& t, std::uint32_t n) {
  std::vector<std::uint32_t> counts(n, 0);
  for (std::uint32_t r = 0; r < t.nb_pairs(); ++r) {
    const std::uint32_t a = t.pairs[2 * std::size_t{r}], b = t.pairs[2 * std::size_t{r} + 1];
    if (a >= n || b >= n) throw Error("cell_table: a neighbour pair names a site out of range");
    ++counts[a];
    ++counts[b];
  }
  return counts;
}

}  // namespace

CellTable cell_table(const ClippedVoronoi2& cv, const double* sites,
                     const NeighborTable* neighbors) {
  CellTable t;
  t.dimension = 2;
  const std::uint32_t n = cv.nb_sites();
  t.sites.assign(sites, sites + 2 * std::size_t{n});
  for (std::uint32_t i = 0; i < n; ++i) {
    t.measure.push_back(cv.area(i));
    t.centroids.insert(t.centroids.end(), cv.centroid(i), cv.centroid(i) + 2);
    t.energy.push_back(cv.energy(i));
    t.boundary.push_back(cv.is_boundary(i) ? 1 : 0);
  }
  if (neighbors != nullptr) t.nb_neighbors = neighbor_counts(*neighbors, n);
  return t;
}

CellTable cell_table(const ClippedVoronoi3& cv, const double* sites,
                     const NeighborTable* neighbors) {
  CellTable t;
  t.dimension = 3;
  const std::uint32_t n = cv.nb_sites();
  t.sites.assign(sites, sites + 3 * std::size_t{n});
  for (std::uint32_t i = 0; i < n; ++i) {
    t.measure.push_back(cv.volume(i));
    t.centroids.insert(t.centroids.end(), cv.centroid(i), cv.centroid(i) + 3);
    t.energy.push_back(cv.energy(i));
    t.boundary.push_back(cv.is_boundary(i) ? 1 : 0);
    t.surface_area.push_back(cv.surface_area(i));
  }
  if (neighbors != nullptr) t.nb_neighbors = neighbor_counts(*neighbors, n);
  return t;
}

}  // namespace voroclip
