// The user's density and sizing field on the command line (cvt2d, cvt3d, mesh2d, mesh3d):
// --density EXPR, --density-file FILE, and for the mesh commands --sizing EXPR and
// --sizing-file FILE, turned into the library's Density2 / Density3.
//
// Expressions are muparser's (MIT; Debian libmuparser-dev): a small, long-maintained
// parser of ordinary infix formulas (+ - * / ^, sqrt, exp, log, sin..., min, max, sum,
// avg, the ternary a ? b : c, the constants _pi and _e) that compiles a formula to
// bytecode once and evaluates it at about the cost of the arithmetic. Chosen over ExprTk
// (not packaged in Debian, a 40,000-line header) and TinyExpr (not packaged, no
// comparisons or conditionals). A muparser Parser keeps its evaluation stack in the
// object, so it is not safe to share between threads: each thread gets its own parser
// of the same formula, bound to its own x, y, z (tbb::enumerable_thread_specific), and
// evaluation takes no lock. The value at a point does not depend on the thread. Points
// are evaluated in batches (Expression::evaluate, Density3::batch_function): muparser's
// bytecode run by columns, muparser's values bit for bit, without Eval()'s per-call cost.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "voroclip/clip.h"

namespace CLI {
class App;
}

namespace voroclip::cli {

struct DensityArgs {
  std::string density;       // --density EXPR
  std::string density_file;  // --density-file FILE
  std::string sizing;        // --sizing EXPR (mesh commands)
  std::string sizing_file;   // --sizing-file FILE (mesh commands)
  bool given() const {
    return !density.empty() || !density_file.empty() || !sizing.empty() || !sizing_file.empty();
  }
  // "--density EXPR" etc.: the option given, for messages; "" when none.
  std::string describe() const;
};

/// Declares --density and --density-file (and, with `sizing`, --sizing and --sizing-file)
/// on a command of dimension 2 or 3; at most one of them may be given.
void add_density_options(CLI::App* command, DensityArgs& args, int dimension, bool sizing);

/// A formula in x, y (dimension 2) or x, y, z (dimension 3), compiled once. Evaluation is
/// safe from any number of threads at once, without locks. `option` names the option in
/// messages ("--density").
class Expression {
 public:
  /// Throws UsageError naming the position (counted from 0) and the problem when the
  /// formula does not parse or uses another variable.
  Expression(const std::string& text, int dimension, const std::string& option);
  ~Expression();
  Expression(const Expression&) = delete;
  Expression& operator=(const Expression&) = delete;
  double operator()(const double* p) const;
  /// out[k] = the formula at the point p + k * dimension, k < n: the values of
  /// operator(), bit for bit, without the parser's per-call cost when the formula is
  /// compiled to columns (every formula without the ternary a ? b : c). Both give
  /// muparser's values except for v^2, always the correctly rounded v * v.
  void evaluate(const double* p, std::size_t n, double* out) const;
  /// Whether the calling thread evaluates by columns (else through muparser's Eval()).
  bool compiled() const;
  /// muparser's own Eval() at p (the tests' reference).
  double parser_value(const double* p) const;
  const std::string& text() const { return text_; }

 private:
  struct Impl;
  std::string text_;
  int dimension_;
  std::unique_ptr<Impl> impl_;
};

/// The density of a 2D command: constant 1 when no option is given; --sizing h gives
/// rho = h^-4 (= h^-(d+2), the CVT's asymptotics: a cell's diameter goes as rho^(-1/(d+2))).
/// A value that is not finite and positive throws Error naming the point, when it is met.
/// Files: .vtk STRUCTURED_POINTS with a 2D grid (nz = 1), interpolated linearly on each
/// half of a grid square (Density2::linear_grid).
Density2 make_density2(const DensityArgs& args, const Domain2& domain);

/// The density of a 3D command, as make_density2 with rho = h^-5. Files: a Medit .sol
/// with one scalar per vertex of the domain's tet mesh (Density3::vertex_linear: linear on
/// each tet; a sizing is turned into rho at the vertices first; with `pointwise`, the same
/// interpolant as a function, for mesh3d, which needs one), a .vtu with a PointData array
/// (a function: linear in the .vtu's tet that holds the point, the nearest tet's clamped
/// interpolant outside them), or a .vtk STRUCTURED_POINTS grid (trilinear in each grid
/// cell, clamped outside the grid).
Density3 make_density3(const DensityArgs& args, const Domain3& domain, bool pointwise = false);

/// rho as a function of the point: a vertex_linear density (a .sol) becomes its linear
/// interpolant on the domain's tets, the one a .vtu over the same tets gives, so that what
/// evaluates rho point by point (the random start sites, mesh3d) sees the same values
/// whatever the file's format; other densities are returned as they are.
Density3 pointwise_density3(const Density3& rho, const Domain3& domain);

}  // namespace voroclip::cli
