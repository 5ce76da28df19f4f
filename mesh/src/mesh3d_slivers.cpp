// Steps 6 and 7 of mesh3d (mesh3d_pipeline.h): the tets of the sites and their repairs. The
// extraction with the sliver perturbation (slivers3d.cpp), insertions at the slivers left,
// with interfaces sites on the lines where they meet, the peeling of flat boundary tets, then
// the flips, moves and insertions against the worst tets and for the mean (flips3d.cpp).
// Every step keeps the input's shape (check_mesh3_shape) or is undone.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "mesh3d_pipeline.h"
#include "voroclip/mesh.h"

namespace voroclip::mesh3 {

namespace {

// Step 7a: a sliver's circumcentre at least this many circumradii from the surface gets a free
// site, a nearer one a site on the surface. A sliver's circumradius R is about its edge
// length a over sqrt(2), so a free site is at least 0.35 a inside. Measured (session 28,
// against 1, every centre on the surface): elk at 100,000 vertices 18.09 -> 23.76 degrees
// (its worst tets, four boundary vertices and no boundary face, lie between two sheets of
// the surface 2-5 spacings apart, with no vertex inside), at 30,000 22.93 -> 23.68;
// skull_low_resolution at 30,000 has 4 tets below 20 degrees instead of 24. On gargoyle at
// 100,000 the pass with 2 free sites broke the shape: tried again with both on the surface it
// is the old pass (the same mesh, 27.5 degrees).
constexpr double kSliverSiteDepth = 0.5;

// Passes of step 7a' (sites on the lines where interfaces meet the boundary or each other,
// against tets in two regions).
constexpr std::uint32_t kJunctionPasses = 3;

// check_mesh3_shape of the mesh `tets` of `sites` (the sites no tet uses left out).
std::string shape_of(const Domain3& domain, const std::vector<double>& sites,
                     const std::vector<std::uint32_t>& tets) {
  std::vector<std::uint32_t> index(sites.size() / 3, SurfaceTree::kNone), renumbered(tets.size());
  std::vector<double> xyz;
  for (std::size_t i = 0; i < tets.size(); ++i) {
    std::uint32_t& v = index[tets[i]];
    if (v == SurfaceTree::kNone) {
      v = static_cast<std::uint32_t>(xyz.size() / 3);
      xyz.insert(xyz.end(), &sites[3 * std::size_t{tets[i]}], &sites[3 * std::size_t{tets[i]}] + 3);
    }
    renumbered[i] = v;
  }
  return check_mesh3_shape(domain, xyz, renumbered);
}

}  // namespace

void Pipeline::make_tets(const Surroundings& around, std::vector<std::uint32_t>& tets,
                         SurfacePatches& patches, TetRegions& regions) {
  const TetExtractor3& extractor = around.extractor;
  const TriangleSurface& surface = around.surface;
  const SurfaceTree& surface_tree = around.surface_tree;
  const FeatureLines& lines = around.lines;
  const FeatureTree& line_tree = around.line_tree;
  const std::vector<std::uint32_t>& triangle_patch = around.triangle_patch;
  const std::vector<std::uint8_t>& junction_line = around.junction_line;
  const Spacing& local_spacing = around.local_spacing;
  const Projection& project = around.project;
  // 6. Extraction; 7. slivers (the perturbation extracts as it goes and returns the
  // final mesh).
  next_phase(Mesh3Phase::kExtraction);
  // Whether q, where surface site s would go, is on s's own patch (a site on no patch goes
  // anywhere): a surface site moves within its patch in steps 7 and 7c, since across a
  // feature line its patch (the crease rule of the extraction) would be stale, and the line
  // could be cut.
  const auto on_own_patch_at = [&](std::uint32_t s, const double* q) {
    return patches.begin[s] == patches.begin[s + 1] ||
           triangle_patch[surface_tree.closest(q).triangle] == patches.patches[patches.begin[s]];
  };
  const auto extract_and_perturb = [&] {
    patches = site_patches(surface, lines, surface_tree, line_tree, sites, kinds, line_of,
                           corner_vertex, triangle_patch);
    // The caller's extraction settings (options.perturbation.extraction), with the surface
    // patches of these sites.
    Extract3Options eo = options.perturbation.extraction;
    eo.surface = &patches;
    if (options.perturb) {
      next_phase(Mesh3Phase::kSlivers);
      Perturb3Options po = options.perturbation;
      po.extraction = eo;
      const auto user = po.progress;
      po.progress = [&](std::uint32_t round, std::uint32_t slivers, double worst) {
        Mesh3Progress p;
        p.iteration = round;
        p.slivers = slivers;
        p.min_dihedral_deg = worst;
        return notify(p) && (!user || user(round, slivers, worst));
      };
      // A surface site moves within its own patch (on_own_patch_at): a candidate that
      // projects onto another patch stays where the site is (the wave's moves are written
      // after its candidates are scored, so sites[s] is the current position).
      const SiteProjector3 on_own_patch = [&](std::uint32_t s, Kind k, const double* p, double* q,
                                              double* d) {
        const bool stays =
            k == Kind::kCurve && !junction_line.empty() && junction_line[line_of[s]] != 0;
        project(s, k, stays ? &sites[3 * std::size_t{s}] : p, q, d);
        if (k == Kind::kSurface && !on_own_patch_at(s, q))
          project(s, k, &sites[3 * std::size_t{s}], q, d);
      };
      // The input's shape (check_mesh3_shape, with the caller's own check): next to thin
      // parts and knife edges a surface site's move can open or close a handle. When the
      // final mesh has the wrong shape, the first round that broke it is undone and the
      // rounds go on moving interior sites only (perturb_slivers3's keep_round).
      const auto caller = po.keep_round;
      po.keep_round = [this, caller](const std::vector<double>& at,
                                     const std::vector<std::uint32_t>& t) {
        return (!caller || caller(at, t)) && shape_of(domain, at, t).empty();
      };
      result.perturbation =
          perturb_slivers3(extractor, sites, kinds, on_own_patch, po, &tets, &result.extraction);
      if (result.perturbation.cancelled) throw Cancelled{};
    } else {
      const Delaunay3 dt(sites.data(), n);
      tets = extractor.extract(dt, eo, &result.extraction);
    }
  };
  extract_and_perturb();

  // 7a. Insertion against the slivers the moves leave (below sliver_insertion_deg): a site at
  // their circumcentres (sliver_centers), then the extraction and perturbation again. A centre
  // deeper than kSliverSiteDepth circumradii in the volume gets a free site (across a thin
  // part, between two sheets of the surface, a sliver whose four vertices are on the
  // boundary needs a vertex inside); one nearer the surface goes onto it (a free site there
  // would make a layer of flat boundary tets). A pass that does not raise the smallest angle,
  // or breaks the shape, is undone; when it had free sites it is tried again with every site
  // on the surface, else the insertion ends.
  for (std::uint32_t pass = 0; options.perturb && pass < options.sliver_insertion_passes; ++pass) {
    double lowest = 0;
    const std::vector<SliverCenter> centers =
        sliver_centers(sites, tets, options.sliver_insertion_deg, &lowest);
    if (centers.empty()) break;
    const auto saved =
        std::make_tuple(sites, kinds, line_of, corner_vertex, n, tets, patches, result.perturbation,
                        result.extraction, result.nb_boundary_sites);
    // One try: the sites at `centers`, free where deep enough if `deep`; how many were free
    // (none: the try is the same as one without `deep`).
    const auto insert = [&](bool deep) {
      std::uint32_t inside = 0;
      for (const SliverCenter& c : centers) {
        double q[3], d[3];
        project(n, Kind::kSurface, c.center.data(), q, d);
        sub3(q, c.center.data(), d);
        const bool on_surface =
            !deep || dot3(d, d) < kSliverSiteDepth * kSliverSiteDepth * c.radius * c.radius;
        if (on_surface) {
          sites.insert(sites.end(), q, q + 3);
          ++result.nb_boundary_sites;
        } else {
          sites.insert(sites.end(), c.center.begin(), c.center.end());
          ++inside;
        }
        kinds.push_back(on_surface ? Kind::kSurface : Kind::kFree);
        line_of.push_back(SurfaceTree::kNone);
        corner_vertex.push_back(SurfaceTree::kNone);
        ++n;
      }
      return inside;
    };
    // Whether the try raised the smallest angle and kept the shape; undone if not.
    const auto kept = [&] {
      extract_and_perturb();
      double after = 0;
      sliver_centers(sites, tets, 0, &after);
      const bool ok = after > lowest && shape_of(domain, sites, tets).empty();
      if (!ok) {
        std::tie(sites, kinds, line_of, corner_vertex, n, tets, patches, result.perturbation,
                 result.extraction, result.nb_boundary_sites) = saved;
      }
      return ok;
    };
    std::uint32_t inside = insert(true);
    bool ok = kept();
    if (!ok && inside > 0) {
      inside = insert(false);
      ok = kept();
    }
    if (!ok) break;
    result.nb_sliver_sites_inside += inside;
    result.nb_sliver_sites += static_cast<std::uint32_t>(centers.size());
    result.nb_sites = n;
  }

  // 7a'. With interfaces: a tet with a vertex in one region only and another in another
  // region only lies across an interface, next to a line where it meets the boundary or
  // another interface (the boundary flat on both sides, a surface site close to the line or
  // a gap between the line's sites): its surface vertices within a quarter spacing of such
  // a line go onto it, else a site goes on the line's point nearest the tet; then 6 and 7
  // again; at most kJunctionPasses passes.
  // The regions of each patch of the surface (those of its triangles).
  std::vector<std::uint64_t> patch_regions;
  if (interfaces && !interfaces->triangle_regions.empty()) {
    for (std::size_t t = 0; t < triangle_patch.size(); ++t) {
      if (triangle_patch[t] >= patch_regions.size())
        patch_regions.resize(std::size_t{triangle_patch[t]} + 1, 0);
      patch_regions[triangle_patch[t]] |= interfaces->triangle_regions[t];
    }
  }
  for (std::uint32_t pass = 0; !patch_regions.empty() && pass < kJunctionPasses; ++pass) {
    // Per site, the regions it belongs to: those of its patches (a site on the surface:
    // on an interface, both sides, whatever the rounding of its projection), or the one
    // holding it (a free site, located exactly).
    std::vector<std::uint64_t> in(n, 0);
    for (const std::uint32_t v : tets) {
      if (in[v] != 0) continue;
      for (std::uint32_t i = patches.begin[v]; i < patches.begin[v + 1]; ++i)
        in[v] |= patch_regions[patches.patches[i]];
      if (patches.begin[v] == patches.begin[v + 1]) {
        const std::uint32_t k = interfaces->region_of(&sites[3 * std::size_t{v}]);
        in[v] = k == kNoRegion ? ~std::uint64_t{0} : std::uint64_t{1} << k;
      }
    }
    // The point of a junction line nearest x, and its distance.
    const auto nearest_junction = [&](const double* x, double& distance) {
      FeatureTree::Closest best;
      double best2 = std::numeric_limits<double>::infinity();
      for (std::uint32_t l = 0; l < junction_line.size(); ++l) {
        if (junction_line[l] == 0) continue;
        const FeatureTree::Closest q = line_tree.closest(x, l);
        double d[3];
        sub3(q.point, x, d);
        if (dot3(d, d) < best2) {
          best2 = dot3(d, d);
          best = q;
          best.line = l;
        }
      }
      distance = std::sqrt(best2);
      return best;
    };
    std::vector<double> added;
    std::vector<std::uint32_t> added_line;
    std::uint32_t snapped = 0;
    for (std::size_t t = 0; t < tets.size(); t += 4) {
      if ((in[tets[t]] & in[tets[t + 1]] & in[tets[t + 2]] & in[tets[t + 3]]) != 0) continue;
      // A surface site within a quarter spacing of the line goes onto it (it stood on the
      // line's other side of the boundary: the boundary's triangles from it cross the line).
      bool moved = false;
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t v = tets[t + k];
        if (kinds[v] != Kind::kSurface) continue;
        double distance = 0;
        const FeatureTree::Closest q = nearest_junction(&sites[3 * std::size_t{v}], distance);
        if (q.line == SurfaceTree::kNone || !(distance < 0.25 * local_spacing(q.point))) continue;
        std::copy_n(q.point, 3, &sites[3 * std::size_t{v}]);
        kinds[v] = Kind::kCurve;
        line_of[v] = q.line;
        moved = true;
        ++snapped;
      }
      if (moved) continue;
      double c[3] = {0, 0, 0};
      for (int k = 0; k < 4; ++k) {
        for (int a = 0; a < 3; ++a) c[a] += 0.25 * sites[3 * std::size_t{tets[t + k]} + a];
      }
      double distance = 0;
      const FeatureTree::Closest best = nearest_junction(c, distance);
      if (best.line == SurfaceTree::kNone) continue;
      // Not within a quarter spacing of a site or of a point taken.
      const double h = 0.25 * local_spacing(best.point);
      const auto near = [&](const std::vector<double>& xyz) {
        for (std::size_t i = 0; i < xyz.size(); i += 3) {
          double d[3];
          sub3(&xyz[i], best.point, d);
          if (dot3(d, d) < h * h) return true;
        }
        return false;
      };
      if (near(sites) || near(added)) continue;
      added.insert(added.end(), best.point, best.point + 3);
      added_line.push_back(best.line);
    }
    if (added_line.empty() && snapped == 0) break;
    result.nb_boundary_sites -= snapped;
    result.nb_feature_sites += snapped;
    append_line_sites(added, added_line);
    extract_and_perturb();
  }

  // 7b. Flat tets on the boundary, which no move of their (surface) vertices fixes.
  if (options.peel_dihedral_deg > 0) {
    result.nb_peeled = peel_flat_boundary_tets(
        sites, kinds, tets, options.peel_dihedral_deg, 4,
        [this](const std::vector<std::uint32_t>& t) { return shape_of(domain, sites, t).empty(); });
  }

  // The regions, while the tets are still Delaunay: from here on flips and moves work
  // within each region (per_region), so the interfaces stay.
  if (interfaces) regions = interface_regions(*interfaces, sites, tets, patches);
  const auto flip = [&](const mesh3::Flip3Options& o) {
    if (!interfaces) return flip_slivers3(sites, kinds, tets, o);
    mesh3::Flip3Stats sum;
    per_region(sites, kinds, tets, regions,
               [&](std::vector<std::uint32_t>& mine, const std::vector<Kind>& k) {
                 const mesh3::Flip3Stats f = flip_slivers3(sites, k, mine, o);
                 sum.flips += f.flips;
                 sum.moves += f.moves;
                 sum.insertions += f.insertions;
                 sum.boundary_flips += f.boundary_flips;
               });
    return sum;
  };

  // 7c. Flips, moves of free vertices and insertions against the worst tets left: the
  // boundary stays, the tets need not be Delaunay.
  if (options.flip_dihedral_deg > 0) {
    mesh3::Flip3Options fo;
    fo.below_deg = options.flip_dihedral_deg;
    fo.gain_deg = options.flip_gain_deg;
    fo.below_q4 = options.flip_q4;
    fo.max_operations = options.max_flips_per_tet * static_cast<std::uint32_t>(tets.size() / 4);
    // A surface vertex moves within its own patch (as in the perturbation): onto the
    // surface, refused where that lands on another patch.
    if (options.flip_moves_surface) {
      fo.on_surface = [&](std::uint32_t s, const double* p, double* q) {
        double d[3];
        project(s, Kind::kSurface, p, q, d);
        return on_own_patch_at(s, q);
      };
    }
    // Boundary flips within one patch: the patches the three vertices of each old and new
    // boundary triangle share, one and the same (so the new triangles' tag is the old ones').
    const auto common = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
      std::uint32_t found = SurfaceTree::kNone, nb = 0;
      for (std::uint32_t i = patches.begin[x]; i < patches.begin[x + 1]; ++i) {
        const std::uint32_t p = patches.patches[i];
        const auto in = [&](std::uint32_t w) {
          return std::find(patches.patches.begin() + patches.begin[w],
                           patches.patches.begin() + patches.begin[w + 1],
                           p) != patches.patches.begin() + patches.begin[w + 1];
        };
        if (in(y) && in(z)) {
          found = p;
          ++nb;
        }
      }
      return nb == 1 ? found : SurfaceTree::kNone;
    };
    fo.same_patch = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
      const std::size_t nb = patches.begin.size() - 1;
      if (a >= nb || b >= nb || c >= nb || d >= nb) return false;
      const std::uint32_t p = common(a, b, c);
      return p != SurfaceTree::kNone && common(a, b, d) == p && common(a, c, d) == p &&
             common(b, d, c) == p;
    };
    const auto before_flips = std::make_tuple(sites, tets, regions);
    mesh3::Flip3Stats fs = flip(fo);
    if ((fs.boundary_flips > 0 || (fs.moves > 0 && fo.on_surface)) &&
        !shape_of(domain, sites, tets).empty() &&
        shape_of(domain, std::get<0>(before_flips), std::get<1>(before_flips)).empty()) {
      // A boundary flip or a surface vertex's move changed the boundary's shape: it reached
      // another part of the surface (a surface vertex's tets stay right-handed, but its
      // boundary triangles can cross a sheet of the boundary outside its star: elk.mesh at
      // 500 vertices, seed 2, where the sites are mostly on the surface). 7c again without
      // the boundary flips, then also without the surface moves. Interior flips and moves
      // keep the boundary.
      std::tie(sites, tets, regions) = before_flips;
      fo.same_patch = nullptr;
      fs = flip(fo);
      if (fs.moves > 0 && fo.on_surface && !shape_of(domain, sites, tets).empty()) {
        std::tie(sites, tets, regions) = before_flips;
        fo.on_surface = nullptr;
        fs = flip(fo);
      }
      result.flips_rerun_for_shape = true;
    }
    result.nb_flips = fs.flips;
    result.nb_boundary_flips = fs.boundary_flips;
    result.nb_flip_moves = fs.moves;
    result.nb_flip_sites = fs.insertions;
    // The vertices inserted are free: on no patch (tag_mesh3 and 7d read the patches of
    // every site).
    for (; n < sites.size() / 3; ++n) {
      kinds.push_back(Kind::kFree);
      line_of.push_back(SurfaceTree::kNone);
      corner_vertex.push_back(SurfaceTree::kNone);
      patches.begin.push_back(static_cast<std::uint32_t>(patches.patches.size()));
    }
    result.nb_sites = n;
  }

  // 7d. Flips and moves for the mean Q1 of all the tets (raise_mean3), the surface vertices
  // sliding within their patch as in 7c; again without the surface moves when the boundary's
  // shape changed.
  if (options.mean_rounds > 0) {
    const auto t_mean = Clock::now();
    std::function<bool(std::uint32_t, const double*, double*)> on_surface;
    if (options.flip_moves_surface) {
      on_surface = [&](std::uint32_t s, const double* p, double* q) {
        double d[3];
        project(s, Kind::kSurface, p, q, d);
        return on_own_patch_at(s, q);
      };
    }
    const auto mean = [&](const std::function<bool(std::uint32_t, const double*, double*)>& o) {
      if (!interfaces) return raise_mean3(sites, kinds, tets, options.mean_rounds, o);
      // Per region; the means weighted by the regions' tets.
      mesh3::Mean3Stats sum;
      per_region(sites, kinds, tets, regions,
                 [&](std::vector<std::uint32_t>& mine, const std::vector<Kind>& k) {
                   const mesh3::Mean3Stats m = raise_mean3(sites, k, mine, options.mean_rounds, o);
                   const double w = static_cast<double>(mine.size() / 4);
                   sum.flips += m.flips;
                   sum.moves += m.moves;
                   sum.rounds = std::max(sum.rounds, m.rounds);
                   sum.mean_before += w * m.mean_before;
                   sum.mean_after += w * m.mean_after;
                 });
      const double nt = static_cast<double>(std::max<std::size_t>(tets.size() / 4, 1));
      sum.mean_before /= nt;
      sum.mean_after /= nt;
      return sum;
    };
    // Kept for the rerun without surface moves (only they can change the shape).
    std::vector<double> sites_before;
    std::vector<std::uint32_t> tets_before;
    TetRegions regions_before;
    if (on_surface) {
      sites_before = sites;
      tets_before = tets;
      regions_before = regions;
    }
    mesh3::Mean3Stats ms = mean(on_surface);
    if (ms.moves > 0 && on_surface && !shape_of(domain, sites, tets).empty()) {
      sites = std::move(sites_before);
      tets = std::move(tets_before);
      regions = std::move(regions_before);
      ms = mean(nullptr);
    }
    result.nb_mean_flips = ms.flips;
    result.nb_mean_moves = ms.moves;
    result.mean_rounds = ms.rounds;
    result.mean_q1_before_deg = ms.mean_before;
    result.mean_q1_after_deg = ms.mean_after;
    result.mean_seconds = since(t_mean);
  }
}

}  // namespace voroclip::mesh3
