// Density3: the density of the 3D cell integrals (see clip.h).
#include <cmath>
#include <string>
#include <utility>

#include "voroclip/clip.h"

namespace voroclip {

Density3 Density3::constant(double rho) {
  if (!(rho > 0) || !std::isfinite(rho)) {
    throw Error("density: a constant density must be finite and positive, not " +
                std::to_string(rho));
  }
  Density3 d;
  d.kind = Kind::kConstant;
  d.value = rho;
  return d;
}

Density3 Density3::function(std::function<double(double, double, double)> rho) {
  if (!rho) throw Error("density: the density function is empty");
  Density3 d;
  d.kind = Kind::kCallback;
  d.callback = std::move(rho);
  return d;
}

Density3 Density3::batch_function(
    std::function<void(const double* xyz, std::size_t n, double* out)> rho) {
  if (!rho) throw Error("density: the density function is empty");
  Density3 d;
  d.kind = Kind::kCallback;
  d.batch = std::move(rho);
  d.callback = [f = d.batch](double x, double y, double z) {
    const double p[3] = {x, y, z};
    double v = 0;
    f(p, 1, &v);
    return v;
  };
  return d;
}

Density3 Density3::vertex_linear(std::vector<double> values) {
  Density3 d;
  d.kind = Kind::kVertexLinear;
  d.vertex_values = std::move(values);
  return d;
}

double Density3::operator()(double x, double y, double z) const {
  switch (kind) {
    case Kind::kConstant:
      return value;
    case Kind::kCallback:
      return callback(x, y, z);
    case Kind::kVertexLinear:
      break;
  }
  throw Error("density: a density linear per tet is evaluated per tet, not at a point");
}

}  // namespace voroclip
