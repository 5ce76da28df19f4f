// voroclip/cvt.h — centroidal Voronoi tessellations (the module's one public header).
//
// The CVT energy of sites x_i in a domain (Yan et al. 2011, eq. 1) is
//     F(X) = sum_i ∫_{cell_i ∩ domain} rho(x) |x - x_i|^2 dx,
// with gradient dF/dx_i = 2 m_i (x_i - c_i) (eq. 2), m_i the mass and c_i the centroid of
// the clipped cell. Both come from one clipped Voronoi diagram (clip.h). Minimisers:
//   Lloyd   x_i <- c_i, each step one diagram;
//   L-BFGS  quasi-Newton on F (Liu et al. 2009), LBFGSpp's L-BFGS-B, so that sites sliding
//           on the boundary keep their arclength within bounds.
// Constraints (mesh generation, sec. 5.1): a site may be free, fixed, or slide along a
// boundary path of the domain (a chain of domain edges between two corners, or a whole
// ring). Sliding sites are parametrised by arclength s on their path; their gradient is
// the tangential component of dF/dx_i (eq. 3) and Lloyd moves them to the projection of
// their centroid on the path.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "voroclip/clip.h"

namespace voroclip {

// A path along the boundary of a Domain2: the domain vertices first, next(first), ...,
// last, walked in the ring's direction (first == last with closed == true: the whole
// ring, starting and ending at `first`).
struct BoundaryPath2 {
  std::uint32_t first = 0, last = 0;
  bool closed = false;
};

// Splits every ring of the domain at its corners: vertices where the boundary turns by
// more than `corner_angle_deg` (the angle between the directions of the edges before and
// after). A ring without such a corner becomes one closed path. `corners` receives the
// corner vertices, in ring order.
std::vector<BoundaryPath2> boundary_paths(const Domain2& domain, double corner_angle_deg,
                                          std::vector<std::uint32_t>* corners = nullptr);

// Arclength parametrisation of a path: position at s in [0, length()], and the closest
// point of the path to a point (its arclength).
class PathParam2 {
 public:
  PathParam2(const Domain2& domain, const BoundaryPath2& path);
  double length() const { return cumulative_.back(); }
  // Position and unit tangent (direction of travel) at arclength s (clamped; wraps for
  // closed paths).
  void eval(double s, double* xy, double* tangent = nullptr) const;
  double closest(const double* p) const;
  bool closed() const { return closed_; }
  // The domain edge (vertex v to next(v)) under arclength s (clamped or wrapped as in
  // eval; at a path vertex, the edge that starts there, or the last edge at the end).
  std::uint32_t edge(double s) const;

 private:
  std::size_t segment(double s) const;  // k >= 1: s lies on the segment from vertex k - 1 to k
  double wrap(double s) const;
  std::vector<double> xy_;           // path vertices (closed: the first repeated at the end)
  std::vector<double> cumulative_;   // arclength at each path vertex
  std::vector<std::uint32_t> edge_;  // per segment: its domain edge
  bool closed_ = false;
};

struct SiteConstraint2 {
  enum class Kind : std::uint8_t { kFree, kFixed, kSlide };
  Kind kind = Kind::kFree;
  std::uint32_t path = 0;  // kSlide: index into Cvt2Options::paths
};

struct CvtProgress {
  std::uint32_t iteration = 0;
  double energy = 0;
  double gradient_norm = 0;  // of the free and tangential components
  double seconds = 0;        // since the start of the optimisation
};

enum class CvtMethod { kLloyd, kLbfgs };

struct Cvt2Options {
  CvtMethod method = CvtMethod::kLbfgs;
  // The default budget lets L-BFGS reach the default tolerance on the polygons of
  // ../shared/data/polygons/valid from uniform random sites (2,000 sites: 213-429
  // iterations; 10,000: 344-608; session 25). Lloyd needs many more. 0: no iteration, the
  // start sites evaluated once and returned (stop: kIterationBudget, unless already
  // converged).
  std::uint32_t max_iterations = 1000;
  // Stop when |g| <= gradient_tolerance * |g_0| (g_0: the gradient at the start).
  double gradient_tolerance = 1e-4;
  Density2 density;
  std::uint32_t lbfgs_memory = 7;
  // L-BFGS: optimise in variables scaled per site by sqrt(2 m_i) (m_i the mass of its
  // cell), a diagonal preconditioner matching the energy's Hessian, refreshed (and the
  // solver restarted) every preconditioner_period accepted iterations. Pays off when the
  // masses vary much (a graded density); with a constant density the masses are nearly
  // equal and it changes little.
  bool precondition = false;
  std::uint32_t preconditioner_period = 25;
  // Called after every iteration (and once at the start, iteration 0); return false to
  // stop (the result then has cancelled == true and the sites of that iteration).
  std::function<bool(const CvtProgress&)> progress;
  // Empty: every site free. Otherwise one entry per site.
  std::vector<SiteConstraint2> constraints;
  std::vector<BoundaryPath2> paths;
};

// Why a CVT optimisation stopped (2D and 3D).
enum class CvtStop : std::uint8_t {
  kConverged,        // |g| <= gradient_tolerance * |g_0|
  kIterationBudget,  // max_iterations iterations done
  kNoProgress,       // L-BFGS: the line search found no lower energy at the energy's
                     // precision (the best point so far is returned)
  kCancelled,        // the progress callback returned false
};
// "converged", "iteration budget", "no progress", "cancelled".
const char* cvt_stop_name(CvtStop stop);

// The outcome of a CVT optimisation (2D and 3D).
struct CvtResult {
  std::uint32_t iterations = 0;
  std::uint32_t evaluations = 0;  // clipped diagrams computed
  double energy = 0;
  double gradient_norm = 0, initial_gradient_norm = 0;
  double seconds = 0;
  bool converged = false;
  bool cancelled = false;
  CvtStop stop = CvtStop::kIterationBudget;  // converged / cancelled agree with it
};
using Cvt2Result = CvtResult;

// The CVT energy and its gradient (2 per site; constrained sites: projected as above) at
// the given sites. One Delaunay triangulation and one clipped diagram.
double cvt_energy2(const Domain2& domain, const std::vector<double>& sites, const Density2& density,
                   std::vector<double>* gradient = nullptr);

// Minimises the CVT energy from the given sites (updated in place). Sliding sites must
// lie on their path on entry (snap them with PathParam2::closest/eval). Deterministic:
// identical results for any thread count. Throws Error, asking to rescale the model, when
// (with sites) the domain's area or the start energy (~ size^4) is 0, subnormal or not
// finite in double precision, or the start gradient is not finite: a domain beyond about
// 2^+-250 in size.
Cvt2Result optimize_cvt2(const Domain2& domain, std::vector<double>& sites,
                         const Cvt2Options& options);

// n points strictly inside the domain (packed x y), independent and distributed with
// density rho, as random_points3 draws them in a volume:
//   constant        uniform: points of the bounding box drawn uniformly, kept when inside
//                   (Domain2::locate, exact);
//   callback, grid  the same candidates, each kept with probability rho / B, where B is
//                   twice the largest rho among max(1024, min(n, 65536)) uniform points of
//                   the domain drawn first (where rho exceeds B, the samples are too few
//                   there in proportion); rho must be finite and positive in the domain.
// Draws from std::mt19937_64(seed) turned into doubles bit by bit: the same points on
// every platform (the CLI's --random N --seed S). Throws Error for a density that is not
// finite and positive (naming the point), or a domain that 1000 n + 10^6 candidates miss.
std::vector<double> random_points2(const Domain2& domain, std::uint32_t n, std::uint64_t seed,
                                   const Density2& density = {});

// ---------------------------------------------------------------------------------------
// 3D: the CVT energy of sites in the volume of a Domain3 (eq. 1 with the clipped cells of
// ClippedVoronoi3), its gradient (eq. 2) and its minimisation, with sites that may be
// free, fixed, or constrained to a surface or a curve (mesh generation, sec. 5.2:
// boundary sites on the boundary surface, feature sites on sharp edges).
//
// A constrained site is parametrised by an unconstrained point z of space: the site is
// x = P(z), the projection of z onto its constraint, given by the caller. Its gradient is
// the part of dF/dx tangent to the constraint at x (eq. 3: (I - n n^T) dF/dx on a
// surface with unit normal n; t t^T dF/dx on a curve with unit tangent t), which is the
// exact derivative of F(P(z)) wherever P is locally an orthogonal projection onto a plane
// or a line (z above the interior of a flat facet or a straight segment).

struct SiteConstraint3 {
  enum class Kind : std::uint8_t {
    kFree,     // moves freely in space
    kFixed,    // never moves
    kSurface,  // stays on a surface (projection and unit normal from Cvt3Options::project)
    kCurve,    // stays on a curve (projection and unit tangent from Cvt3Options::project)
  };
};

// Projects point p (3 values) onto the constraint of `site` (of kind `kind`): writes the
// projected point to q and to `direction` the unit normal (kSurface) or unit tangent
// (kCurve) there. Called from one thread at a time; it must be deterministic.
using SiteProjector3 = std::function<void(std::uint32_t site, SiteConstraint3::Kind kind,
                                          const double* p, double* q, double* direction)>;

struct Cvt3Options {
  CvtMethod method = CvtMethod::kLbfgs;
  // Iterations: Lloyd steps, or L-BFGS points accepted with a lower energy (a line search
  // may accept several in one L-BFGS iteration; each counts), as Cvt2Options (0 included).
  std::uint32_t max_iterations = 1000;
  // Stop when |g| <= gradient_tolerance * |g_0| (g_0: the gradient at the start).
  double gradient_tolerance = 1e-4;
  std::uint32_t lbfgs_memory = 7;
  // Density and other settings of the clipped diagrams (keep_geometry is ignored).
  Clip3Options clip;
  // Called after every iteration and once at the start (iteration 0); return false to
  // stop (the result then has cancelled == true and the sites of the last iteration).
  std::function<bool(const CvtProgress&)> progress;
  // Empty: every site free. Otherwise one entry per site; kSurface and kCurve need
  // `project`.
  std::vector<SiteConstraint3::Kind> constraints;
  SiteProjector3 project;
  // When set (and not cancelled): one flag per site, 1 when its clipped cell at the
  // returned sites meets the domain's boundary (ClippedVoronoi3::is_boundary), read from
  // the last diagram computed, which saves the caller a diagram.
  std::vector<std::uint8_t>* boundary_sites = nullptr;
};

using Cvt3Result = CvtResult;

// The CVT energy at the given sites (packed x y z) and, optionally, its gradient (3 per
// site, unconstrained: 2 m_i (x_i - c_i)). One Delaunay triangulation, one clipped diagram.
double cvt_energy3(const Domain3& domain, const std::vector<double>& sites,
                   const Clip3Options& options = {}, std::vector<double>* gradient = nullptr);

// Minimises the CVT energy from the given sites (updated in place; constrained sites are
// projected first). Lloyd moves each site to its cell's centroid (projected for
// constrained sites); L-BFGS (LBFGSpp, Nocedal-Wright strong-Wolfe line search) minimises F(P(z)).
// Deterministic: identical results for any thread count. Throws Error as optimize_cvt2 for
// the volume and the start energy (~ size^5): a domain beyond about 2^+-200 in size.
Cvt3Result optimize_cvt3(const Domain3& domain, std::vector<double>& sites,
                         const Cvt3Options& options);

// n points strictly inside the volume of the domain, independent and distributed with
// density rho:
//   constant       uniform: points of the bounding box drawn uniformly, kept when inside
//                  (Domain3::locate, exact);
//   callback       the same candidates, each kept with probability rho / B, where B is
//                  twice the largest rho among max(1024, min(n, 65536)) uniform points of
//                  the volume drawn first (where rho exceeds B, the samples are too few
//                  there in proportion); rho must be finite and positive in the volume;
//   vertex_linear  linear on each tet (a tet mesh domain; values >= 0, not all zero): a tet
//                  is drawn by its mass, then a uniform point in it, kept with probability
//                  rho / max rho on the tet.
// Draws from std::mt19937_64(seed) turned into doubles bit by bit: the same points on
// every platform. Throws Error for a domain without boundary, a density that is not
// finite and positive (naming the point), or a volume that 10^7 candidates miss.
std::vector<double> random_points3(const Domain3& domain, std::uint32_t n, std::uint64_t seed,
                                   const Density3& density = {});

}  // namespace voroclip
