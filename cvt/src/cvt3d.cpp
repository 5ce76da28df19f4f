// CVT in 3D: energy and gradient from the clipped Voronoi diagram of a tet-mesh volume
// (Yan et al. 2011, sec. 2 and 5.2, eq. 1-3), minimised by Lloyd's iteration or by
// L-BFGS (Liu, Wang, Lévy et al., "On centroidal Voronoi tessellation — energy smoothness
// and fast computation", ACM TOG 2009) through LBFGSpp.
//
// Constrained sites (on a surface or a curve) are parametrised by a free point z of space
// and placed at its projection x = P(z) (Cvt3Options::project); their gradient is the
// tangential part of dF/dx (eq. 3). Over z above a flat facet (a straight segment), P is
// an orthogonal projection onto a plane (line) and that is the exact derivative of
// F(P(z)), so the line searches see a consistent function and gradient.
#include <LBFGS.h>
#include <LBFGSpp/LineSearchNocedalWright.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "cvt_range.h"
#include "rejection_sampling.h"
#include "voroclip/cvt.h"

namespace voroclip {

namespace {

using Kind3 = SiteConstraint3::Kind;

struct Cancelled3 {};
struct Converged3 {};
// L-BFGS: max_iterations accepted points (iterations) reached.
struct Budget3 {};

// The scale of the L-BFGS variables: z = s x, s a power of two (exact both ways). LBFGSpp's
// first step has unit length in z, so without scaling it depends on the model's units: per
// site about 1 / sqrt(variables) against the spacing h = cbrt(volume / n); r, that ratio, is
// 0.14 for bunny.obj at 10^4 sites and 0.001 for elk.off (diagonal 269), where the line
// searches cope, but bunny scaled by 2^-40 (r ~ 10^11) made no iteration and scaled by 2^20
// (r ~ 10^-7) lowered |g| by 3 % in 16 (the 2D CVT preconditions for the same reason). Within
// [2^-16, 2^8] s = 1, so such models keep their bits; outside, s brings r to 1/8 (and the
// energy is scaled too: Problem3::objective_scale).
double variable_scale(const Domain3& domain, std::size_t n, std::size_t nb_variables) {
  if (n == 0 || nb_variables == 0) return 1;
  const double h = std::cbrt(domain.volume() / static_cast<double>(n));
  const double r = 1 / (std::sqrt(static_cast<double>(nb_variables)) * h);
  if (!(h > 0) || !std::isfinite(r)) return 1;
  const int e = std::ilogb(r);
  if (e >= -16 && e < 8) return 1;
  // A unit step in z is a step of 1 / s in x: r becomes r / s = 1/8 or so.
  return std::ldexp(1.0, std::clamp(e + 3, -900, 900));
}

class Problem3 {
 public:
  Problem3(const Domain3& domain, std::vector<double>& sites, const Cvt3Options& options)
      : domain_(domain), sites_(sites), options_(options), n_(sites.size() / 3) {
    if (sites.size() % 3 != 0) throw Error("cvt3d: the site array's length is not a multiple of 3");
    if (!options.constraints.empty() && options.constraints.size() != n_) {
      throw Error("cvt3d: " + std::to_string(options.constraints.size()) + " constraints for " +
                  std::to_string(n_) + " sites");
    }
    offset_.resize(n_ + 1, 0);
    for (std::size_t i = 0; i < n_; ++i) {
      const Kind3 k = kind(i);
      if ((k == Kind3::kSurface || k == Kind3::kCurve) && !options.project) {
        throw Error("cvt3d: site " + std::to_string(i) +
                    " (from 0) is constrained to a surface or curve, but no projection is given");
      }
      offset_[i + 1] = offset_[i] + (k == Kind3::kFixed ? 0 : 3);
    }
    direction_.assign(3 * n_, 0);
    scale_ = variable_scale(domain, n_, nb_variables());
    clip_options_ = options.clip;
    clip_options_.keep_geometry = false;
  }

  std::size_t nb_variables() const { return offset_[n_]; }
  // The variables are the coordinates times this power of two (variable_scale).
  double scale() const { return scale_; }
  // L-BFGS minimises the energy times this power of two, c, fixed at the first evaluation:
  // 1 when scale() is 1 (models in common units keep their bits), otherwise within a factor
  // 2 of s^2 / (2 m), m the mean mass of the cells, which makes the Hessian in the variables
  // about the identity (the coordinates' Hessian is about 2 m I). Without it the gradient in
  // the variables grows as L^5 for a model of size L (L^4 for the coordinates' gradient, L
  // for 1 / s), its squared norm overflowed from L ~ 10^31 and underflowed below 10^-31,
  // and the sphere scaled by 1e32 or 1e-35 stopped "converged" at iteration 0 with |g| inf
  // or 0. With it the variables, the energy and the gradient L-BFGS sees are about 1 in any
  // units, and powers of two keep the bits of the run (the same iterations, scaled).
  double objective_scale() const { return std::ldexp(1.0, objective_exponent_); }
  // |g_x|, the norm of the coordinates' gradient, from the gradient g in the variables
  // (c g_x / s), without overflow or underflow of the squares.
  double coordinate_norm(const Eigen::VectorXd& g) const {
    return std::ldexp(cvt_detail::euclidean_norm(g), std::ilogb(scale_) - objective_exponent_);
  }
  Kind3 kind(std::size_t i) const {
    return options_.constraints.empty() ? Kind3::kFree : options_.constraints[i];
  }

  // Current sites -> variables (constrained sites are projected first: z = x = P(x)).
  Eigen::VectorXd variables() {
    Eigen::VectorXd z(static_cast<Eigen::Index>(nb_variables()));
    for (std::size_t i = 0; i < n_; ++i) {
      const Kind3 k = kind(i);
      if (k == Kind3::kFixed) continue;
      if (k != Kind3::kFree) project(i, &sites_[3 * i]);
      const auto o = static_cast<Eigen::Index>(offset_[i]);
      for (int c = 0; c < 3; ++c) z[o + c] = scale_ * sites_[3 * i + static_cast<std::size_t>(c)];
    }
    return z;
  }

  // Variables -> sites.
  void place(const Eigen::VectorXd& z) {
    for (std::size_t i = 0; i < n_; ++i) {
      const Kind3 k = kind(i);
      if (k == Kind3::kFixed) continue;
      const auto o = static_cast<Eigen::Index>(offset_[i]);
      double p[3] = {z[o] / scale_, z[o + 1] / scale_, z[o + 2] / scale_};
      if (k != Kind3::kFree) project(i, p);
      for (int c = 0; c < 3; ++c) sites_[3 * i + static_cast<std::size_t>(c)] = p[c];
    }
  }

  // Energy at the current sites (not scaled); gradient with respect to the variables of the
  // objective: the coordinates' gradient times objective_scale() / scale().
  double evaluate(Eigen::VectorXd* grad) {
    // (The triangulation of the sites in spatial order: ClippedVoronoi3 sorts them.)
    cv_.compute(domain_, sites_.data(), static_cast<std::uint32_t>(n_), clip_options_);
    if (evaluations_ == 0) set_objective_scale();
    ++evaluations_;
    if (grad) {
      grad->resize(static_cast<Eigen::Index>(nb_variables()));
      for (std::size_t i = 0; i < n_; ++i) {
        const Kind3 k = kind(i);
        if (k == Kind3::kFixed) continue;
        const auto u = static_cast<std::uint32_t>(i);
        const double m2 = 2 * cv_.mass(u);
        const double* c = cv_.centroid(u);
        double g[3];
        for (int a = 0; a < 3; ++a)
          g[a] = m2 * (sites_[3 * i + static_cast<std::size_t>(a)] - c[a]);
        const double* d = &direction_[3 * i];
        const double gd = g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
        if (k == Kind3::kSurface) {
          for (int a = 0; a < 3; ++a) g[a] -= gd * d[a];
        } else if (k == Kind3::kCurve) {
          for (int a = 0; a < 3; ++a) g[a] = gd * d[a];
        }
        const auto o = static_cast<Eigen::Index>(offset_[i]);
        for (int a = 0; a < 3; ++a) (*grad)[o + a] = g[a] * gradient_factor_;
      }
    }
    return cv_.total_energy();
  }

  // Lloyd: every site to its cell's centroid (constrained sites: its projection).
  void lloyd_step() {
    for (std::size_t i = 0; i < n_; ++i) {
      const Kind3 k = kind(i);
      const auto u = static_cast<std::uint32_t>(i);
      if (k == Kind3::kFixed || cv_.mass(u) <= 0) continue;
      double p[3] = {cv_.centroid(u)[0], cv_.centroid(u)[1], cv_.centroid(u)[2]};
      if (k != Kind3::kFree) project(i, p);
      for (int c = 0; c < 3; ++c) sites_[3 * i + static_cast<std::size_t>(c)] = p[c];
    }
  }

  std::uint32_t evaluations() const { return evaluations_; }

  // 1 for the sites whose clipped cell meets the boundary, at the last evaluation.
  void boundary_flags(std::vector<std::uint8_t>& out) const {
    out.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      out[i] = cv_.is_boundary(static_cast<std::uint32_t>(i)) ? 1 : 0;
    }
  }

 private:
  // p <- P(p), and the constraint's direction there.
  void project(std::size_t i, double* p) {
    double q[3], d[3] = {0, 0, 0};
    options_.project(static_cast<std::uint32_t>(i), kind(i), p, q, d);
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(len > 0) || !std::isfinite(q[0]) || !std::isfinite(q[1]) || !std::isfinite(q[2])) {
      throw Error("cvt3d: the projection of site " + std::to_string(i) +
                  " (from 0) returned a non-finite point or a zero direction");
    }
    for (int c = 0; c < 3; ++c) {
      p[c] = q[c];
      direction_[3 * i + static_cast<std::size_t>(c)] = d[c] / len;
    }
  }

  // objective_scale() from the first diagram's masses (see there).
  void set_objective_scale() {
    objective_exponent_ = 0;
    const double m2 = 2 * cv_.total_mass() / static_cast<double>(std::max<std::size_t>(n_, 1));
    if (scale_ != 1 && m2 > 0 && std::isfinite(m2)) {
      objective_exponent_ = std::clamp(2 * std::ilogb(scale_) - std::ilogb(m2), -1000, 1000);
    }
    gradient_factor_ = std::ldexp(1.0, objective_exponent_ - std::ilogb(scale_));
  }

  const Domain3& domain_;
  std::vector<double>& sites_;
  const Cvt3Options& options_;
  std::size_t n_;
  std::vector<std::size_t> offset_;
  std::vector<double> direction_;  // per site: unit normal (surface) or tangent (curve)
  Clip3Options clip_options_;
  ClippedVoronoi3 cv_;
  std::uint32_t evaluations_ = 0;
  double scale_ = 1;
  int objective_exponent_ = 0;  // objective_scale() = 2^objective_exponent_
  double gradient_factor_ = 1;  // objective_scale() / scale()
};

double seconds_since3(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double tet_det(const Domain3& d, std::uint32_t t) {
  const double* a = d.vertex(d.tet_vertex(t, 0));
  double u[3][3];
  for (int k = 0; k < 3; ++k) {
    const double* b = d.vertex(d.tet_vertex(t, k + 1));
    for (int c = 0; c < 3; ++c) u[k][c] = b[c] - a[c];
  }
  return std::fabs(u[0][0] * (u[1][1] * u[2][2] - u[1][2] * u[2][1]) -
                   u[0][1] * (u[1][0] * u[2][2] - u[1][2] * u[2][0]) +
                   u[0][2] * (u[1][0] * u[2][1] - u[1][1] * u[2][0]));
}

}  // namespace

const char* cvt_stop_name(CvtStop stop) {
  switch (stop) {
    case CvtStop::kConverged:
      return "converged";
    case CvtStop::kIterationBudget:
      return "iteration budget";
    case CvtStop::kNoProgress:
      return "no progress";
    case CvtStop::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

double cvt_energy3(const Domain3& domain, const std::vector<double>& sites,
                   const Clip3Options& options, std::vector<double>* gradient) {
  if (sites.size() % 3 != 0) throw Error("cvt3d: the site array's length is not a multiple of 3");
  const auto n = static_cast<std::uint32_t>(sites.size() / 3);
  ClippedVoronoi3 cv;
  Clip3Options o = options;
  o.keep_geometry = false;
  cv.compute(domain, sites.data(), n, o);
  if (gradient) {
    gradient->resize(sites.size());
    for (std::uint32_t i = 0; i < n; ++i) {
      for (std::uint32_t c = 0; c < 3; ++c) {
        (*gradient)[3 * i + c] = 2 * cv.mass(i) * (sites[3 * i + c] - cv.centroid(i)[c]);
      }
    }
  }
  return cv.total_energy();
}

Cvt3Result optimize_cvt3(const Domain3& domain, std::vector<double>& sites,
                         const Cvt3Options& options) {
  const auto t0 = std::chrono::steady_clock::now();
  Problem3 problem(domain, sites, options);
  Cvt3Result result;
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  const double size = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  const std::string model = cvt_detail::model_name("cvt3d", domain.source(), size);
  const bool has_sites = !sites.empty();
  // A volume of 0 or inf in double precision (a cube scaled by 1e-300 is valid, of volume
  // 0): every energy and gradient would be 0 and the start "converged".
  if (has_sites) cvt_detail::check_representable(model, size, "the volume", domain.volume(), 3);
  Eigen::VectorXd z = problem.variables();
  Eigen::VectorXd g;
  double f = problem.evaluate(&g);
  const double c = problem.objective_scale();
  result.initial_gradient_norm = problem.coordinate_norm(g);
  if (has_sites) {
    // The energy of sites in a volume is positive: 0 is an underflow (size^5 below 2^-1022).
    cvt_detail::check_representable(model, size, "the CVT energy of the start sites", f, 5);
    cvt_detail::check_representable(model, size, "the norm of the start gradient",
                                    result.initial_gradient_norm, 4, true);
  }
  result.energy = f;
  result.gradient_norm = result.initial_gradient_norm;
  const double target = options.gradient_tolerance * result.initial_gradient_norm;
  const auto report = [&](std::uint32_t iteration, double energy, double gnorm) {
    result.iterations = iteration;
    result.energy = energy;
    result.gradient_norm = gnorm;
    if (options.progress && !options.progress({iteration, energy, gnorm, seconds_since3(t0)})) {
      throw Cancelled3{};
    }
  };
  bool stalled = false;  // L-BFGS: the line search made no progress

  try {
    report(0, f, result.gradient_norm);
    if (result.gradient_norm <= target || z.size() == 0) {
      result.converged = true;
    } else if (options.max_iterations == 0) {
      // No iteration: the start, evaluated once (LBFGSpp would take max_iterations = 0 for
      // "no limit", and the budget is tested after an accepted point).
    } else if (options.method == CvtMethod::kLloyd) {
      for (std::uint32_t it = 1; it <= options.max_iterations; ++it) {
        problem.lloyd_step();
        f = problem.evaluate(&g);
        report(it, f, problem.coordinate_norm(g));
        if (result.gradient_norm <= target) {
          result.converged = true;
          break;
        }
      }
    } else {
      // An iteration is reported each time an evaluation improves on the best energy so
      // far (the accepted points of the line searches); the best point is kept.
      LBFGSpp::LBFGSParam<double> param;
      param.m = static_cast<int>(std::max<std::uint32_t>(options.lbfgs_memory, 1));
      param.max_iterations = static_cast<int>(options.max_iterations);
      // The stopping test is the Euclidean norm relative to |g_0|, done in the objective
      // (which ends the run by throwing).
      param.epsilon = 0;
      param.epsilon_rel = 0;
      param.past = 0;
      param.max_linesearch = 30;
      param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_STRONG_WOLFE;
      LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchNocedalWright> solver(param);
      Eigen::VectorXd best_z = z;
      double best_f = f;
      double best_gnorm = result.gradient_norm;
      // The last evaluation was at best_z: the diagram in `problem` is the best point's.
      bool last_is_best = true;
      std::uint32_t accepted = 0;
      auto fun = [&](const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
        // LBFGSpp's line search can end without moving (at its evaluation limit, when every
        // step along the direction is no better at the energy's precision); its update
        // then divides 0 by 0 and the next point is NaN. That is the end of the progress
        // this precision allows: stop there with the best point, as when the line search
        // reports the failure itself (caught below).
        if (!x.allFinite()) throw std::runtime_error("cvt3d: L-BFGS stopped making progress");
        problem.place(x);
        last_is_best = false;
        const double fx = problem.evaluate(&grad);
        // (A NaN energy is never lower, nor a NaN |g| within the tolerance: a trial point
        // whose diagram is not finite is rejected, and the line search goes on or fails.)
        if (fx < best_f) {
          best_f = fx;
          best_z = x;
          best_gnorm = problem.coordinate_norm(grad);
          last_is_best = true;
          report(++accepted, fx, best_gnorm);
          if (best_gnorm <= target) throw Converged3{};
          // LBFGSpp's own limit counts its outer iterations, and a line search can accept
          // several improving points in one: the budget is in accepted points (as cvt2d).
          if (accepted >= options.max_iterations) throw Budget3{};
        }
        return fx * c;
      };
      double fx = f * c;
      try {
        solver.minimize(fun, z, fx);
      } catch (const Converged3&) {
        result.converged = true;
      } catch (const Budget3&) {
        // The best point is the last one evaluated (last_is_best).
      } catch (const Error&) {
        throw;
      } catch (const std::invalid_argument& e) {
        throw Error(std::string("cvt3d: internal error: L-BFGS: ") + e.what());
      } catch (const std::runtime_error&) {
        // The line search could not make progress at the precision of the energy (or the
        // direction stopped being one of descent, below): the best point so far is the
        // answer.
        stalled = true;
      } catch (const std::logic_error&) {
        stalled = true;
      }
      problem.place(best_z);
      if (last_is_best) {
        // place() projects z exactly as it did before that evaluation: same sites.
        result.energy = best_f;
        result.gradient_norm = best_gnorm;
      } else {
        result.energy = problem.evaluate(&g);
        result.gradient_norm = problem.coordinate_norm(g);
      }
      result.converged = result.converged || result.gradient_norm <= target;
    }
    if (options.boundary_sites) problem.boundary_flags(*options.boundary_sites);
  } catch (const Cancelled3&) {
    result.cancelled = true;
  }
  result.stop = result.cancelled                                        ? CvtStop::kCancelled
                : result.converged                                      ? CvtStop::kConverged
                : stalled && result.iterations < options.max_iterations ? CvtStop::kNoProgress
                                                                        : CvtStop::kIterationBudget;
  result.evaluations = problem.evaluations();
  result.seconds = seconds_since3(t0);
  return result;
}

std::vector<double> random_points3(const Domain3& domain, std::uint32_t n, std::uint64_t seed,
                                   const Density3& density) {
  detail::Uniform01 uniform(seed);
  std::vector<double> xyz;
  xyz.reserve(3 * std::size_t{n});
  if (density.kind == Density3::Kind::kVertexLinear) {
    if (!domain.has_tets()) {
      throw Error("random_points3: a density linear per tet needs a domain with a tet mesh");
    }
    const std::vector<double>& values = density.vertex_values;
    if (values.size() != domain.nb_vertices()) {
      throw Error("random_points3: " + std::to_string(values.size()) + " density values for " +
                  std::to_string(domain.nb_vertices()) + " vertices");
    }
    const auto rho = [&](std::uint32_t t, int k) { return values[domain.tet_vertex(t, k)]; };
    // Cumulative mass per tet (|det| = 6 volume; the factor does not matter).
    std::vector<double> cumulative(domain.nb_tets());
    double total = 0;
    for (std::uint32_t t = 0; t < domain.nb_tets(); ++t) {
      double s = 0;
      for (int k = 0; k < 4; ++k) {
        const double r = rho(t, k);
        if (!(r >= 0) || !std::isfinite(r)) {
          throw Error("random_points3: density " + std::to_string(r) + " at vertex " +
                      std::to_string(domain.tet_vertex(t, k)) + " (must be finite and >= 0)");
        }
        s += r;
      }
      total += tet_det(domain, t) * s / 4;
      cumulative[t] = total;
    }
    if (!(total > 0)) throw Error("random_points3: the domain has zero mass");
    for (std::uint32_t i = 0; i < n; ++i) {
      const double r = uniform() * total;
      const auto t = static_cast<std::uint32_t>(std::min<std::size_t>(
          static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), r) -
                                   cumulative.begin()),
          domain.nb_tets() - 1));
      double rho_max = 0;
      for (int k = 0; k < 4; ++k) rho_max = std::max(rho_max, rho(t, k));
      for (;;) {
        // Barycentric gaps of three sorted uniforms: uniform in the tet.
        double b[3] = {uniform(), uniform(), uniform()};
        std::sort(b, b + 3);
        const double w[4] = {b[0], b[1] - b[0], b[2] - b[1], 1 - b[2]};
        double p[3] = {0, 0, 0};
        double value = 0;
        for (int k = 0; k < 4; ++k) {
          for (int c = 0; c < 3; ++c) p[c] += w[k] * domain.vertex(domain.tet_vertex(t, k))[c];
          value += w[k] * rho(t, k);
        }
        if (uniform() * rho_max > value) continue;  // rejected: draw again in this tet
        xyz.insert(xyz.end(), p, p + 3);
        break;
      }
    }
    return xyz;
  }

  if (domain.surface().nb_triangles() == 0) {
    throw Error("random_points3: the domain has no boundary");
  }
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  // A uniform point of the volume: candidates from the bounding box, located exactly.
  const auto draw = [&](double* p) {
    for (std::uint32_t attempt = 0; attempt < 10000000u; ++attempt) {
      for (int c = 0; c < 3; ++c) p[c] = lo[c] + uniform() * (hi[c] - lo[c]);
      if (domain.locate(p) == Sign::positive) return;
    }
    throw Error("random_points3: 10^7 points of the bounding box of " + domain.source() +
                " all missed its volume");
  };
  const auto value = [&](const double* p) {
    const double r = density.callback(p[0], p[1], p[2]);
    if (!(r > 0) || !std::isfinite(r)) {
      throw Error("random_points3: the density is " + std::to_string(r) + " at (" +
                  std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " + std::to_string(p[2]) +
                  "); it must be finite and positive in the volume");
    }
    return r;
  };
  if (density.kind == Density3::Kind::kCallback && !density.callback) {
    throw Error("random_points3: the density function is empty");
  }
  return detail::rejection_sample<3>(n, density.kind == Density3::Kind::kCallback, uniform, draw,
                                     value);
}

}  // namespace voroclip
