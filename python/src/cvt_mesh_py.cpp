// python/src/cvt_mesh_py.cpp — CVT (cvt2d, cvt3d), meshing (mesh2d, mesh3d) and quality,
// with progress callbacks that can stop a run and Ctrl-C that cancels it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>
#include <utility>

#include "common.h"
#include "voroclip/cvt.h"
#include "voroclip/mesh.h"

namespace voroclip::python {

namespace {

CvtMethod parse_method(const py::handle& method, const std::string& what = "method") {
  if (py::isinstance<py::str>(method)) {
    const auto m = method.cast<std::string>();
    if (m == "lbfgs") return CvtMethod::kLbfgs;
    if (m == "lloyd") return CvtMethod::kLloyd;
  }
  throw Error(what + ": expected 'lbfgs' or 'lloyd', got " + py::repr(method).cast<std::string>());
}

py::dict cvt_result(const CvtResult& r, std::vector<double>&& sites, int dim,
                    std::vector<double>&& energies, std::vector<double>&& gradients) {
  py::dict d;
  const auto n = static_cast<py::ssize_t>(sites.size() / static_cast<std::size_t>(dim));
  d["sites"] = to_array(std::move(sites), {n, py::ssize_t{dim}});
  d["energy_history"] = to_array(std::move(energies));
  d["gradient_history"] = to_array(std::move(gradients));
  d["iterations"] = r.iterations;
  d["evaluations"] = r.evaluations;
  d["energy"] = r.energy;
  d["gradient_norm"] = r.gradient_norm;
  d["initial_gradient_norm"] = r.initial_gradient_norm;
  d["seconds"] = r.seconds;
  d["converged"] = r.converged;
  d["cancelled"] = r.cancelled;
  d["stop"] = cvt_stop_name(r.stop);
  return d;
}

py::dict progress_info(const CvtProgress& p) {
  py::dict d;
  d["iteration"] = p.iteration;
  d["energy"] = p.energy;
  d["gradient_norm"] = p.gradient_norm;
  d["seconds"] = p.seconds;
  return d;
}

py::dict cvt2d(const Domain2& domain, const py::object& sites_arg, const py::object& method,
               const py::object& iterations_arg, double tolerance, const py::object& density,
               const py::object& callback, const py::object& threads) {
  const DoubleArray sites = double_array(sites_arg, "sites");
  const auto iterations =
      static_cast<std::uint32_t>(count_arg(iterations_arg, "iterations", UINT32_MAX));
  const std::uint32_t n = rows(sites, 2, "sites");
  if (n == 0) throw Error("sites: at least 1 site is needed, got 0");
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) {
    throw Error("tolerance: expected a finite number >= 0");
  }
  std::shared_ptr<PyDensity> rho;
  Cvt2Options o;
  o.method = parse_method(method);
  o.max_iterations = iterations;
  o.gradient_tolerance = tolerance;
  o.density = density2(density, rho);
  Progress progress(callback);
  std::vector<double> energies, gradients;
  o.progress = [&](const CvtProgress& p) {
    energies.push_back(p.energy);
    gradients.push_back(p.gradient_norm);
    return progress.check([&] { return progress_info(p); });
  };
  std::vector<double> x(sites.data(), sites.data() + 2 * std::size_t{n});
  CvtResult r;
  run_released(threads, [&] { r = optimize_cvt2(domain, x, o); });
  if (rho) rho->rethrow();
  progress.rethrow();
  return cvt_result(r, std::move(x), 2, std::move(energies), std::move(gradients));
}

py::dict cvt3d(const Domain3& domain, const py::object& sites_arg, const py::object& method,
               const py::object& iterations_arg, double tolerance, const py::object& density,
               const py::object& callback, const py::object& threads) {
  const DoubleArray sites = double_array(sites_arg, "sites");
  const auto iterations =
      static_cast<std::uint32_t>(count_arg(iterations_arg, "iterations", UINT32_MAX));
  const std::uint32_t n = rows(sites, 3, "sites");
  if (n < 1) throw Error("sites: at least 1 site is needed, got 0");
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) {
    throw Error("tolerance: expected a finite number >= 0");
  }
  std::shared_ptr<PyDensity> rho;
  Cvt3Options o;
  o.method = parse_method(method);
  o.max_iterations = iterations;
  o.gradient_tolerance = tolerance;
  o.clip.density = density3(density, rho);
  Progress progress(callback);
  std::vector<double> energies, gradients;
  o.progress = [&](const CvtProgress& p) {
    energies.push_back(p.energy);
    gradients.push_back(p.gradient_norm);
    return progress.check([&] { return progress_info(p); });
  };
  std::vector<double> x(sites.data(), sites.data() + 3 * std::size_t{n});
  CvtResult r;
  run_released(threads, [&] { r = optimize_cvt3(domain, x, o); });
  if (rho) rho->rethrow();
  progress.rethrow();
  return cvt_result(r, std::move(x), 3, std::move(energies), std::move(gradients));
}

template <class T>
py::array_t<std::int32_t> as_int32(const std::vector<T>& v, py::ssize_t cols = 0) {
  std::vector<std::int32_t> out(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) out[k] = static_cast<std::int32_t>(v[k]);
  if (cols == 0) return to_array(std::move(out));
  const auto n = static_cast<py::ssize_t>(out.size()) / cols;
  return to_array(std::move(out), {n, cols});
}

// Options given by name (a dict from Python): each sets its field of the library's
// default-constructed options struct, so that an option not given keeps the library's
// default. An unknown name or a value of the wrong type throws Error naming it, as does an
// integer option out of its type's range (count_arg: -5 is not 2^32 - 5).
template <class Options>
class OptionSetter {
 public:
  // Sets the option from v; `what` ("mesh2d: option 'vertices'") names it in errors.
  using Setter = std::function<void(Options&, const py::handle& v, const std::string& what)>;
  OptionSetter(const char* what, std::vector<std::pair<std::string, Setter>> setters)
      : what_(what), setters_(std::move(setters)) {}
  template <class T, class Field>
  static Setter field(Field Options::*member) {
    return [member](Options& o, const py::handle& v, const std::string& what) {
      if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
        static_assert(std::is_unsigned_v<T>);
        o.*member = static_cast<Field>(count_arg(v, what.c_str(), std::numeric_limits<T>::max()));
      } else {
        o.*member = static_cast<Field>(v.cast<T>());
      }
    };
  }
  void apply(Options& o, const py::dict& options) const {
    for (const auto& [key, value] : options) {
      const auto name = py::cast<std::string>(key);
      const auto it = std::find_if(setters_.begin(), setters_.end(),
                                   [&](const auto& s) { return s.first == name; });
      if (it == setters_.end()) {
        std::string known;
        for (const auto& s : setters_) known += (known.empty() ? "" : ", ") + s.first;
        throw Error(std::string(what_) + ": unknown option '" + name + "' (known: " + known + ")");
      }
      try {
        it->second(o, value, std::string(what_) + ": option '" + name + "'");
      } catch (py::cast_error&) {
        throw Error(std::string(what_) + ": option '" + name + "': a value of the wrong type (" +
                    py::str(py::type::of(value)).cast<std::string>() + ")");
      }
    }
  }

 private:
  const char* what_;
  std::vector<std::pair<std::string, Setter>> setters_;
};

// A sizing h given as a number: checked finite and positive ("<command>: sizing: ...").
double sizing_number(const py::object& sizing, const std::string& command) {
  const double h = sizing.cast<double>();
  if (!(h > 0) || !std::isfinite(h))
    throw Error(command + ": sizing: expected a finite number > 0");
  return h;
}

// A sizing h given as a callable (plain or Vectorized): its PyDensity, named "sizing".
std::shared_ptr<PyDensity> sizing_callable(const py::object& sizing, const std::string& command,
                                           const char* signature) {
  const std::optional<py::object> vectorized = vectorized_callable(sizing);
  if (!vectorized && PyCallable_Check(sizing.ptr()) == 0) {
    throw Error(command + ": sizing: expected None, a number or a callable " + signature);
  }
  return std::make_shared<PyDensity>(vectorized ? *vectorized : sizing, "sizing",
                                     vectorized.has_value());
}

// mesh2d's sizing h (an edge length: a number or a callable h(x, y), plain or Vectorized),
// rho = h^-4 as the CLI's --sizing. Without a vertex count or edge length, h is absolute
// (edge_length 1 scales h itself; a number h is the edge length); with a vertex count only
// h's shape counts; with an edge length, an error (the CLI's "give exactly one").
void mesh2d_sizing(Mesh2Options& o, const py::dict& options, const py::object& density,
                   const py::object& sizing, std::shared_ptr<PyDensity>& callback) {
  if (!density.is_none()) throw Error("mesh2d: density and sizing exclude each other (rho = h^-4)");
  if (options.contains("edge_length")) {
    throw Error("mesh2d: sizing and edge_length exclude each other (sizing is the edge length)");
  }
  const bool alone = !options.contains("vertices");
  if (py::isinstance<py::float_>(sizing) || py::isinstance<py::int_>(sizing)) {
    const double h = sizing_number(sizing, "mesh2d");
    if (alone) o.edge_length = h;  // a uniform size: h is the edge length
    return;
  }
  callback = sizing_callable(sizing, "mesh2d", "h(x, y)");
  auto c = callback;
  o.density = Density2::function([c](double x, double y) {
    const double h = (*c)(x, y, 0, 2);
    const double rho = std::pow(h, -4.0);
    if (!std::isfinite(rho)) {
      throw Error("sizing: h = " + std::to_string(h) + " at (" + std::to_string(x) + ", " +
                  std::to_string(y) + "): h^-4 overflows");
    }
    return rho;
  });
  if (alone) o.edge_length = 1;
}

py::dict mesh2d(const Domain2& domain, const py::dict& options, const py::object& density,
                const py::object& sizing, const py::object& callback, const py::object& threads) {
  using S = OptionSetter<Mesh2Options>;
  static const S setter(
      "mesh2d",
      {{"vertices", S::field<std::uint32_t>(&Mesh2Options::nb_vertices)},
       {"edge_length", S::field<double>(&Mesh2Options::edge_length)},
       {"gradation", S::field<double>(&Mesh2Options::gradation)},
       {"corner_angle", S::field<double>(&Mesh2Options::corner_angle_deg)},
       {"sharp_angle", S::field<double>(&Mesh2Options::sharp_angle_deg)},
       {"fix_input_vertices", S::field<bool>(&Mesh2Options::fix_input_vertices)},
       {"keep_gaps", S::field<bool>(&Mesh2Options::keep_gaps)},
       {"conforming", S::field<bool>(&Mesh2Options::conforming)},
       {"seed", S::field<std::uint64_t>(&Mesh2Options::seed)},
       {"method", [](Mesh2Options& o, const py::handle& v,
                     const std::string& what) { o.method = parse_method(v, what); }},
       {"unconstrained_iterations",
        S::field<std::uint32_t>(&Mesh2Options::unconstrained_iterations)},
       {"constrained_iterations", S::field<std::uint32_t>(&Mesh2Options::constrained_iterations)},
       {"unconstrained_tolerance", S::field<double>(&Mesh2Options::unconstrained_tolerance)},
       {"constrained_tolerance", S::field<double>(&Mesh2Options::constrained_tolerance)},
       {"repair_rounds", S::field<std::uint32_t>(&Mesh2Options::repair_rounds)},
       {"repair_angle", S::field<double>(&Mesh2Options::repair_angle_deg)},
       {"repair_iterations", S::field<std::uint32_t>(&Mesh2Options::repair_iterations)},
       {"exact_vertices", [](Mesh2Options& o, const py::handle& v,
                             const std::string&) { o.raise_for_mean_angle = !v.cast<bool>(); }},
       {"mean_angle_target", S::field<double>(&Mesh2Options::mean_angle_target_deg)},
       {"max_mean_angle_runs", S::field<std::uint32_t>(&Mesh2Options::max_mean_angle_runs)}});
  // As the CLI's "give exactly one of --vertices N and --edge-length H": with both,
  // Mesh2Options would take nb_vertices and drop edge_length without a word.
  if (options.contains("vertices") && options.contains("edge_length")) {
    throw Error("mesh2d: give exactly one of vertices and edge_length, got vertices=" +
                py::repr(options["vertices"]).cast<std::string>() +
                " and edge_length=" + py::repr(options["edge_length"]).cast<std::string>());
  }
  Mesh2Options o;
  setter.apply(o, options);
  std::shared_ptr<PyDensity> rho;
  if (!sizing.is_none()) {
    mesh2d_sizing(o, options, density, sizing, rho);
  } else if (!density.is_none()) {
    o.density = density2(density, rho);
  }
  Progress progress(callback);
  o.progress = [&](const Mesh2Progress& p) {
    return progress.check([&] {
      py::dict d;
      d["phase"] = phase_name(p.phase);
      d["iteration"] = p.iteration;
      d["energy"] = p.energy;
      d["gradient_norm"] = p.gradient_norm;
      d["seconds"] = p.seconds;
      if (p.retry_vertices > 0) d["retry_vertices"] = p.retry_vertices;
      if (p.implied_vertices > 0) d["implied_vertices"] = p.implied_vertices;
      return d;
    });
  };
  Mesh2 mesh;
  Mesh2Stats st;
  run_released(threads, [&] { mesh = mesh_domain2(domain, o, &st); });
  if (rho) rho->rethrow();
  progress.rethrow();
  py::dict r;
  const auto nv = static_cast<py::ssize_t>(mesh.nb_vertices());
  std::vector<std::uint8_t> kind(mesh.vertex_kind.size());
  for (std::size_t k = 0; k < kind.size(); ++k)
    kind[k] = static_cast<std::uint8_t>(mesh.vertex_kind[k]);
  r["points"] = to_array(std::vector<double>(mesh.xy), {nv, 2});
  r["triangles"] = as_int32(mesh.triangles, 3);
  r["vertex_kind"] = to_array(std::move(kind));
  r["vertex_domain"] = as_int32(mesh.vertex_domain);
  r["vertex_edge"] = as_int32(mesh.vertex_edge);
  r["boundary_edges"] = as_int32(mesh.boundary_edges, 2);
  r["boundary_tags"] = as_int32(mesh.boundary_tags);
  r["triangle_regions"] = as_int32(mesh.triangle_regions);
  py::dict s;
  s["sites"] = st.nb_sites;
  s["fixed_sites"] = st.nb_fixed;
  s["sliding_sites"] = st.nb_sliding;
  s["sharp_corners"] = st.nb_sharp_corners;
  s["tip_triangles"] = st.nb_tip_triangles;
  s["edge_length"] = st.edge_length;
  // The count an edge length or a sizing alone implies (the CLI's note), None with vertices.
  s["implied_vertices"] =
      st.implied_vertices > 0 ? py::object(py::int_(st.implied_vertices)) : py::object(py::none());
  s["min_feature_size"] = st.min_size;
  s["unconstrained_iterations"] = st.unconstrained_iterations;
  s["constrained_iterations"] = st.constrained_iterations;
  s["energy"] = st.energy;
  s["relative_gradient"] = st.relative_gradient;
  s["gap_sites"] = st.nb_gap_sites;
  s["repair_rounds"] = st.repair_rounds;
  s["repair_removed"] = st.repair_removed;
  s["gaps"] = st.nb_gaps;
  s["covered_fraction"] = st.covered_fraction;
  s["dropped_outside"] = st.dropped_outside;
  s["removed_vertices"] = st.removed_vertices;
  s["feature_vertices"] = st.feature_vertices;
  s["refined_vertices"] = st.refine_added;
  s["smoothed_vertices"] = st.smoothed;
  if (st.vertex_count_note.empty()) {
    s["vertex_count_note"] = py::none();
  } else {
    s["vertex_count_note"] = st.vertex_count_note;
  }
  s["flips"] = st.flips;
  if (st.mean_angle_note.empty()) {
    s["mean_angle_note"] = py::none();
  } else {
    s["mean_angle_note"] = st.mean_angle_note;
  }
  s["mean_angle_runs"] = st.mean_angle_runs;
  if (st.mean_angle_raise.empty()) {
    s["mean_angle_raise"] = py::none();
  } else {
    s["mean_angle_raise"] = st.mean_angle_raise;
  }
  s["requested_vertices"] = st.requested_vertices;
  s["seconds"] = st.seconds;
  s["cancelled"] = st.cancelled;
  s["check"] = st.check;
  r["stats"] = s;
  return r;
}

// mesh3d's size: a density rho (a number or a callable rho(x, y, z)) or a sizing h (an edge
// length: a number or a callable h(x, y, z)), rho = h^-5 as the CLI's --sizing. Without a
// vertex count, h is absolute (edge_length 1 scales h itself; a number h is the edge length).
void mesh3d_size(Mesh3Options& o, bool vertices_given, const py::object& density,
                 const py::object& sizing, std::shared_ptr<PyDensity>& callback) {
  if (!density.is_none() && !sizing.is_none()) {
    throw Error("mesh3d: density and sizing exclude each other (rho = h^-5)");
  }
  const auto number = [](const py::object& v) {
    return py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v);
  };
  if (!density.is_none()) {
    if (!number(density) && PyCallable_Check(density.ptr()) == 0 && !vectorized_callable(density)) {
      throw Error("mesh3d: density: expected None, a number or a callable rho(x, y, z)");
    }
    o.density = density3(density, callback);
    return;
  }
  if (sizing.is_none()) return;
  if (number(sizing)) {
    const double h = sizing_number(sizing, "mesh3d");
    if (!vertices_given) o.edge_length = h;  // a uniform size: h is the edge length
    return;
  }
  callback = sizing_callable(sizing, "mesh3d", "h(x, y, z)");
  // rho = h^-5, an error where that overflows.
  const auto rho = [](double h, const double* p) {
    const double r = std::pow(h, -5.0);
    if (!std::isfinite(r)) {
      throw Error("sizing: h = " + std::to_string(h) + " at (" + std::to_string(p[0]) + ", " +
                  std::to_string(p[1]) + ", " + std::to_string(p[2]) + "): h^-5 overflows");
    }
    return r;
  };
  auto c = callback;
  if (c->vectorized()) {
    o.density = Density3::batch_function([c, rho](const double* xyz, std::size_t n, double* out) {
      c->batch(xyz, n, out, 3);
      for (std::size_t i = 0; i < n; ++i) out[i] = rho(out[i], xyz + 3 * i);
    });
  } else {
    o.density = Density3::function([c, rho](double x, double y, double z) {
      const double p[3] = {x, y, z};
      return rho((*c)(x, y, z, 3), p);
    });
  }
  if (!vertices_given) o.edge_length = 1;
}

py::dict mesh3d(const Domain3& domain, const py::dict& options, const py::object& density,
                const py::object& sizing, const py::object& callback, const py::object& threads) {
  using S = OptionSetter<Mesh3Options>;
  static const S setter(
      "mesh3d",
      {{"vertices", S::field<std::uint32_t>(&Mesh3Options::nb_vertices)},
       {"adaptive", S::field<bool>(&Mesh3Options::adaptive)},
       {"lfs_cap", S::field<double>(&Mesh3Options::lfs_cap)},
       {"facet_distance", S::field<double>(&Mesh3Options::facet_distance)},
       {"features", S::field<bool>(&Mesh3Options::features)},
       {"feature_angle", S::field<double>(&Mesh3Options::feature_angle_deg)},
       {"min_feature_length", S::field<double>(&Mesh3Options::min_feature_length)},
       {"sampling",
        [](Mesh3Options& o, const py::handle& v, const std::string&) {
          const auto s = v.cast<std::string>();
          if (s != "lattice" && s != "random") {
            throw Error("mesh3d: sampling: expected 'lattice' or 'random', got '" + s + "'");
          }
          o.sampling = s == "lattice" ? Mesh3Sampling::kLattice : Mesh3Sampling::kRandom;
        }},
       {"seed", S::field<std::uint64_t>(&Mesh3Options::seed)},
       {"unconstrained_iterations",
        S::field<std::uint32_t>(&Mesh3Options::unconstrained_iterations)},
       {"constrained_iterations", S::field<std::uint32_t>(&Mesh3Options::constrained_iterations)},
       {"gradient_tolerance", S::field<double>(&Mesh3Options::gradient_tolerance)},
       {"smooth_surface", S::field<bool>(&Mesh3Options::smooth_surface)},
       {"smooth_shape", S::field<double>(&Mesh3Options::smooth_shape)},
       {"exact_vertices",
        [](Mesh3Options& o, const py::handle& v, const std::string&) {
          o.vertex_count = v.cast<bool>() ? Mesh3Options::VertexCount::kExact
                                          : Mesh3Options::VertexCount::kRaise;
        }},
       {"max_topology_rounds", S::field<std::uint32_t>(&Mesh3Options::max_topology_rounds)},
       {"max_topology_sites", S::field<double>(&Mesh3Options::max_topology_sites)},
       {"max_boundary_distance", S::field<double>(&Mesh3Options::max_boundary_distance)},
       {"perturb", S::field<bool>(&Mesh3Options::perturb)},
       {"sliver_angle",
        [](Mesh3Options& o, const py::handle& v, const std::string&) {
          o.perturbation.target_dihedral_deg = v.cast<double>();
        }},
       {"flip_angle", S::field<double>(&Mesh3Options::flip_dihedral_deg)},
       {"mean_rounds", S::field<std::uint32_t>(&Mesh3Options::mean_rounds)}});
  Mesh3Options o;
  setter.apply(o, options);
  std::shared_ptr<PyDensity> rho;
  mesh3d_size(o, options.contains("vertices"), density, sizing, rho);
  Progress progress(callback);
  o.progress = [&](const Mesh3Progress& p) {
    return progress.check([&] {
      py::dict d;
      d["phase"] = mesh3_phase_name(p.phase);
      d["iteration"] = p.iteration;
      d["energy"] = p.energy;
      d["gradient_norm"] = p.gradient_norm;
      d["slivers"] = p.slivers;
      d["min_dihedral_deg"] = p.min_dihedral_deg;
      d["seconds"] = p.seconds;
      if (p.nb_bodies > 0) {
        d["body"] = p.body;
        d["nb_bodies"] = p.nb_bodies;
      }
      if (p.body_vertices > 0) d["body_vertices"] = p.body_vertices;
      if (p.implied_vertices > 0) d["implied_vertices"] = p.implied_vertices;
      return d;
    });
  };
  Mesh3Result m;
  run_released(threads, [&] { m = mesh3d(domain, o); });
  if (rho) rho->rethrow();
  progress.rethrow();
  py::dict r;
  const auto nv = static_cast<py::ssize_t>(m.nb_vertices());
  std::vector<std::uint8_t> kind(m.kinds.size());
  for (std::size_t k = 0; k < kind.size(); ++k) kind[k] = static_cast<std::uint8_t>(m.kinds[k]);
  r["points"] = to_array(std::move(m.xyz), {nv, 3});
  r["tets"] = as_int32(m.tets, 4);
  r["vertex_kind"] = to_array(std::move(kind));
  r["boundary_triangles"] = as_int32(m.boundary_triangles, 3);
  r["boundary_tags"] = as_int32(m.boundary_tags);
  r["interface_triangles"] = as_int32(m.interface_triangles, 3);
  r["interface_tags"] = as_int32(m.interface_tags);
  r["tet_tags"] = as_int32(m.tet_tags);
  py::list names;
  for (const auto& t : m.tag_names) names.append(py::make_tuple(t.dimension, t.tag, t.name));
  r["tag_names"] = names;
  r["shape_problem"] = m.shape_problem;
  py::dict s;
  s["sites"] = m.nb_sites;
  s["dropped_sites"] = m.nb_dropped_sites;
  s["boundary_sites"] = m.nb_boundary_sites;
  s["feature_sites"] = m.nb_feature_sites;
  s["corner_sites"] = m.nb_corner_sites;
  s["feature_lines"] = m.nb_feature_lines;
  s["feature_corners"] = m.nb_feature_corners;
  s["lfs_capped_volume_fraction"] = m.lfs_capped_fraction;
  s["lfs_cap_spacing"] = m.lfs_cap_spacing;
  s["distance_sites"] = m.nb_distance_sites;
  s["distance_sites_added"] = m.nb_distance_sites_added;
  s["sliver_sites"] = m.nb_sliver_sites;
  s["sliver_sites_inside"] = m.nb_sliver_sites_inside;
  s["flips"] = m.nb_flips;
  s["flip_moves"] = m.nb_flip_moves;
  s["flip_sites"] = m.nb_flip_sites;
  s["boundary_flips"] = m.nb_boundary_flips;
  s["mean_flips"] = m.nb_mean_flips;
  s["mean_moves"] = m.nb_mean_moves;
  s["mean_rounds"] = m.mean_rounds;
  s["mean_q1_before_deg"] = m.mean_q1_before_deg;
  s["mean_q1_after_deg"] = m.mean_q1_after_deg;
  s["mean_seconds"] = m.mean_seconds;
  s["bodies"] = m.nb_bodies;
  s["topology_sites"] = m.nb_topology_sites;
  s["topology_rounds"] = m.topology_rounds;
  s["topology_defects_left"] = m.topology_defects_left;
  // The topology sites reached max_topology_sites times the vertices with defects left,
  // the first of them near topology_capped_near (None when not capped).
  s["topology_capped"] = m.topology_capped;
  if (m.topology_capped) {
    const auto& p = m.topology_capped_near;
    s["topology_capped_near"] = py::make_tuple(p[0], p[1], p[2]);
  } else {
    s["topology_capped_near"] = py::none();
  }
  // When capped: the domain's thickness there, and about how many vertices a uniform
  // spacing resolving it needs (0 when not capped).
  s["topology_capped_thickness"] = m.topology_capped_thickness;
  s["topology_capped_vertices_needed"] = m.topology_capped_vertices;
  s["hausdorff"] = m.distance.max;
  s["hausdorff_rel"] = m.distance.max_relative();
  s["hausdorff_to_edge_length"] = m.distance_to_edge_length;
  s["unconstrained_iterations"] = m.unconstrained.iterations;
  s["constrained_iterations"] = m.constrained.iterations;
  s["energy"] = m.constrained.energy;
  s["slivers_initial"] = m.perturbation.initial_slivers;
  s["slivers_final"] = m.perturbation.final_slivers;
  s["input_sharpest_dihedral_deg"] = m.input_sharpest_dihedral_deg;
  s["dihedral_bound_deg"] = m.dihedral_bound_deg;
  s["tets_below_dihedral_bound"] = m.nb_tets_below_bound;
  s["input_regions"] = m.nb_input_regions;
  s["tets_across_region_interfaces"] = m.nb_tets_across_regions;
  s["region_interfaces_followed"] = m.nb_interfaces_followed;
  s["region_interfaces_not_followed"] = m.interfaces_not_followed;
  s["interface_distance_to_edge_length"] = m.interface_distance_to_edge_length;
  {
    py::list dropped;  // the input's embedded surfaces the mesh does not follow
    for (const Mesh3Result::EmbeddedTag& e : m.embedded_tags_dropped)
      dropped.append(py::dict(py::arg("tag") = e.tag, py::arg("name") = e.name,
                              py::arg("triangles") = e.nb_triangles));
    s["embedded_tags_not_followed"] = dropped;
  }
  s["seconds"] = m.total_seconds;
  s["cancelled"] = m.cancelled;
  r["stats"] = s;
  return r;
}

py::dict tet_quality_py(const py::object& points_arg, const py::object& tets_arg,
                        const py::object& threads) {
  const DoubleArray points = double_array(points_arg, "points");
  const IndexArray tets = index_array(tets_arg, "tets");
  const std::uint32_t nv = rows(points, 3, "points");
  if (tets.ndim() != 2 || tets.shape(1) != 4) throw Error("tets: expected an (n, 4) array");
  const auto nt = static_cast<std::uint32_t>(tets.shape(0));
  std::vector<std::uint32_t> t(4 * std::size_t{nt});
  for (std::size_t k = 0; k < t.size(); ++k) {
    const std::int64_t v = tets.data()[k];
    if (v < 0 || v >= std::int64_t{nv}) {
      throw Error("tets: tet " + std::to_string(k / 4) + " has the vertex index " +
                  std::to_string(v) + ", out of range [0, " + std::to_string(nv) + ")");
    }
    t[k] = static_cast<std::uint32_t>(v);
  }
  TetQualityOptions o;
  o.keep_per_tet = true;
  TetQuality q;
  run_released(threads, [&] { q = tet_quality(points.data(), nv, t.data(), nt, o); });
  std::vector<double> q1(nt), q2(nt), q3(nt), q4(nt), volume(nt), dihedral(6 * std::size_t{nt});
  for (std::uint32_t i = 0; i < nt; ++i) {
    const TetShape& s = q.per_tet[i];
    q1[i] = s.q1_deg, q2[i] = s.q2_deg, q3[i] = s.q3, q4[i] = s.q4, volume[i] = s.volume;
    for (int k = 0; k < 6; ++k)
      dihedral[6 * std::size_t{i} + static_cast<std::size_t>(k)] = s.dihedral_deg[k];
  }
  std::ostringstream json;
  write_quality_json(json, q);
  py::dict r;
  r["q1"] = to_array(std::move(q1));
  r["q2"] = to_array(std::move(q2));
  r["q3"] = to_array(std::move(q3));
  r["q4"] = to_array(std::move(q4));
  r["volume"] = to_array(std::move(volume));
  r["dihedral"] = to_array(std::move(dihedral), {py::ssize_t{nt}, 6});
  r["report_json"] = json.str();
  return r;
}

py::dict triangle_quality_py(const py::object& points_arg, const py::object& triangles_arg) {
  const DoubleArray points = double_array(points_arg, "points");
  const IndexArray triangles = index_array(triangles_arg, "triangles");
  const std::uint32_t nv = rows(points, 2, "points");
  if (triangles.ndim() != 2 || triangles.shape(1) != 3) {
    throw Error("triangles: expected an (n, 3) array");
  }
  Mesh2 mesh;
  mesh.xy.assign(points.data(), points.data() + 2 * std::size_t{nv});
  mesh.triangles.resize(static_cast<std::size_t>(triangles.size()));
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const std::int64_t v = triangles.data()[k];
    if (v < 0 || v >= std::int64_t{nv}) {
      throw Error("triangles: triangle " + std::to_string(k / 3) + " has the vertex index " +
                  std::to_string(v) + ", out of range [0, " + std::to_string(nv) + ")");
    }
    mesh.triangles[k] = static_cast<std::uint32_t>(v);
  }
  const TriangleQuality2 q = triangle_quality2(mesh);
  py::dict r;
  r["report_json"] = quality_json(q);
  return r;
}

}  // namespace

namespace {

// The library's tet mesh writer (core.h write_tet_mesh), so that a mesh written from Python
// is the file the CLI writes, byte for byte. format: "msh" (Gmsh 4.1 ASCII), "msh-binary",
// "msh22", "mesh" (Medit), "tetgen" (.node/.ele/.face), "vtk", "vtu", "vtu-ascii",
// "vtu-zlib".
void write_tet_mesh_py(const std::string& path, const DoubleArray& points, const py::array& tets,
                       const py::array& triangles, const py::array& triangle_tags,
                       const py::array& tet_tags, const py::list& tag_names,
                       const std::string& format) {
  static const std::pair<const char*, TetMeshFormat> kFormats[] = {
      {"msh", TetMeshFormat::kGmsh41},
      {"msh-binary", TetMeshFormat::kGmsh41Binary},
      {"msh22", TetMeshFormat::kGmsh22},
      {"mesh", TetMeshFormat::kMedit},
      {"tetgen", TetMeshFormat::kTetGen},
      {"vtk", TetMeshFormat::kVtk},
      {"vtu", TetMeshFormat::kVtu},
      {"vtu-ascii", TetMeshFormat::kVtuAscii},
      {"vtu-zlib", TetMeshFormat::kVtuCompressed}};
  const auto* f = std::find_if(std::begin(kFormats), std::end(kFormats),
                               [&](const auto& k) { return format == k.first; });
  if (f == std::end(kFormats)) throw Error("write: unknown tet mesh format '" + format + "'");
  const auto u32 = [](const py::array& a, const char* what) {
    const auto v = a.cast<py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>>();
    std::vector<std::uint32_t> out(static_cast<std::size_t>(v.size()));
    for (std::size_t k = 0; k < out.size(); ++k) {
      const std::int64_t x = v.data()[k];
      if (x < 0 || x > INT32_MAX) {
        throw Error(std::string(what) + ": index " + std::to_string(x) + " at position " +
                    std::to_string(k) + " (from 0) is out of range");
      }
      out[k] = static_cast<std::uint32_t>(x);
    }
    return out;
  };
  const auto i32 = [](const py::array& a) {
    const auto v = a.cast<py::array_t<std::int32_t, py::array::c_style | py::array::forcecast>>();
    return std::vector<std::int32_t>(v.data(), v.data() + v.size());
  };
  const std::uint32_t n = rows(points, 3, "points");
  TetMeshInput mesh;
  mesh.source = path;
  mesh.xyz.assign(points.data(), points.data() + 3 * std::size_t{n});
  mesh.tets = u32(tets, "tets");
  mesh.triangles = u32(triangles, "triangles");
  mesh.triangle_ref = i32(triangle_tags);
  mesh.tet_ref = i32(tet_tags);
  for (const auto& t : tag_names) {
    const auto tuple = t.cast<py::tuple>();
    TetMeshInput::TagName name;
    name.dimension = tuple[0].cast<int>();
    name.tag = tuple[1].cast<std::int32_t>();
    name.name = tuple[2].cast<std::string>();
    mesh.tag_names.push_back(std::move(name));
  }
  py::gil_scoped_release release;
  const bool vtu = f->second == TetMeshFormat::kVtu || f->second == TetMeshFormat::kVtuAscii ||
                   f->second == TetMeshFormat::kVtuCompressed;
  // A .vtu carries the quality array the CLI's mesh3d writes (the same bytes).
  write_tet_mesh(path, mesh, f->second,
                 vtu ? tet_quality_fields(mesh) : std::vector<VtuCellField>{});
}

// The library's 2D mesh writer (mesh.h write_mesh2): the files of the CLI's mesh2d. format:
// "vtu" (ASCII), "vtu-binary" (base64), "vtu-zlib", "mesh" (Medit), "msh" (Gmsh 4.1),
// "msh22".
void write_mesh2_py(const std::string& path, const DoubleArray& points, const py::array& triangles,
                    const py::array& vertex_kind, const py::array& boundary_edges,
                    const py::array& boundary_tags, const py::array& triangle_regions,
                    const std::string& format) {
  Mesh2FileFormat f;
  if (format == "vtu") {
    f = Mesh2FileFormat::kVtu;
  } else if (format == "vtu-binary") {
    f = Mesh2FileFormat::kVtuBinary;
  } else if (format == "vtu-zlib") {
    f = Mesh2FileFormat::kVtuCompressed;
  } else if (format == "mesh") {
    f = Mesh2FileFormat::kMedit;
  } else if (format == "msh") {
    f = Mesh2FileFormat::kGmsh41;
  } else if (format == "msh22") {
    f = Mesh2FileFormat::kGmsh22;
  } else {
    throw Error("write: unknown triangle mesh format '" + format + "'");
  }
  const auto u32 = [](const py::array& a) {
    const auto v = a.cast<py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>>();
    std::vector<std::uint32_t> out(static_cast<std::size_t>(v.size()));
    for (std::size_t k = 0; k < out.size(); ++k) {
      if (v.data()[k] < 0 || v.data()[k] > INT32_MAX) {
        throw Error("write: index " + std::to_string(v.data()[k]) + " at position " +
                    std::to_string(k) + " (from 0) is out of range");
      }
      out[k] = static_cast<std::uint32_t>(v.data()[k]);
    }
    return out;
  };
  const auto i32 = [](const py::array& a) {
    const auto v = a.cast<py::array_t<std::int32_t, py::array::c_style | py::array::forcecast>>();
    return std::vector<std::int32_t>(v.data(), v.data() + v.size());
  };
  const std::uint32_t n = rows(points, 2, "points");
  Mesh2 mesh;
  mesh.xy.assign(points.data(), points.data() + 2 * std::size_t{n});
  mesh.triangles = u32(triangles);
  for (const std::uint32_t k : u32(vertex_kind)) {
    if (k > 2) throw Error("write: a vertex kind is not 0, 1 or 2");
    mesh.vertex_kind.push_back(static_cast<Mesh2::VertexKind>(k));
  }
  mesh.boundary_edges = u32(boundary_edges);
  mesh.boundary_tags = i32(boundary_tags);
  mesh.triangle_regions = i32(triangle_regions);
  py::gil_scoped_release release;
  write_file_atomically(path, [&](std::ostream& out) { write_mesh2(out, mesh, f); });
}

}  // namespace

void bind_cvt_mesh(py::module_& m) {
  m.def("write_mesh2", &write_mesh2_py, py::arg("path"), py::arg("points"), py::arg("triangles"),
        py::arg("vertex_kind"), py::arg("boundary_edges"), py::arg("boundary_tags"),
        py::arg("triangle_regions"), py::arg("format"));
  m.def("write_tet_mesh", &write_tet_mesh_py, py::arg("path"), py::arg("points"), py::arg("tets"),
        py::arg("triangles"), py::arg("triangle_tags"), py::arg("tet_tags"), py::arg("tag_names"),
        py::arg("format"));
  m.def("cvt2d", &cvt2d, py::arg("domain"), py::arg("sites"), py::arg("method") = "lbfgs",
        py::arg("iterations") = 1000, py::arg("tolerance") = 1e-4, py::arg("density") = py::none(),
        py::arg("callback") = py::none(), py::arg("threads") = 0);
  m.def("cvt3d", &cvt3d, py::arg("domain"), py::arg("sites"), py::arg("method") = "lbfgs",
        py::arg("iterations") = 1000, py::arg("tolerance") = 1e-4, py::arg("density") = py::none(),
        py::arg("callback") = py::none(), py::arg("threads") = 0);
  m.def("mesh2d", &mesh2d, py::arg("domain"), py::arg("options") = py::dict(),
        py::arg("density") = py::none(), py::arg("sizing") = py::none(),
        py::arg("callback") = py::none(), py::arg("threads") = 0);
  m.def("mesh3d", &mesh3d, py::arg("domain"), py::arg("options") = py::dict(),
        py::arg("density") = py::none(), py::arg("sizing") = py::none(),
        py::arg("callback") = py::none(), py::arg("threads") = 0);
  m.def("tet_quality", &tet_quality_py, py::arg("points"), py::arg("tets"), py::arg("threads") = 0);
  m.def("triangle_quality", &triangle_quality_py, py::arg("points"), py::arg("triangles"));
}

}  // namespace voroclip::python
