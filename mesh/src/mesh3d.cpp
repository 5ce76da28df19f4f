// The 3D CVT tet-meshing pipeline (Yan et al. 2011, sec. 5.2; the steps are listed in
// mesh.h): sizing, sampling, unconstrained CVT, snapping of boundary, feature and corner
// sites, constrained CVT, exact extraction, sliver perturbation, output and quality.
// The steps with code of their own live in the files mesh3d_pipeline.h lists.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "mesh3d_pipeline.h"
#include "mesh3d_tags.h"
#include "voroclip/mesh.h"

namespace voroclip {

namespace mesh3 {

// Sites on a body-centred cubic lattice (the points a (i, j, k) + o and a (i + 1/2, j + 1/2,
// k + 1/2) + o) strictly inside the domain (exact point location), about n of them: the
// spacing starts at (2 V / n)^(1/3) and is corrected by the count's cube root (by a factor
// within [1/2, 2], and between the spacings known to give too many and too few once both are
// known) until the count is within 0.5 % of n, at most 12 times; the closest count is kept.
// The offset o is a function of the seed. The BCC lattice is the best known CVT in space
// (its cells are truncated octahedra, Du & Wang 2005), so only the sites near the boundary
// have far to go. But in a part thinner than the layers' spacing the count jumps between 0
// and several times n as the layers move (a plate 0.1 thick at 1,000 sites had 0, then
// 950,544, then 0, ...: the CVT of a million sites ran for hours): when no spacing comes
// within 10 % of n, the result is empty and the caller draws the sites at random instead.
std::vector<double> lattice_sites(const Domain3& domain, const TetExtractor3& locator,
                                  std::uint32_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  double offset[3];
  for (double& o : offset) o = static_cast<double>(rng() >> 11) * 0x1p-53;
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  // The lattice points inside for spacing a; stops past `cap` points.
  const auto fill = [&](double a, std::size_t cap, std::vector<double>& xyz) {
    xyz.clear();
    std::int64_t first[3], last[3];
    for (int c = 0; c < 3; ++c) {
      first[c] = static_cast<std::int64_t>(std::floor(lo[c] / a - offset[c])) - 1;
      last[c] = static_cast<std::int64_t>(std::ceil(hi[c] / a - offset[c])) + 1;
    }
    for (int shift = 0; shift < 2; ++shift) {
      for (std::int64_t k = first[2]; k <= last[2]; ++k) {
        for (std::int64_t j = first[1]; j <= last[1]; ++j) {
          for (std::int64_t i = first[0]; i <= last[0]; ++i) {
            const std::int64_t ijk[3] = {i, j, k};
            double p[3];
            for (int c = 0; c < 3; ++c) {
              p[c] = a * (static_cast<double>(ijk[c]) + offset[c] + 0.5 * shift);
            }
            if (locator.point_side(p) == Sign::positive) {
              xyz.insert(xyz.end(), p, p + 3);
              if (xyz.size() / 3 > cap) return;
            }
          }
        }
      }
    }
  };
  const double target = n;
  const std::size_t cap = 4 * std::size_t{n} + 16;
  double a = std::cbrt(2 * domain.volume() / target);
  double too_small = 0, too_large = 0;  // spacings known to give more / fewer than n
  std::vector<double> xyz, best;
  double best_error = -1;
  for (int attempt = 0; attempt < 12; ++attempt) {
    fill(a, cap, xyz);
    const double count = static_cast<double>(xyz.size() / 3);
    const double error = std::fabs(count - target);
    if (best_error < 0 || error < best_error) {
      best_error = error;
      best.swap(xyz);
    }
    if (error <= 0.005 * target) break;
    (count > target ? too_small : too_large) = a;
    double next = a * std::clamp(std::cbrt(std::max(count, 1.0) / target), 0.5, 2.0);
    if (too_small > 0 && too_large > 0 && !(next > too_small && next < too_large)) {
      next = std::sqrt(too_small * too_large);
    }
    a = next;
  }
  if (best_error > 0.1 * target || best.size() < 12) return {};
  return best;
}

namespace {

// For each centre (x, y, z) of the cells of a grid of 48 cells along the longest side of
// the bounding box that lie in the volume (each centre located exactly), visit(p, out),
// `out` the vector of p's grid layer; the layers' entries joined in the grid's order
// whatever the thread count, and the volume of one cell.
template <class T, class Visit>
std::vector<T> over_volume(const Domain3& domain, const Visit& visit, double& cell_volume) {
  constexpr double kCells = 48;
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  cell_volume = 0;
  if (!(longest > 0)) return {};
  const double h = longest / kCells;
  cell_volume = h * h * h;
  std::uint32_t n[3];
  for (int c = 0; c < 3; ++c) {
    n[c] = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::ceil((hi[c] - lo[c]) / h)));
  }
  std::vector<std::vector<T>> slice(n[2]);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n[2], 1), [&](const auto& range) {
    for (std::uint32_t k = range.begin(); k != range.end(); ++k) {
      for (std::uint32_t j = 0; j < n[1]; ++j) {
        for (std::uint32_t i = 0; i < n[0]; ++i) {
          const double p[3] = {lo[0] + (i + 0.5) * h, lo[1] + (j + 0.5) * h, lo[2] + (k + 0.5) * h};
          if (domain.locate(p) == Sign::positive) visit(p, slice[k]);
        }
      }
    }
  });
  std::vector<T> values;
  for (const std::vector<T>& v : slice) values.insert(values.end(), v.begin(), v.end());
  return values;
}

// f at over_volume's cell centres, in its order, and the volume of one cell.
template <class F>
std::vector<double> sample_over_volume(const Domain3& domain, const F& f, double& cell_volume) {
  return over_volume<double>(
      domain, [&f](const double* p, std::vector<double>& out) { out.push_back(f(p)); },
      cell_volume);
}

// The integral of f over the volume by the midpoint rule on sample_over_volume's grid,
// summed in order (the same value for any thread count). For the scale of the sizing
// field, which needs a few digits.
template <class F>
double integrate_over_volume(const Domain3& domain, const F& f) {
  double cell = 0;
  double total = 0;
  for (const double v : sample_over_volume(domain, f, cell)) total += v;
  return total * cell;
}

// The field of the local feature size (adaptive sizing and the lfs cap): the domain's, or,
// with interfaces, that of its regions, each region's boundary (its part of the domain's
// boundary and its interfaces) seeding it, so that an inclusion or a thin layer is sized by
// its own shape as a part of the boundary would be. With skip_sharp, without the vertices of
// sharp edges (their pole distance measures the input's sampling, not its shape).
std::unique_ptr<SizingField3> lfs_field(const Domain3& domain, const RegionInterfaces* interfaces,
                                        const Mesh3Options& options, bool skip_sharp) {
  const auto sharp_vertices = [&](const Domain3& d) {
    std::vector<std::uint8_t> skip;
    if (!skip_sharp || !options.features) return skip;
    skip.assign(d.nb_vertices(), 0);
    const FeatureLines sharp =
        extract_feature_lines(boundary_surface(d), options.feature_angle_deg, d.boundary_refs());
    for (const std::uint32_t v : sharp.line_vertices) skip[v] = 1;
    for (const std::uint32_t v : sharp.corners) skip[v] = 1;
    return skip;
  };
  if (!interfaces) {
    return std::make_unique<SizingField3>(domain, options.sizing, sharp_vertices(domain));
  }
  std::vector<const Domain3*> parts;
  std::vector<std::vector<std::uint8_t>> skips;
  for (const Domain3& region : interfaces->regions) {
    parts.push_back(&region);
    skips.push_back(sharp_vertices(region));
  }
  return std::make_unique<SizingField3>(domain, parts, options.sizing, skips);
}

// The lfs cap's samples over a volume: the lfs field off the sharp edges (lfs_field), and
// the cap, lfs_cap times it, at the cells of sample_over_volume's grid, each of volume `cell`.
struct CapSamples {
  std::unique_ptr<SizingField3> field;
  std::vector<double> caps;
  double cell = 0;
};

CapSamples lfs_cap_samples(const Domain3& domain, const RegionInterfaces* interfaces,
                           const Mesh3Options& options) {
  CapSamples c;
  c.field = lfs_field(domain, interfaces, options, true);
  const SizingField3* h = c.field.get();
  const double k = options.lfs_cap;
  c.caps = sample_over_volume(
      domain, [h, k](const double* p) { return k * h->size(p); }, c.cell);
  return c;
}

// The regions of a body whose interfaces mesh3d follows (null when it follows none).
std::unique_ptr<RegionInterfaces> followed_interfaces(const Domain3& body) {
  auto found = std::make_unique<RegionInterfaces>();
  std::string why_not;
  if (!region_interfaces(body, *found, why_not)) return nullptr;
  return found;
}

// The sites' density under the cap at a sample c (cap value), for the uniform spacing H (0:
// the cap's shape, lfs_cap / c): (spacing / local spacing)^3.
double capped_ratio(double c, double H, double k) {
  const double r = H == 0 ? k / c : std::max(1.0, H / c);
  return r * r * r;
}

// The uniform spacing H of n sites under the cap over the volumes `parts` (the whole domain,
// or each of its bodies): the sites' spacing is min(H, cap(x)), so n = integral of
// max(1, (H / cap)^3) / H^3. H^3 n - integral grows with H (its derivative is 3 H^2 times n
// minus the cap's own count, positive while a root exists): bisection. 0 when no H gives n
// (the cap alone needs n sites or more).
double capped_spacing(const std::vector<const CapSamples*>& parts, double n) {
  const auto excess = [&](double H) {
    double integral = 0;
    for (const CapSamples* part : parts) {
      double sum = 0;
      for (const double c : part->caps) sum += c < H ? (H / c) * (H / c) * (H / c) : 1.0;
      integral += sum * part->cell;
    }
    return H * H * H * n - integral;
  };
  double volume = 0;
  for (const CapSamples* part : parts)
    volume += part->cell * static_cast<double>(part->caps.size());
  double lo = std::cbrt(volume / n), hi = lo;
  if (excess(lo) >= 0) return lo;  // the cap binds nowhere at the uniform spacing
  for (int k = 0; excess(hi) < 0; ++k) {
    if (k == 60) return 0;
    hi *= 2;
  }
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (excess(mid) < 0 ? lo : hi) = mid;
  }
  return hi;
}

// The integral over the volume of h^-3 for the user's density (rho = h^-5, so h^-3 =
// rho^(3/5)): n sites of density h^-3 have spacing about (integral / n)^(1/3) h(x). The
// volume for a constant density; Error for a density linear per tet.
double density_sites_integral(const Domain3& domain, const Density3& rho) {
  if (rho.is_constant()) return domain.volume();
  if (rho.kind != Density3::Kind::kCallback || !rho.callback) {
    throw Error(
        "mesh3d: the density must be a function (a density linear per tet is not supported "
        "here)");
  }
  if (!rho.batch) {
    return integrate_over_volume(
        domain, [&rho](const double* p) { return std::pow(rho.callback(p[0], p[1], p[2]), 0.6); });
  }
  // A density given at many points at once (an interpreted formula, a Python callable
  // pays its call once): the centres first, rho at all of them in one call, then the
  // same sum in the same order as integrate_over_volume's (the same bits).
  double cell = 0;
  const std::vector<double> xyz = over_volume<double>(
      domain, [](const double* p, std::vector<double>& out) { out.insert(out.end(), p, p + 3); },
      cell);
  std::vector<double> values(xyz.size() / 3);
  rho.batch(xyz.data(), values.size(), values.data());
  double total = 0;
  for (const double v : values) total += std::pow(v, 0.6);
  return total * cell;
}

// "more than" (bound 1) or "<ratio> times" (bound other than 1).
std::string more_than(double ratio, double bound) {
  return bound == 1 ? "more than" : brief(ratio) + " times";
}

// Step 8's distance check: result.distance (the output's boundary against the domain's,
// `reference` with its tree) and result.distance_to_edge_length, the largest sampled
// distance either way over edge_length at the sample (a constant when not graded: the
// plain distances divided by it). What is wrong when that exceeds `bound` (> 0), else "".
std::string check_boundary_distance(const TriangleSurface& reference,
                                    const SurfaceTree& reference_tree, bool graded,
                                    const HausdorffOptions& relative, double bound,
                                    Mesh3Result& result) {
  const std::function<double(const double*)>& edge_length = relative.scale;
  if (result.boundary_triangles.empty()) return "";
  TriangleSurface mine;
  mine.source = "the mesh's boundary";
  mine.xyz = result.xyz;
  mine.triangles = result.boundary_triangles;
  const SurfaceTree mine_tree(mine);
  const HausdorffDistance& d = result.distance =
      hausdorff_distance(mine, mine_tree, reference, reference_tree);
  OneSidedDistance forward = d.forward, backward = d.backward;
  if (graded) {
    forward = sampled_distance(mine, reference_tree, relative);
    backward = sampled_distance(reference, mine_tree, relative);
  } else {
    const double length = edge_length(d.forward.where);
    forward.max /= length;
    backward.max /= length;
  }
  const bool cut = backward.max >= forward.max;
  const OneSidedDistance& worst = cut ? backward : forward;
  result.distance_to_edge_length = worst.max;
  if (!(bound > 0 && worst.max > bound)) return "";
  const double length = edge_length(worst.where);
  const std::string at = "(" + brief(worst.where[0]) + ", " + brief(worst.where[1]) + ", " +
                         brief(worst.where[2]) + ")";
  return cut ? "the domain's surface at " + at + " is " + brief(worst.max * length) +
                   " from its boundary, " + more_than(worst.max, bound) +
                   " the local edge length " + brief(length) +
                   " (a part thinner than the edges is cut off)"
             : "its boundary at " + at + " is " + brief(worst.max * length) +
                   " from the domain's surface, " + more_than(worst.max, bound) +
                   " the local edge length " + brief(length) +
                   " (it bridges a gap or rounds off a part narrower than the edges)";
}

}  // namespace

// x to 4 significant digits.
std::string brief(double x) {
  std::ostringstream out;
  out << std::setprecision(4) << x;
  return out.str();
}

std::vector<double> body_site_integrals(const std::vector<Domain3>& bodies,
                                        const Mesh3Options& options) {
  std::vector<double> integrals;
  if (!options.density.is_constant()) {
    for (const Domain3& body : bodies)
      integrals.push_back(density_sites_integral(body, options.density));
  } else if (options.adaptive) {
    for (const Domain3& body : bodies) {
      const std::unique_ptr<SizingField3> h =
          lfs_field(body, followed_interfaces(body).get(), options, false);
      const SizingField3& field = *h;
      integrals.push_back(integrate_over_volume(body, [&field](const double* p) {
        const double s = field.size(p);
        return 1 / (s * s * s);
      }));
    }
  } else if (options.lfs_cap > 0) {
    // One uniform spacing H for all the bodies: each body's run, with its integral's share of
    // the sites, solves its H from its own samples, which are these.
    std::vector<CapSamples> samples;
    std::vector<const CapSamples*> parts;
    for (const Domain3& body : bodies)
      samples.push_back(lfs_cap_samples(body, followed_interfaces(body).get(), options));
    for (const CapSamples& c : samples) {
      if (!c.caps.empty()) parts.push_back(&c);
    }
    const double H = parts.empty() ? 0 : capped_spacing(parts, options.nb_vertices);
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      double sum = 0;
      for (const double c : samples[b].caps) sum += capped_ratio(c, H, options.lfs_cap);
      // A body no cell centre of the grid falls in: uncapped, its volume.
      integrals.push_back(samples[b].caps.empty() ? bodies[b].volume() : sum * samples[b].cell);
    }
  } else {
    for (const Domain3& body : bodies) integrals.push_back(body.volume());
  }
  return integrals;
}

Mesh3Result raise_vertices(const Mesh3Options& options, Mesh3Result result,
                           const std::function<Mesh3Result(const Mesh3Options&)>& run,
                           const std::function<bool(const Mesh3Result&)>& wrong,
                           const std::string& what) {
  Mesh3Options raised = options;
  double seconds = result.total_seconds;
  // A part far thinner than the spacing (the topology sites capped): when a uniform spacing
  // resolving it needs more than 4 times the count the retries reach, they would only take
  // time (a 1 x 1 x 0.001 plate at 1,000 vertices: 2.5 minutes, about 250,000 needed).
  const double reach = std::ldexp(static_cast<double>(options.nb_vertices),
                                  static_cast<int>(std::min(options.max_shape_retries, 64u)));
  if (options.max_shape_retries > 0 && wrong(result) && result.topology_capped &&
      result.topology_capped_vertices > 4 * reach) {
    result.shape_retries_skipped = true;
    return result;
  }
  for (std::uint32_t retry = 1; retry <= options.max_shape_retries && !result.cancelled &&
                                wrong(result) && raised.nb_vertices <= 0x7fffffffu;
       ++retry) {
    raised.nb_vertices *= 2;
    if (options.progress) {
      Mesh3Progress p;
      p.retry_vertices = raised.nb_vertices;
      if (!options.progress(p)) {
        result.cancelled = true;
        break;
      }
    }
    const std::string because =
        result.raised_because.empty() ? what + result.shape_problem : result.raised_because;
    Mesh3Result next = run(raised);
    seconds += next.total_seconds;
    next.total_seconds = seconds;
    next.requested_vertices = options.nb_vertices;
    next.shape_retries = std::max(next.shape_retries, retry);
    next.raised_because = because;
    result = std::move(next);
  }
  return result;
}

void measure_mesh3_quality(const Domain3& domain, Mesh3Result& result) {
  TetQualityOptions qo;
  qo.keep_per_tet = true;
  result.quality = tet_quality(result.xyz.data(), result.nb_vertices(), result.tets.data(),
                               result.nb_tets(), qo);
  result.input_sharpest_dihedral_deg = sharpest_dihedral_deg(domain.surface());
  result.dihedral_bound_deg = std::min(20.0, result.input_sharpest_dihedral_deg / 2);
  result.nb_tets_below_bound = 0;
  for (Mesh3Result::Q1Class& c : result.q1_by_boundary_vertices) c = {};
  for (std::uint32_t t = 0; t < result.nb_tets(); ++t) {
    int on_boundary = 0;
    for (int k = 0; k < 4; ++k) {
      on_boundary += result.kinds[result.tets[4 * std::size_t{t} + static_cast<std::size_t>(k)]] !=
                     Mesh3VertexKind::kInterior;
    }
    Mesh3Result::Q1Class& c = result.q1_by_boundary_vertices[on_boundary == 4   ? 0
                                                             : on_boundary == 3 ? 1
                                                                                : 2];
    const double q1 = result.quality.per_tet[t].q1_deg;
    result.nb_tets_below_bound += q1 < result.dihedral_bound_deg;
    c.min_deg = c.nb_tets == 0 ? q1 : std::min(c.min_deg, q1);
    c.mean_deg += q1;
    ++c.nb_tets;
  }
  for (Mesh3Result::Q1Class& c : result.q1_by_boundary_vertices) {
    if (c.nb_tets > 0) c.mean_deg /= c.nb_tets;
  }
  result.quality.per_tet = {};
}

bool Pipeline::notify(Mesh3Progress p) const {
  p.phase = phase;
  p.seconds = since(t_start);
  return !options.progress || options.progress(p);
}

void Pipeline::report(const Mesh3Progress& p) const {
  if (!notify(p)) throw Cancelled{};
}

void Pipeline::next_phase(Mesh3Phase next) {
  result.seconds[static_cast<int>(phase)] += since(t_phase);
  t_phase = Clock::now();
  phase = next;
  report({});
}

std::function<bool(const CvtProgress&)> Pipeline::cvt_progress() const {
  return [this](const CvtProgress& c) {
    Mesh3Progress p;
    p.iteration = c.iteration;
    p.energy = c.energy;
    p.gradient_norm = c.gradient_norm;
    return notify(p);
  };
}

void Pipeline::run() {
  try {
    report({});
    // 1. Sizing.
    Clip3Options clip;
    // The local spacing of the sites is about spacing_scale * h(x) (h = 1 when uniform):
    // with n sites of density h^-3 in the volume, spacing_scale^3 = (integral of h^-3) / n.
    std::unique_ptr<SizingField3> field;
    double integral = domain.volume();
    const Density3& user_density = options.density;
    bool graded = options.adaptive || !user_density.is_constant();
    // Interfaces between the input's regions, when the mesh can follow them (closed surfaces
    // inside the volume): the sites are then sampled on the boundary and the interfaces.
    {
      auto found = std::make_unique<RegionInterfaces>();
      if (region_interfaces(domain, *found, result.interfaces_not_followed)) {
        interfaces = std::move(found);
        result.nb_interfaces_followed = interfaces->nb_interfaces;
      }
    }
    const TriangleSurface surface = interfaces ? interfaces->surface : boundary_surface(domain);
    // The input's triangle tags (a tet mesh file's boundary triangles): the borders of
    // their patches are feature lines too, kept however short or flat, so that every
    // boundary triangle of the mesh lies in one patch and carries its tag.
    const std::vector<std::int32_t>& input_tags =
        interfaces ? interfaces->refs : domain.boundary_refs();
    double cap_scale = 0;  // > 0: h = min(1, field / cap_scale)
    if (!user_density.is_constant()) {
      if (options.adaptive) throw Error("mesh3d: a density and adaptive sizing exclude each other");
      clip.density = user_density;
      integral = density_sites_integral(domain, user_density);
    } else if (options.adaptive) {
      field = lfs_field(domain, interfaces.get(), options, false);
      const SizingField3* h = field.get();
      clip.density = Density3::function([h](double x, double y, double z) {
        const double p[3] = {x, y, z};
        const double s = h->size(p);
        return 1 / (s * s * s * s * s);
      });
      integral = integrate_over_volume(domain, [h](const double* p) {
        const double s = h->size(p);
        return 1 / (s * s * s);
      });
    } else if (options.lfs_cap > 0) {
      if (!(std::isfinite(options.lfs_cap))) {
        throw Error("mesh3d: lfs_cap " + std::to_string(options.lfs_cap) +
                    "; expected a positive number or 0");
      }
      CapSamples samples = lfs_cap_samples(domain, interfaces.get(), options);
      const SizingField3* h = samples.field.get();
      const std::vector<double>& caps = samples.caps;
      const double k = options.lfs_cap;
      const double H = caps.empty() ? 0 : capped_spacing({&samples}, options.nb_vertices);
      const double smallest = caps.empty() ? 0 : *std::min_element(caps.begin(), caps.end());
      if (!caps.empty() && (H == 0 || smallest < H)) {
        // The cap binds somewhere: h = min(1, cap / H) (H = 0: the cap's shape, scaled).
        std::size_t bound = 0;
        double sum = 0;
        for (const double c : caps) {
          sum += capped_ratio(c, H, k);
          bound += H == 0 || c < H ? 1 : 0;
        }
        result.lfs_capped_fraction = static_cast<double>(bound) / static_cast<double>(caps.size());
        result.lfs_cap_spacing = H;
        cap_scale = H == 0 ? 1.0 : H / k;
        integral = sum * samples.cell;
        field = std::move(samples.field);
        graded = true;
        const bool uniform_part = H > 0;
        const double scale = cap_scale;
        clip.density = Density3::function([h, scale, uniform_part](double x, double y, double z) {
          const double p[3] = {x, y, z};
          const double s = uniform_part ? std::min(1.0, h->size(p) / scale) : h->size(p);
          return 1 / (s * s * s * s * s);
        });
      }
    }
    // The spacing where the user's density is rho (h = rho^(-1/5), scaled to the count).
    const auto density_spacing = [&](double rho) {
      return std::cbrt(integral / options.nb_vertices) * std::pow(rho, -0.2);
    };
    const auto local_spacing = [&](const double* x) {
      const double scale = std::cbrt(integral / options.nb_vertices);
      if (!user_density.is_constant()) {
        return density_spacing(user_density.callback(x[0], x[1], x[2]));
      }
      if (field && cap_scale > 0 && result.lfs_cap_spacing > 0) {
        return scale * std::min(1.0, field->size(x) / cap_scale);
      }
      return field ? scale * field->size(x) : scale;
    };
    const SurfaceTree surface_tree(surface);
    const std::vector<std::uint64_t> tag_borders = tag_border_edges(surface, input_tags);
    FeatureLines lines;
    if (options.features || !tag_borders.empty()) {
      // Without features, only the tags' borders (no edge is sharper than 180 degrees).
      const double angle = options.features ? options.feature_angle_deg : 180.0;
      lines = drop_short_lines(
          surface,
          split_at_turns(surface, extract_feature_lines(surface, angle, input_tags), angle),
          options.min_feature_length, local_spacing, tag_borders);
    }
    const FeatureTree line_tree(surface, lines);
    const std::vector<std::uint32_t> triangle_patch = triangle_patches(surface, lines);
    // The smooth surface's patches are bounded by every edge sharper than feature_angle_deg,
    // and pinned there, kept feature line or not: a crease too short to keep (or
    // features = false) is not rounded by the interpolant, which would bulge the large flat
    // triangles beside it.
    std::unique_ptr<PhongSurface> smooth;
    if (options.smooth_surface) {
      const FeatureLines sharp =
          extract_feature_lines(surface, options.feature_angle_deg, input_tags);
      std::vector<std::uint8_t> pinned(surface.nb_vertices(), 0);
      for (const std::uint32_t v : sharp.line_vertices) pinned[v] = 1;
      for (const std::uint32_t v : sharp.corners) pinned[v] = 1;
      smooth = std::make_unique<PhongSurface>(surface, triangle_patches(surface, sharp), pinned,
                                              options.smooth_shape);
    }
    result.nb_feature_lines = lines.nb_lines();
    result.nb_feature_corners = static_cast<std::uint32_t>(lines.corners.size());
    // With interfaces, the feature lines where an interface meets the boundary or another
    // interface (an edge of three triangles or more): their sites stay put in the sliver
    // perturbation, which would otherwise open gaps along them that a tet in two regions fills.
    std::vector<std::uint8_t> junction_line;
    if (interfaces) {
      const std::vector<std::uint32_t> next = triangle_neighbours(surface);
      std::vector<std::uint64_t> junctions;
      for (std::size_t i = 0; i < next.size(); ++i) {
        if (next[i] != SurfaceTree::kNone) continue;
        const std::size_t t = i / 3, e = i % 3;
        junctions.push_back(edge_key(surface.triangles[3 * t + (e + 1) % 3],
                                     surface.triangles[3 * t + (e + 2) % 3]));
      }
      std::sort(junctions.begin(), junctions.end());
      junction_line.assign(lines.nb_lines(), 0);
      for (std::uint32_t l = 0; l < lines.nb_lines(); ++l) {
        for (std::uint32_t i = lines.line_begin[l]; i + 1 < lines.line_begin[l + 1]; ++i) {
          if (std::binary_search(junctions.begin(), junctions.end(),
                                 edge_key(lines.line_vertices[i], lines.line_vertices[i + 1])))
            junction_line[l] = 1;
        }
      }
    }

    // 2. Sampling.
    next_phase(Mesh3Phase::kSampling);
    const TetExtractor3 extractor(domain);
    if (options.sampling == Mesh3Sampling::kLattice && !graded) {
      sites = lattice_sites(domain, extractor, options.nb_vertices, options.seed);
    }
    if (sites.empty()) {
      // Graded, or a part too thin for the lattice: drawn at random with the density.
      sites =
          random_points3(domain, options.nb_vertices, options.seed,
                         user_density.is_constant()
                             ? clip.density
                             : Density3::function([&user_density](double x, double y, double z) {
                                 return std::pow(user_density.callback(x, y, z), 0.6);
                               }));
    }

    // 3. Unconstrained CVT.
    next_phase(Mesh3Phase::kUnconstrained);
    Cvt3Options cvt;
    cvt.method = CvtMethod::kLbfgs;
    cvt.max_iterations = options.unconstrained_iterations;
    cvt.gradient_tolerance = options.gradient_tolerance;
    cvt.clip = clip;
    cvt.progress = cvt_progress();
    std::vector<std::uint8_t> boundary;  // per site, from the CVT's last diagram
    cvt.boundary_sites = &boundary;
    result.unconstrained = optimize_cvt3(domain, sites, cvt);
    if (result.unconstrained.cancelled) throw Cancelled{};
    mark_interface_sites(boundary, false);

    // 4. Classification and snapping.
    next_phase(Mesh3Phase::kSnapping);
    const Projection project{&surface_tree, &line_tree, &line_of, smooth.get()};
    constrain_sites(lines, line_tree, local_spacing, boundary, project);

    // 5. Constrained CVT, in up to three stages (two thirds of the iterations, then the
    // rest, then a few more): after a stage, free sites whose cells now reach the boundary
    // (the boundary layer settles after the snapping) are snapped to the surface too, or
    // they would become boundary vertices inside the volume.
    next_phase(Mesh3Phase::kConstrained);
    cvt.project = project;
    const std::uint32_t total = options.constrained_iterations;
    const std::uint32_t stages[3] = {total - total / 3, std::max<std::uint32_t>(total / 3, 1), 5};
    for (int stage = 0; stage < 3; ++stage) {
      cvt.max_iterations = stages[stage];
      cvt.constraints = kinds;
      const CvtResult r = optimize_cvt3(domain, sites, cvt);
      if (r.cancelled) throw Cancelled{};
      mark_interface_sites(boundary, true);
      if (stage == 0) {
        result.constrained = r;
      } else {
        result.constrained.iterations += r.iterations;
        result.constrained.evaluations += r.evaluations;
        result.constrained.energy = r.energy;
        result.constrained.gradient_norm = r.gradient_norm;
        result.constrained.seconds += r.seconds;
        result.constrained.converged = r.converged;
      }
      if (stage == 2) break;
      if (snap_boundary_free_sites(boundary, project) == 0) break;
    }

    // 5a. Distance to the input: sites fixed at the input vertices the boundary cuts off.
    approximate_boundary(extractor, cvt, local_spacing, boundary, project, [&] {
      return site_patches(surface, lines, surface_tree, line_tree, sites, kinds, line_of,
                          corner_vertex, triangle_patch);
    });

    // 5b. Topology: sites where the restricted Voronoi diagram lacks the closed-ball
    // property (closed_ball_defects), round after round with no CVT in between (the
    // farthest-point refinement, which converges), then a short constrained CVT to spread
    // them, checked again; the last state without defects is the one meshed (a CVT that
    // breaks the property is undone when more rounds cannot repair it).
    next_phase(Mesh3Phase::kTopology);
    repair_topology(surface, clip, cvt, boundary, project);
    // With interfaces, the CVT can open gaps along the lines where an interface meets the
    // boundary (a flat face on both sides: its surface sites close in on the line from both),
    // and a tet across such a gap lies in two regions: the gaps get sites again, as in step 4.
    if (interfaces) refill_line_gaps(line_tree, local_spacing);

    // 6. Extraction; 7. slivers (mesh3d_slivers.cpp).
    std::vector<std::uint32_t> tets;
    SurfacePatches patches;
    TetRegions regions;
    const Spacing spacing(local_spacing);
    make_tets({extractor, surface, surface_tree, lines, line_tree, triangle_patch, junction_line,
               spacing, project},
              tets, patches, regions);

    // 8. Output: the used sites, renumbered in site order.
    next_phase(Mesh3Phase::kQuality);
    std::vector<std::uint32_t> index(n, SurfaceTree::kNone);
    for (const std::uint32_t v : tets) index[v] = 0;
    std::uint32_t nv = 0;
    for (std::uint32_t s = 0; s < n; ++s) {
      if (index[s] == SurfaceTree::kNone) {
        ++result.nb_dropped_sites;
        continue;
      }
      index[s] = nv++;
      result.xyz.insert(result.xyz.end(), &sites[3 * std::size_t{s}],
                        &sites[3 * std::size_t{s}] + 3);
      result.kinds.push_back(kinds[s] == Kind::kSurface ? Mesh3VertexKind::kSurface
                             : kinds[s] == Kind::kCurve ? Mesh3VertexKind::kFeature
                             : kinds[s] == Kind::kFixed ? Mesh3VertexKind::kCorner
                                                        : Mesh3VertexKind::kInterior);
    }
    result.tets.resize(tets.size());
    for (std::size_t i = 0; i < tets.size(); ++i) result.tets[i] = index[tets[i]];

    // Boundary triangles and tags: patches (the input's triangle tags, else the patches
    // between feature lines, from 1) and regions (the input's tet tags, else one per volume
    // component).
    tag_mesh3(domain, surface_tree, triangle_patch, patches, index, interfaces ? &regions : nullptr,
              result);
    if (interfaces) tag_interfaces(*interfaces, surface_tree, regions, result);
    measure_mesh3_quality(domain, result);
    result.shape_problem = check_mesh3_shape(domain, result.xyz, result.tets);
    if (result.shape_problem.empty() && interfaces)
      result.shape_problem = interface_shape(*interfaces, result.xyz, result.tets, regions);
    const Clock::time_point t_distance = Clock::now();
    const double edge_per_spacing = std::cbrt(kMesh3VerticesPerEdgeVolume);
    // The distance of the boundary to the domain's surface (without the interfaces).
    const TriangleSurface boundary_only = interfaces ? boundary_surface(domain) : TriangleSurface{};
    const std::unique_ptr<SurfaceTree> boundary_tree =
        interfaces ? std::make_unique<SurfaceTree>(boundary_only) : nullptr;
    // The local edge length; a user density with a batch form (a Python function, an
    // expression) is evaluated a block of samples at a time (local_spacing's values).
    HausdorffOptions relative;
    relative.scale = [&](const double* x) { return edge_per_spacing * local_spacing(x); };
    if (user_density.kind == Density3::Kind::kCallback && user_density.batch) {
      relative.scale_batch = [&](const double* xyz, std::size_t count, double* out) {
        user_density.batch(xyz, count, out);
        for (std::size_t k = 0; k < count; ++k) out[k] = edge_per_spacing * density_spacing(out[k]);
      };
    }
    std::string far = check_boundary_distance(interfaces ? boundary_only : surface,
                                              interfaces ? *boundary_tree : surface_tree, graded,
                                              relative, options.max_boundary_distance, result);
    if (far.empty() && interfaces) {
      far = interface_distance(*interfaces, relative, options.max_boundary_distance, result);
    }
    result.distance_seconds = since(t_distance);
    if (result.shape_problem.empty()) result.shape_problem = std::move(far);
    result.seconds[static_cast<int>(phase)] += since(t_phase);
  } catch (const Cancelled&) {
    result.cancelled = true;
    result.xyz.clear();
    result.kinds.clear();
    result.tets.clear();
  }
  result.total_seconds = since(t_start);
}

}  // namespace mesh3

const char* mesh3_phase_name(Mesh3Phase phase) {
  switch (phase) {
    case Mesh3Phase::kSizing:
      return "sizing";
    case Mesh3Phase::kSampling:
      return "sampling";
    case Mesh3Phase::kUnconstrained:
      return "unconstrained";
    case Mesh3Phase::kSnapping:
      return "snapping";
    case Mesh3Phase::kConstrained:
      return "constrained";
    case Mesh3Phase::kTopology:
      return "topology";
    case Mesh3Phase::kExtraction:
      return "extraction";
    case Mesh3Phase::kSlivers:
      return "slivers";
    case Mesh3Phase::kQuality:
      return "quality";
  }
  return "?";
}

TriangleSurface boundary_surface(const Domain3& domain) {
  TriangleSurface s;
  s.source = domain.source() + " (boundary)";
  s.xyz = domain.coords();
  s.triangles.reserve(3 * std::size_t{domain.surface().nb_triangles()});
  s.triangles = domain.surface().triangles();
  s.triangle_line.assign(domain.surface().nb_triangles(), 0);
  return s;
}
Mesh3Result mesh3d(const Domain3& domain, const Mesh3Options& options) {
  if (options.edge_length != 0) {
    // An absolute size: the vertex count it takes, then the run with that count.
    if (!(options.edge_length > 0) || !std::isfinite(options.edge_length)) {
      throw Error("mesh3d: edge length " + std::to_string(options.edge_length) +
                  "; expected a positive number");
    }
    if (options.adaptive)
      throw Error("mesh3d: an absolute edge length and adaptive sizing exclude each other");
    if (domain.surface().nb_triangles() == 0) throw Error("mesh3d: the domain has no boundary");
    const double integral = mesh3::density_sites_integral(domain, options.density);
    const double h = options.edge_length;
    const double n = std::round(kMesh3VerticesPerEdgeVolume * integral / (h * h * h));
    if (!(n <= 2e9)) {
      // n as an integer ("7880381944 vertices", not "7880381944.000000"); %.0f also for n
      // beyond 64 bits.
      char count[64];
      std::snprintf(count, sizeof count, "%.0f", n);
      throw Error("mesh3d: the edge length asks for " + std::string(count) +
                  " vertices; at most 2e9");
    }
    Mesh3Options o = options;
    o.edge_length = 0;
    o.nb_vertices = static_cast<std::uint32_t>(std::max(4.0, n));
    if (o.progress) {
      Mesh3Progress implied;
      implied.implied_vertices = o.nb_vertices;
      if (!o.progress(implied)) {
        Mesh3Result cancelled;
        cancelled.cancelled = true;
        return cancelled;
      }
    }
    return mesh3d(domain, o);
  }
  if (options.nb_vertices < 4) {
    throw Error("mesh3d: " + std::to_string(options.nb_vertices) + " vertices; need at least 4");
  }
  if (!(options.feature_angle_deg >= 0 && options.feature_angle_deg <= 180)) {
    throw Error("mesh3d: feature angle " + std::to_string(options.feature_angle_deg) +
                " degrees; expected a value in [0, 180]");
  }
  if (!(options.facet_distance >= 0) || !std::isfinite(options.facet_distance) ||
      !(options.facet_distance_budget >= 0 && options.facet_distance_budget <= 1)) {
    throw Error("mesh3d: facet_distance " + std::to_string(options.facet_distance) +
                ", facet_distance_budget " + std::to_string(options.facet_distance_budget) +
                "; expected a number >= 0 and a fraction in [0, 1]");
  }
  if (!(options.max_topology_sites >= 0) || !std::isfinite(options.max_topology_sites)) {
    throw Error("mesh3d: max_topology_sites " + std::to_string(options.max_topology_sites) +
                "; expected a finite number >= 0");
  }
  if (!(options.flip_dihedral_deg >= 0 && options.flip_dihedral_deg < 70.5) ||
      !(options.flip_gain_deg >= 0) || !std::isfinite(options.flip_gain_deg) ||
      !(options.flip_q4 >= 0 && options.flip_q4 <= 1)) {
    throw Error("mesh3d: flip_dihedral_deg " + std::to_string(options.flip_dihedral_deg) +
                ", flip_gain_deg " + std::to_string(options.flip_gain_deg) + ", flip_q4 " +
                std::to_string(options.flip_q4) +
                "; expected degrees in [0, 70.5), a finite gain >= 0 and a Q4 in [0, 1]");
  }
  if (!(options.max_boundary_distance >= 0) || !std::isfinite(options.max_boundary_distance)) {
    throw Error("mesh3d: max_boundary_distance " + std::to_string(options.max_boundary_distance) +
                "; expected a number >= 0 (0: not checked)");
  }
  if (!(options.smooth_shape >= 0 && options.smooth_shape <= 1)) {
    throw Error("mesh3d: smooth_shape " + std::to_string(options.smooth_shape) +
                "; expected a value in [0, 1]");
  }
  // As the command line's checks: NaN fails every comparison, so each test is written to
  // refuse it.
  if (!(options.perturbation.target_dihedral_deg >= 0 &&
        options.perturbation.target_dihedral_deg < 70.5)) {
    throw Error("mesh3d: sliver angle (perturbation.target_dihedral_deg) " +
                std::to_string(options.perturbation.target_dihedral_deg) +
                "; expected degrees in [0, 70.5)");
  }
  if (!(options.lfs_cap >= 0) || !std::isfinite(options.lfs_cap)) {
    throw Error("mesh3d: lfs_cap " + std::to_string(options.lfs_cap) +
                "; expected a finite number >= 0 (0: no cap)");
  }
  if (!(options.gradient_tolerance >= 0) || !std::isfinite(options.gradient_tolerance)) {
    throw Error("mesh3d: gradient_tolerance " + std::to_string(options.gradient_tolerance) +
                "; expected a finite number >= 0");
  }
  if (!(options.min_feature_length >= 0) || !std::isfinite(options.min_feature_length)) {
    throw Error("mesh3d: min_feature_length " + std::to_string(options.min_feature_length) +
                "; expected a finite number >= 0");
  }
  if (domain.surface().nb_triangles() == 0) throw Error("mesh3d: the domain has no boundary");
  const std::vector<Domain3> bodies = mesh3::domain_bodies(domain);
  if (!bodies.empty()) return mesh3::mesh3d_bodies(domain, bodies, options);
  Mesh3Result result;
  mesh3::Pipeline(domain, options, result).run();
  result.requested_vertices = options.nb_vertices;
  if (options.vertex_count != Mesh3Options::VertexCount::kRaise) return result;
  // A mesh of the wrong shape: features thinner than the sites' spacing. Run again with
  // twice the vertices until the shape is right.
  result = mesh3::raise_vertices(
      options, std::move(result),
      [&domain](const Mesh3Options& raised) {
        Mesh3Result next;
        mesh3::Pipeline(domain, raised, next).run();
        return next;
      },
      [](const Mesh3Result& r) { return !r.shape_problem.empty(); }, "");
  return result;
}

}  // namespace voroclip
