// CVT in 2D: energy and gradient from the clipped Voronoi diagram (Yan et al. 2011,
// sec. 2, eq. 1-3), minimised by Lloyd's iteration or by L-BFGS (Liu, Wang, Lévy et al.,
// "On centroidal Voronoi tessellation — energy smoothness and fast computation", ACM TOG
// 2009) through LBFGSpp's L-BFGS-B, whose box constraints keep sliding sites within their
// boundary paths.
#include <LBFGSB.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "cvt_range.h"
#include "rejection_sampling.h"
#include "voroclip/cvt.h"

namespace voroclip {

// ---------------------------------------------------------------------------------------
// Boundary paths.

std::vector<BoundaryPath2> boundary_paths(const Domain2& domain, double corner_angle_deg,
                                          std::vector<std::uint32_t>* corners) {
  const double cos_limit = std::cos(corner_angle_deg * M_PI / 180);
  std::vector<BoundaryPath2> paths;
  if (corners) corners->clear();
  std::vector<std::uint32_t> ring_corners;
  for (std::uint32_t r = 0; r < domain.nb_rings(); ++r) {
    ring_corners.clear();
    for (std::uint32_t v = domain.ring_begin(r); v < domain.ring_end(r); ++v) {
      const double* a = domain.vertex(domain.prev(v));
      const double* b = domain.vertex(v);
      const double* c = domain.vertex(domain.next(v));
      const double ux = b[0] - a[0], uy = b[1] - a[1], wx = c[0] - b[0], wy = c[1] - b[1];
      const double cosine = (ux * wx + uy * wy) / (std::hypot(ux, uy) * std::hypot(wx, wy));
      if (cosine < cos_limit) ring_corners.push_back(v);
    }
    if (corners) corners->insert(corners->end(), ring_corners.begin(), ring_corners.end());
    if (ring_corners.empty()) {
      paths.push_back({domain.ring_begin(r), domain.ring_begin(r), true});
      continue;
    }
    for (std::size_t k = 0; k < ring_corners.size(); ++k) {
      paths.push_back(
          {ring_corners[k], ring_corners[(k + 1) % ring_corners.size()], ring_corners.size() == 1});
    }
  }
  return paths;
}

PathParam2::PathParam2(const Domain2& domain, const BoundaryPath2& path) : closed_(path.closed) {
  std::uint32_t v = path.first;
  do {
    xy_.push_back(domain.vertex(v)[0]);
    xy_.push_back(domain.vertex(v)[1]);
    edge_.push_back(v);
    v = domain.next(v);
  } while (v != path.last);
  xy_.push_back(domain.vertex(v)[0]);
  xy_.push_back(domain.vertex(v)[1]);
  cumulative_.push_back(0);
  for (std::size_t k = 1; k < xy_.size() / 2; ++k) {
    cumulative_.push_back(cumulative_.back() +
                          std::hypot(xy_[2 * k] - xy_[2 * k - 2], xy_[2 * k + 1] - xy_[2 * k - 1]));
  }
}

double PathParam2::wrap(double s) const {
  const double len = length();
  if (closed_) {
    s = std::fmod(s, len);
    if (s < 0) s += len;
    return s;
  }
  return std::clamp(s, 0.0, len);
}

std::size_t PathParam2::segment(double s) const {
  const auto k = static_cast<std::size_t>(
      std::upper_bound(cumulative_.begin(), cumulative_.end(), s) - cumulative_.begin());
  return std::clamp<std::size_t>(k, 1, cumulative_.size() - 1);
}

void PathParam2::eval(double s, double* xy, double* tangent) const {
  s = wrap(s);
  const std::size_t k = segment(s);
  const double* a = &xy_[2 * (k - 1)];
  const double* b = &xy_[2 * k];
  const double seg = cumulative_[k] - cumulative_[k - 1];
  const double t = seg > 0 ? (s - cumulative_[k - 1]) / seg : 0;
  xy[0] = a[0] + t * (b[0] - a[0]);
  xy[1] = a[1] + t * (b[1] - a[1]);
  if (tangent) {
    tangent[0] = seg > 0 ? (b[0] - a[0]) / seg : 0;
    tangent[1] = seg > 0 ? (b[1] - a[1]) / seg : 0;
  }
}

std::uint32_t PathParam2::edge(double s) const { return edge_[segment(wrap(s)) - 1]; }

double PathParam2::closest(const double* p) const {
  double best = std::numeric_limits<double>::infinity(), best_s = 0;
  for (std::size_t k = 1; k < cumulative_.size(); ++k) {
    const double* a = &xy_[2 * (k - 1)];
    const double* b = &xy_[2 * k];
    const double dx = b[0] - a[0], dy = b[1] - a[1];
    const double l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    const double qx = a[0] + t * dx - p[0], qy = a[1] + t * dy - p[1];
    const double d2 = qx * qx + qy * qy;
    if (d2 < best) {
      best = d2;
      best_s = cumulative_[k - 1] + t * (cumulative_[k] - cumulative_[k - 1]);
    }
  }
  return best_s;
}

// ---------------------------------------------------------------------------------------
// The optimisation problem: variables z (free sites: x, y; sliding sites: s; fixed: none).

namespace {

struct Cancelled {};
struct Converged {};

class Problem {
 public:
  Problem(const Domain2& domain, std::vector<double>& sites, const Cvt2Options& options)
      : domain_(domain), sites_(sites), options_(options), n_(sites.size() / 2) {
    if (sites.size() % 2 != 0) throw Error("cvt2d: the site array has an odd length");
    if (!options.constraints.empty() && options.constraints.size() != n_) {
      throw Error("cvt2d: " + std::to_string(options.constraints.size()) + " constraints for " +
                  std::to_string(n_) + " sites");
    }
    for (const BoundaryPath2& p : options.paths) params_.emplace_back(domain, p);
    offset_.resize(n_ + 1, 0);
    for (std::size_t i = 0; i < n_; ++i) offset_[i + 1] = offset_[i] + nb_vars(i);
    clip_options_.density = options.density;
  }

  std::size_t nb_variables() const { return offset_[n_]; }

  SiteConstraint2::Kind kind(std::size_t i) const {
    return options_.constraints.empty() ? SiteConstraint2::Kind::kFree
                                        : options_.constraints[i].kind;
  }
  const PathParam2& path(std::size_t i) const { return params_[options_.constraints[i].path]; }

  // Current sites -> variables (sliding sites: the arclength of their closest point).
  Eigen::VectorXd variables() const {
    Eigen::VectorXd z(static_cast<Eigen::Index>(nb_variables()));
    for (std::size_t i = 0; i < n_; ++i) {
      const auto o = static_cast<Eigen::Index>(offset_[i]);
      switch (kind(i)) {
        case SiteConstraint2::Kind::kFree:
          z[o] = scale(i) * sites_[2 * i];
          z[o + 1] = scale(i) * sites_[2 * i + 1];
          break;
        case SiteConstraint2::Kind::kSlide:
          z[o] = scale(i) * path(i).closest(&sites_[2 * i]);
          break;
        case SiteConstraint2::Kind::kFixed:
          break;
      }
    }
    return z;
  }

  void bounds(Eigen::VectorXd& lo, Eigen::VectorXd& hi) const {
    const double inf = std::numeric_limits<double>::infinity();
    lo = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(nb_variables()), -inf);
    hi = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(nb_variables()), inf);
    for (std::size_t i = 0; i < n_; ++i) {
      if (kind(i) == SiteConstraint2::Kind::kSlide && !path(i).closed()) {
        lo[static_cast<Eigen::Index>(offset_[i])] = 0;
        hi[static_cast<Eigen::Index>(offset_[i])] = scale(i) * path(i).length();
      }
    }
  }

  // Variables -> sites.
  void place(const Eigen::VectorXd& z) {
    for (std::size_t i = 0; i < n_; ++i) {
      const auto o = static_cast<Eigen::Index>(offset_[i]);
      switch (kind(i)) {
        case SiteConstraint2::Kind::kFree:
          sites_[2 * i] = z[o] / scale(i);
          sites_[2 * i + 1] = z[o + 1] / scale(i);
          break;
        case SiteConstraint2::Kind::kSlide:
          path(i).eval(z[o] / scale(i), &sites_[2 * i]);
          break;
        case SiteConstraint2::Kind::kFixed:
          break;
      }
    }
  }

  // Energy at the current sites; gradient with respect to the variables at z (the
  // gradient with respect to the unscaled variables is kept for the norms).
  double evaluate(const Eigen::VectorXd& z, Eigen::VectorXd* grad) {
    clip_current();
    if (grad) {
      grad->resize(static_cast<Eigen::Index>(nb_variables()));
      unscaled_.resize(grad->size());
      for (std::size_t i = 0; i < n_; ++i) {
        const auto o = static_cast<Eigen::Index>(offset_[i]);
        const auto u = static_cast<std::uint32_t>(i);
        const double gx = 2 * cv_.mass(u) * (sites_[2 * i] - cv_.centroid(u)[0]);
        const double gy = 2 * cv_.mass(u) * (sites_[2 * i + 1] - cv_.centroid(u)[1]);
        switch (kind(i)) {
          case SiteConstraint2::Kind::kFree:
            unscaled_[o] = gx;
            unscaled_[o + 1] = gy;
            break;
          case SiteConstraint2::Kind::kSlide: {
            double xy[2], t[2];
            path(i).eval(z[o] / scale(i), xy, t);
            unscaled_[o] = gx * t[0] + gy * t[1];
            break;
          }
          case SiteConstraint2::Kind::kFixed:
            break;
        }
        for (std::size_t k = offset_[i]; k < offset_[i + 1]; ++k) {
          const auto e = static_cast<Eigen::Index>(k);
          (*grad)[e] = unscaled_[e] / scale(i);
        }
      }
    }
    ++evaluations_;
    return cv_.total_energy();
  }

  // Norm of the (unscaled) gradient of the last evaluate, without the components that
  // push a bounded variable out. The squares are summed scaled by a power of two when they
  // would overflow or underflow (cvt_range.h): the gradient grows as L^3 for a domain of
  // size L, its squares overflowed from L ~ 2^170 (|g| inf) and underflowed below 2^-170
  // (|g| 0), and such runs stopped "converged" at iteration 0.
  double projected_norm(const Eigen::VectorXd& z, const Eigen::VectorXd& lo,
                        const Eigen::VectorXd& hi) const {
    int k = 0;
    const double s = cvt_detail::sum_of_squares(
        [&](const auto& visit) {
          for (Eigen::Index e = 0; e < unscaled_.size(); ++e) {
            const double g = unscaled_[e];
            if ((z[e] <= lo[e] && g > 0) || (z[e] >= hi[e] && g < 0)) continue;
            visit(g);
          }
        },
        &k);
    return std::ldexp(std::sqrt(s), k);
  }

  // Diagonal preconditioning: variables of site i scaled by lambda sqrt(2 m_i), from the
  // last evaluate. sqrt(2 m_i) is the square root of the CVT Hessian's diagonal (d2F/dx_i^2
  // is about 2 m_i I), so the scaled Hessian is about I / lambda^2 and the Newton step
  // about minus lambda^2 times the scaled gradient; lambda = 1 / |sqrt(2 m)-scaled gradient|
  // makes that step of unit length, the length of L-BFGS-B's first step. The energy is
  // then scaled by lambda^2 (objective_scale): the Hessian becomes about the identity and
  // the gradient about the Newton step, of unit length too. Cells of mass below 1e-6 of
  // the mean are treated as of that mass.
  void set_scales() {
    scale_.assign(n_, 1.0);
    const double floor =
        1e-6 * cv_.total_mass() / static_cast<double>(std::max<std::size_t>(n_, 1));
    for (std::size_t i = 0; i < n_; ++i) {
      scale_[i] = std::sqrt(2 * std::max(cv_.mass(static_cast<std::uint32_t>(i)), floor));
    }
    // g2 = |scaled gradient|^2 = g2s 4^e (sum_of_squares: without overflow or underflow).
    int e = 0;
    const double g2s = cvt_detail::sum_of_squares(
        [&](const auto& visit) {
          for (std::size_t i = 0; i < n_; ++i) {
            for (std::size_t k = offset_[i]; k < offset_[i + 1]; ++k) {
              visit(unscaled_[static_cast<Eigen::Index>(k)] / scale_[i]);
            }
          }
        },
        &e);
    const double lambda_s = g2s > 0 ? 1 / std::sqrt(g2s) : 1.0;
    if (!(g2s > 0)) e = 0;
    const double lambda = std::ldexp(lambda_s, -e);
    for (double& w : scale_) w *= lambda;
    set_objective_scale(lambda_s * lambda_s, -2 * e);
  }

  // Without preconditioning, one scale for every variable, 2 m / |g| (m the mean mass of the
  // cells, g the gradient of the last evaluate): the Newton step of a Hessian 2 m I then has
  // unit length, the length of L-BFGS-B's first step, whatever the domain's units. With
  // unscaled variables that first step is one unit of length, and its More-Thuente line
  // search extrapolates from there by small factors: on earcut.json (14,000 units wide,
  // 2000 sites) 30 trials moved the sites by a few units and the solver stopped with
  // "no progress" at |g|/|g0| 0.91, while the same polygon scaled by 1e-3 converged.
  // In the variables z = s x the Hessian is 2 m / s^2 = |g|^2 / (2 m): the energy is scaled
  // by its inverse (objective_scale), so that the gradient too is about the Newton step.
  void set_uniform_scale() {
    scale_.clear();
    set_objective_scale(1);
    // |g|^2 = g2s 4^e (sum_of_squares: without overflow or underflow).
    int e = 0;
    const double g2s = cvt_detail::sum_of_squares(
        [&](const auto& visit) {
          for (Eigen::Index k = 0; k < unscaled_.size(); ++k) visit(unscaled_[k]);
        },
        &e);
    const double m = cv_.total_mass() / static_cast<double>(std::max<std::size_t>(n_, 1));
    if (!(g2s > 0 && m > 0)) return;
    const double s = std::ldexp(2 * m / std::sqrt(g2s), -e);
    if (std::isfinite(s) && s > 0) {
      scale_.assign(n_, s);
      set_objective_scale(2 * m / g2s, -2 * e);
    }
  }

  // The factor of the energy (and its gradient) that L-BFGS-B minimises: a power of two
  // (exact both ways) within a factor 2 of the inverse of the Hessian in the variables z.
  // Without it the gradient in z scales as the fourth power of the model's units (energy
  // ~ L^4, variables ~ 1): at 2^-20 it is 2^-80 of the variables, LBFGSpp's projected
  // gradient (z - g) - z rounds to 0 and the solver returned at once, having taken no step
  // (cvt2d on a polygon scaled by 2^-20: 0 iterations of 30).
  double objective_scale() const { return objective_scale_; }

  // Lloyd: every site to its centroid (sliding sites: to the closest point of their path).
  void lloyd_step() {
    for (std::size_t i = 0; i < n_; ++i) {
      const auto u = static_cast<std::uint32_t>(i);
      if (cv_.mass(u) <= 0) continue;
      switch (kind(i)) {
        case SiteConstraint2::Kind::kFree:
          sites_[2 * i] = cv_.centroid(u)[0];
          sites_[2 * i + 1] = cv_.centroid(u)[1];
          break;
        case SiteConstraint2::Kind::kSlide:
          path(i).eval(path(i).closest(cv_.centroid(u)), &sites_[2 * i]);
          break;
        case SiteConstraint2::Kind::kFixed:
          break;
      }
    }
  }

  std::uint32_t evaluations() const { return evaluations_; }

 private:
  double scale(std::size_t i) const { return scale_.empty() ? 1.0 : scale_[i]; }
  // The largest power of two not above c 2^e (1 for c not a positive finite number).
  void set_objective_scale(double c, int e = 0) {
    objective_scale_ = std::isfinite(c) && c > 0
                           ? std::ldexp(1.0, std::clamp(std::ilogb(c) + e, -1000, 1000))
                           : 1.0;
  }
  std::size_t nb_vars(std::size_t i) const {
    switch (kind(i)) {
      case SiteConstraint2::Kind::kFree:
        return 2;
      case SiteConstraint2::Kind::kSlide:
        if (options_.constraints[i].path >= params_.size()) {
          throw Error("cvt2d: site " + std::to_string(i) + " (from 0) slides on path " +
                      std::to_string(options_.constraints[i].path) +
                      " (from 0), but there are only " + std::to_string(params_.size()));
        }
        return 1;
      case SiteConstraint2::Kind::kFixed:
        return 0;
    }
    return 0;
  }

  void clip_current() {
    cv_.compute(domain_, sites_.data(), static_cast<std::uint32_t>(n_), clip_options_);
  }

  const Domain2& domain_;
  std::vector<double>& sites_;
  const Cvt2Options& options_;
  std::size_t n_;
  std::vector<PathParam2> params_;
  std::vector<std::size_t> offset_;
  std::vector<double> scale_;  // per site; empty: 1
  double objective_scale_ = 1;
  Eigen::VectorXd unscaled_;
  Clip2Options clip_options_;
  ClippedVoronoi2 cv_;
  std::uint32_t evaluations_ = 0;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

double cvt_energy2(const Domain2& domain, const std::vector<double>& sites, const Density2& density,
                   std::vector<double>* gradient) {
  if (sites.size() % 2 != 0) throw Error("cvt2d: the site array has an odd length");
  const auto n = static_cast<std::uint32_t>(sites.size() / 2);
  ClippedVoronoi2 cv;
  Clip2Options o;
  o.density = density;
  cv.compute(domain, sites.data(), n, o);
  if (gradient) {
    gradient->resize(sites.size());
    for (std::uint32_t i = 0; i < n; ++i) {
      (*gradient)[2 * i] = 2 * cv.mass(i) * (sites[2 * i] - cv.centroid(i)[0]);
      (*gradient)[2 * i + 1] = 2 * cv.mass(i) * (sites[2 * i + 1] - cv.centroid(i)[1]);
    }
  }
  return cv.total_energy();
}

Cvt2Result optimize_cvt2(const Domain2& domain, std::vector<double>& sites,
                         const Cvt2Options& options) {
  const auto t0 = std::chrono::steady_clock::now();
  Problem problem(domain, sites, options);
  Cvt2Result result;
  const double size = std::hypot(domain.bbox_hi()[0] - domain.bbox_lo()[0],
                                 domain.bbox_hi()[1] - domain.bbox_lo()[1]);
  const std::string model = cvt_detail::model_name("cvt2d", domain.source(), size);
  const bool has_sites = !sites.empty();
  // An area of 0 or inf in double precision: every energy and gradient would be 0 (inf), and
  // the start "converged".
  if (has_sites) cvt_detail::check_representable(model, size, "the area", domain.area(), 2);
  Eigen::VectorXd lo, hi;
  problem.bounds(lo, hi);
  Eigen::VectorXd z = problem.variables();
  problem.place(z);
  Eigen::VectorXd g;
  double f = problem.evaluate(z, &g);
  result.initial_gradient_norm = problem.projected_norm(z, lo, hi);
  if (has_sites) {
    // The energy of sites in an area is positive: 0 is an underflow (size^4 below 2^-1022).
    cvt_detail::check_representable(model, size, "the CVT energy of the start sites", f, 4);
    cvt_detail::check_representable(model, size, "the norm of the start gradient",
                                    result.initial_gradient_norm, 3, true);
  }
  result.energy = f;
  result.gradient_norm = result.initial_gradient_norm;
  const double target = options.gradient_tolerance * result.initial_gradient_norm;
  const auto report = [&](std::uint32_t iteration, double energy, double gnorm) {
    result.iterations = iteration;
    result.energy = energy;
    result.gradient_norm = gnorm;
    if (options.progress && !options.progress({iteration, energy, gnorm, seconds_since(t0)})) {
      throw Cancelled{};
    }
  };
  bool stalled = false;  // L-BFGS: the last line search made no progress

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
        z = problem.variables();
        f = problem.evaluate(z, &g);
        report(it, f, problem.projected_norm(z, lo, hi));
        if (result.gradient_norm <= target) {
          result.converged = true;
          break;
        }
      }
    } else {
      // L-BFGS-B. An iteration is reported each time an evaluation improves on the best
      // energy so far (the accepted points of the line searches). With preconditioning the
      // scales are refreshed, and the solver restarted, every `preconditioner_period`
      // iterations.
      std::uint32_t accepted = 0;
      bool stop = false;
      while (!stop) {
        stalled = false;
        const std::uint32_t accepted_at_start = accepted;
        if (options.precondition) {
          problem.set_scales();
        } else {
          problem.set_uniform_scale();
        }
        const double c = problem.objective_scale();
        problem.bounds(lo, hi);
        z = problem.variables();
        LBFGSpp::LBFGSBParam<double> param;
        param.m = static_cast<int>(std::max<std::uint32_t>(options.lbfgs_memory, 1));
        param.max_iterations = static_cast<int>(options.max_iterations - accepted);
        // LBFGSpp tests the infinity norm of the projected gradient; the criterion here is
        // the Euclidean norm, tested in the objective below, which ends the run by throwing.
        param.epsilon = 0;
        param.epsilon_rel = 0;
        param.past = 0;
        param.max_linesearch = 30;
        LBFGSpp::LBFGSBSolver<double> solver(param);
        Eigen::VectorXd best_z = z;
        double best_f = f;
        const std::uint32_t restart_at = options.precondition && options.preconditioner_period > 0
                                             ? accepted + options.preconditioner_period
                                             : std::numeric_limits<std::uint32_t>::max();
        bool restart = false;
        auto fun = [&](const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
          // A line search that ends without moving leaves LBFGSpp's update 0 / 0: a NaN
          // point is the end of the progress this precision allows (as cvt3d.cpp).
          if (!x.allFinite()) throw std::runtime_error("cvt2d: L-BFGS stopped making progress");
          problem.place(x);
          const double fx = problem.evaluate(x, &grad);
          // L-BFGS-B sees the energy times c (objective_scale); best_f is the energy itself.
          grad *= c;
          // (A NaN energy is never lower, nor a NaN |g| within the tolerance: a trial point
          // whose diagram is not finite is rejected, and the line search goes on or fails.)
          if (fx < best_f) {
            best_f = fx;
            best_z = x;
            const double gnorm = problem.projected_norm(x, lo, hi);
            report(++accepted, fx, gnorm);
            if (gnorm <= target) throw Converged{};
            if (accepted >= options.max_iterations) throw Converged{};
            if (accepted >= restart_at) {
              restart = true;
              throw Converged{};
            }
          }
          return fx * c;
        };
        double fx = f * c;
        stop = true;
        try {
          solver.minimize(fun, z, fx, lo, hi);
          // LBFGSpp returned by itself, before the budget or the target: its projected
          // gradient vanished at the precision of the variables, or its own count of outer
          // iterations (more than the points accepted here) ran out. The best point so far
          // is kept, and the solver restarted from it while that makes progress.
          stalled = accepted < options.max_iterations;
        } catch (const Converged&) {
          stop = !restart;
        } catch (const Error&) {
          throw;
        } catch (const std::runtime_error&) {
          // The line search could not make progress (at the precision of the energy, or
          // within its 30 trials): the solver starts again from the best point, with a fresh
          // memory and scale, while its runs make progress; the best point is the answer
          // when one makes none.
          stalled = true;
        } catch (const std::logic_error&) {
          stalled = true;
        }
        if (stalled && accepted > accepted_at_start) stop = false;
        z = best_z;
        problem.place(z);
        f = problem.evaluate(z, &g);
        result.energy = f;
        result.gradient_norm = problem.projected_norm(z, lo, hi);
        result.converged = result.gradient_norm <= target;
        if (result.converged || accepted >= options.max_iterations) stop = true;
      }
    }
  } catch (const Cancelled&) {
    result.cancelled = true;
  }
  result.stop = result.cancelled                                        ? CvtStop::kCancelled
                : result.converged                                      ? CvtStop::kConverged
                : stalled && result.iterations < options.max_iterations ? CvtStop::kNoProgress
                                                                        : CvtStop::kIterationBudget;
  result.evaluations = problem.evaluations();
  result.seconds = seconds_since(t0);
  return result;
}

std::vector<double> random_points2(const Domain2& domain, std::uint32_t n, std::uint64_t seed,
                                   const Density2& density) {
  detail::Uniform01 uniform(seed);
  const double* lo = domain.bbox_lo();
  const double* hi = domain.bbox_hi();
  const std::uint64_t max_tries = 1000 * std::uint64_t{n} + 1000000;
  std::uint64_t tries = 0;
  // A uniform point of the domain: candidates from the bounding box, located exactly.
  const auto draw = [&](double* p) {
    for (;;) {
      const double u = uniform();
      const double v = uniform();
      p[0] = lo[0] + u * (hi[0] - lo[0]);
      p[1] = lo[1] + v * (hi[1] - lo[1]);
      const bool inside = domain.locate(p) == Sign::positive;
      if (++tries > max_tries && !inside) {
        throw Error("random_points2: " + std::to_string(max_tries) +
                    " points of the bounding box of " + domain.source() +
                    " were drawn and too few fell inside (is its area zero?)");
      }
      if (inside) return;
    }
  };
  const auto value = [&](const double* p) {
    const double r = density(p[0], p[1]);
    if (!(r > 0) || !std::isfinite(r)) {
      throw Error("random_points2: the density is " + std::to_string(r) + " at (" +
                  std::to_string(p[0]) + ", " + std::to_string(p[1]) +
                  "); it must be finite and positive in the domain");
    }
    return r;
  };
  if (density.kind == Density2::Kind::kCallback && !density.callback) {
    throw Error("random_points2: the density function is empty");
  }
  return detail::rejection_sample<2>(n, !density.is_constant(), uniform, draw, value);
}

}  // namespace voroclip
