// Feature lines, surface patches and the constraints of the sites (mesh3d_pipeline.h):
// step 4 of mesh3d.
//
// Feature sites. Each feature line is sampled every eighth of the local spacing of the sites
// (the spacing that n sites of density h^-3 have: (integral of h^-3 / n)^(1/3) h(x), h the
// sizing field or 1), and at its end; the site nearest to a sample (Delaunay3::nearest_vertex,
// exact) is the site whose Voronoi cell holds it, so the sites sampled are those whose cells
// the line crosses, in order along it. A site met on several lines goes to the line with the
// most samples in its cell (ties: the lower line). Corners come first: each takes the site
// nearest to it unless that site already went to another corner, in which case a new site is
// added at the corner. Surface sites are then the boundary sites (ClippedVoronoi3::
// is_boundary) left. Every choice is a function of the sites, in index order.
//
// Gaps. A site whose cell holds two lines takes one of them, so where two lines run within a
// spacing of each other (the two rims of a plate about a spacing thick), one of them is left
// without sites: a 10 x 10 x 0.5 box at 1000 vertices (spacing 0.46) kept only the corners of
// four of its rims, and tets 5 units long along them fell to 1.8 degrees. A gap of kLineGap
// spacings or more between a line's sites gets sites at even arclengths, each where no
// constrained site is within kLineGapRoom spacings (nearer, the two lines are closer than
// that, the wall between them thinner: sites on both would make flat tets across it).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "mesh3d_pipeline.h"
#include "voroclip/predicates.h"

namespace voroclip::mesh3 {
namespace {

constexpr double kLineGap = 1.5;
constexpr double kLineGapRoom = 0.5;

}  // namespace

void Projection::operator()(std::uint32_t site, Kind kind, const double* p, double* q,
                            double* d) const {
  if (kind == Kind::kCurve) {
    const FeatureTree::Closest c = lines->closest(p, (*line_of)[site]);
    std::copy_n(c.point, 3, q);
    std::copy_n(c.tangent, 3, d);
  } else if (smooth) {
    smooth->project(*surface, p, q, d);
  } else {
    const SurfaceTree::Closest c = surface->closest(p);
    std::copy_n(c.point, 3, q);
    std::copy_n(c.normal, 3, d);
  }
}

std::vector<std::uint32_t> triangle_neighbours(const TriangleSurface& surface) {
  const std::size_t nt = surface.nb_triangles();
  std::vector<std::array<std::uint32_t, 3>> edges(3 * nt);  // lo, hi, 3 triangle + edge
  for (std::size_t t = 0; t < nt; ++t) {
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = surface.triangles[3 * t + (e + 1) % 3];
      const std::uint32_t b = surface.triangles[3 * t + (e + 2) % 3];
      edges[3 * t + e] = {std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(3 * t + e)};
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::uint32_t> next(3 * nt, SurfaceTree::kNone);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
    if (j - i == 2) {
      next[edges[i][2]] = edges[i + 1][2] / 3;
      next[edges[i + 1][2]] = edges[i][2] / 3;
    }
    i = j;
  }
  return next;
}

std::vector<std::uint64_t> tag_border_edges(const TriangleSurface& surface,
                                            const std::vector<std::int32_t>& tags) {
  std::vector<std::uint64_t> borders;
  if (tags.empty()) return borders;
  const std::vector<std::uint32_t> next = triangle_neighbours(surface);
  for (std::uint32_t b = 0; b < surface.nb_triangles(); ++b) {
    for (std::uint32_t e = 0; e < 3; ++e) {
      const std::uint32_t a = next[3 * std::size_t{b} + e];
      if (a != SurfaceTree::kNone && a > b && tags[a] != tags[b]) {
        borders.push_back(edge_key(surface.triangles[3 * std::size_t{b} + (e + 1) % 3],
                                   surface.triangles[3 * std::size_t{b} + (e + 2) % 3]));
      }
    }
  }
  std::sort(borders.begin(), borders.end());
  return borders;
}

double sharpest_dihedral_deg(const Surface3& surface) {
  const auto normal = [&](std::uint32_t t, double* n) {
    const double* a = surface.vertex(surface.triangle_vertex(t, 0));
    const double* b = surface.vertex(surface.triangle_vertex(t, 1));
    const double* c = surface.vertex(surface.triangle_vertex(t, 2));
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
  };
  double sharpest = 180;
  for (std::uint32_t t = 0; t < surface.nb_triangles(); ++t) {
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = surface.adjacent(t, e);
      if (a == Surface3::kNone || a < t) continue;  // each edge once
      // The corner of a off the edge (from corner e + 1 to e + 2 of t).
      const std::uint32_t u = surface.triangle_vertex(t, (e + 1) % 3);
      const std::uint32_t w = surface.triangle_vertex(t, (e + 2) % 3);
      std::uint32_t apex = surface.triangle_vertex(a, 0);
      for (int k = 1; k < 3 && (apex == u || apex == w); ++k) apex = surface.triangle_vertex(a, k);
      const Sign side =
          orient3d(surface.vertex(surface.triangle_vertex(t, 0)),
                   surface.vertex(surface.triangle_vertex(t, 1)),
                   surface.vertex(surface.triangle_vertex(t, 2)), surface.vertex(apex));
      if (side == Sign::zero) continue;  // flat: 180
      double m[3], n[3];
      normal(t, m);
      normal(a, n);
      const double cross[3] = {m[1] * n[2] - m[2] * n[1], m[2] * n[0] - m[0] * n[2],
                               m[0] * n[1] - m[1] * n[0]};
      const double between =
          std::atan2(std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]),
                     m[0] * n[0] + m[1] * n[1] + m[2] * n[2]) *
          (180 / 3.14159265358979323846);
      // orient3d > 0: the apex is below t's plane, inside the volume (t's corners run
      // counter-clockwise seen from outside): a convex edge.
      sharpest = std::min(sharpest, side == Sign::positive ? 180 - between : 180 + between);
    }
  }
  return sharpest;
}

FeatureLines split_at_turns(const TriangleSurface& s, const FeatureLines& lines, double angle_deg) {
  const double cos_limit = std::cos(angle_deg * (3.14159265358979323846 / 180));
  const auto turns = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) {
      u[k] = s.xyz[3 * std::size_t{b} + static_cast<std::size_t>(k)] -
             s.xyz[3 * std::size_t{a} + static_cast<std::size_t>(k)];
      v[k] = s.xyz[3 * std::size_t{c} + static_cast<std::size_t>(k)] -
             s.xyz[3 * std::size_t{b} + static_cast<std::size_t>(k)];
    }
    const double uv = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    return uv < cos_limit * std::sqrt(uu * vv);
  };
  FeatureLines out;
  out.corners = lines.corners;
  out.nb_feature_edges = lines.nb_feature_edges;
  const auto emit = [&](const std::vector<std::uint32_t>& vs, bool closed) {
    out.line_vertices.insert(out.line_vertices.end(), vs.begin(), vs.end());
    out.line_begin.push_back(static_cast<std::uint32_t>(out.line_vertices.size()));
    out.line_closed.push_back(closed ? 1 : 0);
  };
  std::vector<std::uint32_t> vs, piece;
  for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
    vs.assign(lines.line_vertices.begin() + lines.line_begin[l],
              lines.line_vertices.begin() + lines.line_begin[l + 1]);
    const bool closed = lines.line_closed[l] != 0;
    const std::size_t m = vs.size();
    std::vector<std::size_t> cuts;  // positions of turning vertices
    for (std::size_t i = 0; i < m; ++i) {
      if (closed ? i + 1 == m : (i == 0 || i + 1 == m)) continue;
      const std::uint32_t prev = closed && i == 0 ? vs[m - 2] : vs[i - (i > 0 ? 1 : 0)];
      if (turns(prev, vs[i], vs[i + 1])) cuts.push_back(i);
    }
    if (cuts.empty()) {
      emit(vs, closed);
      continue;
    }
    for (const std::size_t c : cuts) out.corners.push_back(vs[c]);
    if (closed) {
      // Start at the first cut: an open line from cut to cut, all the way round.
      std::vector<std::uint32_t> ring(vs.begin(), vs.end() - 1);
      std::rotate(ring.begin(), ring.begin() + static_cast<std::ptrdiff_t>(cuts[0]), ring.end());
      ring.push_back(ring.front());
      for (std::size_t& c : cuts) c = (c + (m - 1) - cuts[0]) % (m - 1);
      cuts.push_back(m - 1);
      vs = ring;
    } else {
      cuts.push_back(m - 1);
      cuts.insert(cuts.begin(), 0);
    }
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      if (cuts[k + 1] <= cuts[k]) continue;
      piece.assign(vs.begin() + static_cast<std::ptrdiff_t>(cuts[k]),
                   vs.begin() + static_cast<std::ptrdiff_t>(cuts[k + 1]) + 1);
      emit(piece, false);
    }
  }
  std::sort(out.corners.begin(), out.corners.end());
  out.corners.erase(std::unique(out.corners.begin(), out.corners.end()), out.corners.end());
  return out;
}

FeatureLines drop_short_lines(const TriangleSurface& s, const FeatureLines& lines, double ratio,
                              const Spacing& spacing, const std::vector<std::uint64_t>& keep) {
  FeatureLines out;
  out.nb_feature_edges = 0;
  for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
    const std::uint32_t b = lines.line_begin[l], e = lines.line_begin[l + 1];
    double length = 0;
    bool kept = false;
    for (std::uint32_t i = b; i + 1 < e; ++i) {
      kept =
          kept || std::binary_search(keep.begin(), keep.end(),
                                     edge_key(lines.line_vertices[i], lines.line_vertices[i + 1]));
      const double* p = &s.xyz[3 * std::size_t{lines.line_vertices[i]}];
      const double* q = &s.xyz[3 * std::size_t{lines.line_vertices[i + 1]}];
      length += std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                          (p[2] - q[2]) * (p[2] - q[2]));
    }
    const double* middle = &s.xyz[3 * std::size_t{lines.line_vertices[b + (e - b) / 2]}];
    if (!kept && length < ratio * spacing(middle)) continue;
    out.line_vertices.insert(out.line_vertices.end(), lines.line_vertices.begin() + b,
                             lines.line_vertices.begin() + e);
    out.line_begin.push_back(static_cast<std::uint32_t>(out.line_vertices.size()));
    out.line_closed.push_back(lines.line_closed[l]);
    out.nb_feature_edges += e - b - 1;
    if (lines.line_closed[l] == 0) {
      out.corners.push_back(lines.line_vertices[b]);
      out.corners.push_back(lines.line_vertices[e - 1]);
    }
  }
  std::sort(out.corners.begin(), out.corners.end());
  out.corners.erase(std::unique(out.corners.begin(), out.corners.end()), out.corners.end());
  return out;
}

std::vector<std::uint64_t> sorted_feature_edges(const FeatureLines& lines) {
  std::vector<std::uint64_t> features;
  for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
    for (std::uint32_t i = lines.line_begin[l]; i + 1 < lines.line_begin[l + 1]; ++i) {
      features.push_back(edge_key(lines.line_vertices[i], lines.line_vertices[i + 1]));
    }
  }
  std::sort(features.begin(), features.end());
  return features;
}

std::vector<std::uint32_t> triangle_patches(const TriangleSurface& surface,
                                            const FeatureLines& lines) {
  const std::vector<std::uint64_t> features = sorted_feature_edges(lines);
  const std::vector<std::uint32_t> next = triangle_neighbours(surface);
  const std::uint32_t nb = surface.nb_triangles();
  std::vector<std::uint32_t> patch(nb, SurfaceTree::kNone), queue;
  std::uint32_t nb_patches = 0;
  for (std::uint32_t b0 = 0; b0 < nb; ++b0) {
    if (patch[b0] != SurfaceTree::kNone) continue;
    patch[b0] = nb_patches;
    queue.assign(1, b0);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t b = queue[q];
      for (std::uint32_t e = 0; e < 3; ++e) {
        const std::uint32_t a = next[3 * std::size_t{b} + e];
        const std::uint64_t key = edge_key(surface.triangles[3 * std::size_t{b} + (e + 1) % 3],
                                           surface.triangles[3 * std::size_t{b} + (e + 2) % 3]);
        if (a == SurfaceTree::kNone || patch[a] != SurfaceTree::kNone ||
            std::binary_search(features.begin(), features.end(), key))
          continue;
        patch[a] = nb_patches;
        queue.push_back(a);
      }
    }
    ++nb_patches;
  }
  return patch;
}

SurfacePatches site_patches(const TriangleSurface& input, const FeatureLines& lines,
                            const SurfaceTree& surface, const FeatureTree& line_tree,
                            const std::vector<double>& sites, const std::vector<Kind>& kinds,
                            const std::vector<std::uint32_t>& line_of,
                            const std::vector<std::uint32_t>& corner_vertex,
                            const std::vector<std::uint32_t>& patch) {
  const std::vector<std::uint64_t> features = sorted_feature_edges(lines);
  const auto is_feature = [&](std::uint64_t k) {
    return std::binary_search(features.begin(), features.end(), k);
  };
  const std::uint32_t nb = input.nb_triangles();
  const auto edge_of = [&](std::uint32_t b, int e) {
    return edge_key(input.triangles[3 * std::size_t{b} + static_cast<std::size_t>((e + 1) % 3)],
                    input.triangles[3 * std::size_t{b} + static_cast<std::size_t>((e + 2) % 3)]);
  };
  // (feature edge, patch) and (corner vertex, patch) pairs.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edge_patch, vertex_patch;
  std::vector<std::uint32_t> corner_mark(input.nb_vertices(), 0);
  for (const std::uint32_t v : corner_vertex) {
    if (v != SurfaceTree::kNone) corner_mark[v] = 1;
  }
  for (std::uint32_t b = 0; b < nb; ++b) {
    for (int e = 0; e < 3; ++e) {
      if (is_feature(edge_of(b, e))) edge_patch.emplace_back(edge_of(b, e), patch[b]);
      const std::uint32_t v = input.triangles[3 * std::size_t{b} + static_cast<std::size_t>(e)];
      if (corner_mark[v] != 0) vertex_patch.emplace_back(v, patch[b]);
    }
  }
  std::sort(edge_patch.begin(), edge_patch.end());
  edge_patch.erase(std::unique(edge_patch.begin(), edge_patch.end()), edge_patch.end());
  std::sort(vertex_patch.begin(), vertex_patch.end());
  vertex_patch.erase(std::unique(vertex_patch.begin(), vertex_patch.end()), vertex_patch.end());
  const auto append_all = [](auto& pairs, auto key, std::vector<std::uint32_t>& out) {
    auto it = std::lower_bound(pairs.begin(), pairs.end(),
                               std::make_pair(std::uint64_t{key}, std::uint32_t{0}));
    for (; it != pairs.end() && it->first == key; ++it) out.push_back(it->second);
  };
  SurfacePatches sp;
  const auto n = static_cast<std::uint32_t>(kinds.size());
  sp.begin.reserve(std::size_t{n} + 1);
  sp.begin.push_back(0);
  for (std::uint32_t s = 0; s < n; ++s) {
    const double* p = &sites[3 * std::size_t{s}];
    if (kinds[s] == Kind::kSurface) {
      sp.patches.push_back(patch[surface.closest(p).triangle]);
    } else if (kinds[s] == Kind::kCurve) {
      const std::uint32_t l = line_of[s];
      const FeatureTree::Closest c = line_tree.closest(p, l);
      const std::uint32_t i = lines.line_begin[l] + c.segment;
      append_all(edge_patch, edge_key(lines.line_vertices[i], lines.line_vertices[i + 1]),
                 sp.patches);
    } else if (kinds[s] == Kind::kFixed && corner_vertex[s] != SurfaceTree::kNone) {
      append_all(vertex_patch, std::uint64_t{corner_vertex[s]}, sp.patches);
    }
    sp.begin.push_back(static_cast<std::uint32_t>(sp.patches.size()));
  }
  return sp;
}

void Pipeline::constrain_sites(const FeatureLines& lines, const FeatureTree& line_tree,
                               const Spacing& local_spacing,
                               const std::vector<std::uint8_t>& boundary,
                               const Projection& project) {
  n = static_cast<std::uint32_t>(sites.size() / 3);
  kinds.assign(n, Kind::kFree);
  line_of.assign(n, SurfaceTree::kNone);
  corner_vertex.assign(n, SurfaceTree::kNone);
  {
    const Delaunay3 dt(sites.data(), n);
    // Corners. (The sites move only after the last query: dt reads them.)
    std::vector<double> added;
    std::vector<std::uint32_t> added_corner, added_line;
    for (const std::uint32_t c : lines.corners) {
      const double* p = domain.vertex(c);
      const std::uint32_t s = dt.nearest_vertex(p);
      if (kinds[s] != Kind::kFixed) {
        kinds[s] = Kind::kFixed;
        corner_vertex[s] = c;
      } else {
        added.insert(added.end(), p, p + 3);
        added_corner.push_back(c);
      }
    }
    // Feature lines: the sites whose cells hold points along them.
    if (lines.nb_lines() > 0) {
      // Samples every eighth of the local spacing along each line, and its end.
      std::vector<std::uint64_t> claims;  // (site, line) per sample
      std::uint32_t hint = Delaunay3::kNoTet;
      for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
        const double length = line_tree.length(l);
        double arclength = 0;
        for (bool last = false; !last;) {
          last = arclength >= length;
          double x[3];
          line_tree.eval(l, std::min(arclength, length), x);
          const std::uint32_t s = dt.nearest_vertex(x, hint);
          hint = dt.vertex_tet(s);
          if (kinds[s] != Kind::kFixed) claims.push_back(std::uint64_t{s} << 32 | l);
          arclength += 0.125 * local_spacing(x);
        }
      }
      std::sort(claims.begin(), claims.end());
      for (std::size_t i = 0; i < claims.size();) {
        const auto s = static_cast<std::uint32_t>(claims[i] >> 32);
        std::uint32_t best_line = 0, best_count = 0;
        std::size_t j = i;
        while (j < claims.size() && (claims[j] >> 32) == s) {
          std::size_t k = j;
          while (k < claims.size() && claims[k] == claims[j]) ++k;
          if (k - j > best_count) {
            best_count = static_cast<std::uint32_t>(k - j);
            best_line = static_cast<std::uint32_t>(claims[j] & 0xffffffffu);
          }
          j = k;
        }
        kinds[s] = Kind::kCurve;
        line_of[s] = best_line;
        i = j;
      }
      fill_line_gaps(line_tree, local_spacing, added, added_line);
    }
    for (std::uint32_t s = 0; s < n; ++s) {
      if (kinds[s] == Kind::kFree && boundary[s] != 0) kinds[s] = Kind::kSurface;
    }
    for (std::uint32_t v = 0; v < n; ++v) {
      if (corner_vertex[v] != SurfaceTree::kNone) {
        std::copy_n(domain.vertex(corner_vertex[v]), 3, &sites[3 * std::size_t{v}]);
      }
    }
    // Corners without a site of their own get a new one, then the lines' gaps theirs.
    sites.insert(sites.end(), added.begin(), added.end());
    const auto extra = static_cast<std::uint32_t>(added_corner.size());
    kinds.insert(kinds.end(), extra, Kind::kFixed);
    line_of.insert(line_of.end(), extra, SurfaceTree::kNone);
    corner_vertex.insert(corner_vertex.end(), added_corner.begin(), added_corner.end());
    kinds.insert(kinds.end(), added_line.size(), Kind::kCurve);
    line_of.insert(line_of.end(), added_line.begin(), added_line.end());
    corner_vertex.insert(corner_vertex.end(), added_line.size(), SurfaceTree::kNone);
    n += extra + static_cast<std::uint32_t>(added_line.size());
  }
  for (std::uint32_t s = 0; s < n; ++s) {
    if (kinds[s] == Kind::kSurface || kinds[s] == Kind::kCurve) {
      double q[3], d[3];
      project(s, kinds[s], &sites[3 * std::size_t{s}], q, d);
      std::copy_n(q, 3, &sites[3 * std::size_t{s}]);
    }
    result.nb_boundary_sites += kinds[s] == Kind::kSurface ? 1 : 0;
    result.nb_feature_sites += kinds[s] == Kind::kCurve ? 1 : 0;
    result.nb_corner_sites += kinds[s] == Kind::kFixed ? 1 : 0;
  }
  result.nb_sites = n;
}

void Pipeline::fill_line_gaps(const FeatureTree& line_tree, const Spacing& local_spacing,
                              std::vector<double>& added, std::vector<std::uint32_t>& added_line) {
  // The constrained sites where they will be (a line site at its closest point on its line, a
  // corner site at its corner; `added` holds the new corners), and each line's sites'
  // arclengths, line by line.
  std::vector<double> taken(added);
  std::vector<std::pair<std::uint32_t, double>> at;
  for (std::uint32_t s = 0; s < n; ++s) {
    if (kinds[s] == Kind::kCurve) {
      const FeatureTree::Closest c = line_tree.closest(&sites[3 * std::size_t{s}], line_of[s]);
      at.emplace_back(line_of[s], c.arclength);
      taken.insert(taken.end(), c.point, c.point + 3);
    } else if (kinds[s] == Kind::kFixed && corner_vertex[s] != SurfaceTree::kNone) {
      const double* p = domain.vertex(corner_vertex[s]);
      taken.insert(taken.end(), p, p + 3);
    }
  }
  std::sort(at.begin(), at.end());
  const auto room = [&](const double* x, double h) {
    for (std::size_t i = 0; i < taken.size(); i += 3) {
      double d[3];
      sub3(x, &taken[i], d);
      if (dot3(d, d) < kLineGapRoom * kLineGapRoom * h * h) return false;
    }
    return true;
  };
  std::vector<double> ends;
  auto it = at.begin();
  for (std::uint32_t l = 0; l < line_tree.nb_lines(); ++l) {
    const double length = line_tree.length(l);
    ends.clear();
    // An open line ends at corners (or at another line): its ends count as sites.
    if (!line_tree.closed(l)) ends.push_back(0);
    for (; it != at.end() && it->first == l; ++it) ends.push_back(it->second);
    if (!line_tree.closed(l)) {
      ends.push_back(length);
    } else if (ends.empty()) {
      ends.push_back(0);  // a loop with no site: one gap all around
    }
    std::sort(ends.begin(), ends.end());
    // A closed line's last gap wraps around to its first site.
    if (line_tree.closed(l)) ends.push_back(ends.front() + length);
    for (std::size_t i = 0; i + 1 < ends.size(); ++i) {
      const double gap = ends[i + 1] - ends[i];
      double mid[3];
      line_tree.eval(l, ends[i] + gap / 2, mid);
      const double h = local_spacing(mid);
      if (gap < kLineGap * h) continue;
      const auto k = static_cast<std::uint32_t>(std::floor(gap / h + 0.5)) - 1;
      for (std::uint32_t j = 1; j <= k; ++j) {
        double x[3];
        line_tree.eval(l, ends[i] + gap * j / (k + 1), x);
        if (!room(x, h)) continue;
        added.insert(added.end(), x, x + 3);
        taken.insert(taken.end(), x, x + 3);
        added_line.push_back(l);
      }
    }
  }
}

std::uint32_t Pipeline::refill_line_gaps(const FeatureTree& line_tree,
                                         const Spacing& local_spacing) {
  std::vector<double> added;
  std::vector<std::uint32_t> added_line;
  fill_line_gaps(line_tree, local_spacing, added, added_line);
  append_line_sites(added, added_line);
  return static_cast<std::uint32_t>(added_line.size());
}

void Pipeline::append_line_sites(const std::vector<double>& xyz,
                                 const std::vector<std::uint32_t>& line) {
  const auto extra = static_cast<std::uint32_t>(line.size());
  sites.insert(sites.end(), xyz.begin(), xyz.end());
  kinds.insert(kinds.end(), extra, Kind::kCurve);
  line_of.insert(line_of.end(), line.begin(), line.end());
  corner_vertex.insert(corner_vertex.end(), extra, SurfaceTree::kNone);
  n += extra;
  result.nb_feature_sites += extra;
  result.nb_sites = n;
}

std::uint32_t Pipeline::snap_boundary_free_sites(const std::vector<std::uint8_t>& boundary,
                                                 const Projection& project) {
  std::uint32_t snapped = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (kinds[v] != Kind::kFree || boundary[v] == 0) continue;
    kinds[v] = Kind::kSurface;
    double q[3], d[3];
    project(v, kinds[v], &sites[3 * std::size_t{v}], q, d);
    std::copy_n(q, 3, &sites[3 * std::size_t{v}]);
    ++snapped;
  }
  result.nb_boundary_sites += snapped;
  return snapped;
}

}  // namespace voroclip::mesh3
