// python/src/cvt_mesh_py.cpp — CVT (cvt2d, cvt3d), meshing (mesh2d, mesh3d) and quality,
// with progress callbacks that can stop a run and Ctrl-C that cancels it.
#include <algorithm>
#include <sstream>
#include <utility>

#include "common.h"
#include "voroclip/cvt.h"
#include "voroclip/mesh.h"

namespace voroclip::python {

namespace {

CvtMethod parse_method(const std::string& method) {
  if (method == "lbfgs") return CvtMethod::kLbfgs;
  if (method == "lloyd") return CvtMethod::kLloyd;
  throw Error("method: expected 'lbfgs' or 'lloyd', got '" + method + "'");
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

py::dict cvt2d(const Domain2& domain, const DoubleArray& sites, const std::string& method,
               std::uint32_t iterations, double tolerance, const py::object& density,
               const py::object& callback, int threads) {
  const std::uint32_t n = rows(sites, 2, "sites");
  if (n < 3) throw Error("sites: at least 3 sites are needed, got " + std::to_string(n));
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

py::dict cvt3d(const Domain3& domain, const DoubleArray& sites, const std::string& method,
               std::uint32_t iterations, double tolerance, const py::object& density,
               const py::object& callback, int threads) {
  const std::uint32_t n = rows(sites, 3, "sites");
  if (n < 4) throw Error("sites: at least 4 sites are needed, got " + std::to_string(n));
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
// default. An unknown name or a value of the wrong type throws Error naming it.
template <class Options>
class OptionSetter {
 public:
  using Setter = std::function<void(Options&, const py::handle&)>;
  OptionSetter(const char* what, std::vector<std::pair<std::string, Setter>> setters)
      : what_(what), setters_(std::move(setters)) {}
  template <class T, class Field>
  static Setter field(Field Options::*member) {
    return
        [member](Options& o, const py::handle& v) { o.*member = static_cast<Field>(v.cast<T>()); };
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
        it->second(o, value);
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

py::dict mesh2d(const Domain2& domain, const py::dict& options, const py::object& density,
                const py::object& callback, int threads) {
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
       {"method", [](Mesh2Options& o,
                     const py::handle& v) { o.method = parse_method(v.cast<std::string>()); }},
       {"unconstrained_iterations",
        S::field<std::uint32_t>(&Mesh2Options::unconstrained_iterations)},
       {"constrained_iterations", S::field<std::uint32_t>(&Mesh2Options::constrained_iterations)},
       {"unconstrained_tolerance", S::field<double>(&Mesh2Options::unconstrained_tolerance)},
       {"constrained_tolerance", S::field<double>(&Mesh2Options::constrained_tolerance)},
       {"repair_rounds", S::field<std::uint32_t>(&Mesh2Options::repair_rounds)},
       {"repair_angle", S::field<double>(&Mesh2Options::repair_angle_deg)},
       {"repair_iterations", S::field<std::uint32_t>(&Mesh2Options::repair_iterations)}});
  Mesh2Options o;
  setter.apply(o, options);
  std::shared_ptr<PyDensity> rho;
  if (!density.is_none()) o.density = density2(density, rho);
  Progress progress(callback);
  o.progress = [&](const Mesh2Progress& p) {
    return progress.check([&] {
      py::dict d;
      d["phase"] = phase_name(p.phase);
      d["iteration"] = p.iteration;
      d["energy"] = p.energy;
      d["gradient_norm"] = p.gradient_norm;
      d["seconds"] = p.seconds;
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
  s["seconds"] = st.seconds;
  s["cancelled"] = st.cancelled;
  s["check"] = st.check;
  r["stats"] = s;
  return r;
}

py::dict mesh3d(const Domain3& domain, const py::dict& options, const py::object& callback,
                int threads) {
  using S = OptionSetter<Mesh3Options>;
  static const S setter(
      "mesh3d",
      {{"vertices", S::field<std::uint32_t>(&Mesh3Options::nb_vertices)},
       {"adaptive", S::field<bool>(&Mesh3Options::adaptive)},
       {"features", S::field<bool>(&Mesh3Options::features)},
       {"feature_angle", S::field<double>(&Mesh3Options::feature_angle_deg)},
       {"min_feature_length", S::field<double>(&Mesh3Options::min_feature_length)},
       {"sampling",
        [](Mesh3Options& o, const py::handle& v) {
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
        [](Mesh3Options& o, const py::handle& v) {
          o.vertex_count = v.cast<bool>() ? Mesh3Options::VertexCount::kExact
                                          : Mesh3Options::VertexCount::kRaise;
        }},
       {"max_topology_rounds", S::field<std::uint32_t>(&Mesh3Options::max_topology_rounds)},
       {"perturb", S::field<bool>(&Mesh3Options::perturb)},
       {"sliver_angle", [](Mesh3Options& o, const py::handle& v) {
          o.perturbation.target_dihedral_deg = v.cast<double>();
        }}});
  Mesh3Options o;
  setter.apply(o, options);
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
      return d;
    });
  };
  Mesh3Result m;
  run_released(threads, [&] { m = mesh3d(domain, o); });
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
  s["topology_sites"] = m.nb_topology_sites;
  s["topology_rounds"] = m.topology_rounds;
  s["topology_defects_left"] = m.topology_defects_left;
  s["unconstrained_iterations"] = m.unconstrained.iterations;
  s["constrained_iterations"] = m.constrained.iterations;
  s["energy"] = m.constrained.energy;
  s["slivers_initial"] = m.perturbation.initial_slivers;
  s["slivers_final"] = m.perturbation.final_slivers;
  s["seconds"] = m.total_seconds;
  s["cancelled"] = m.cancelled;
  r["stats"] = s;
  return r;
}

py::dict tet_quality_py(const DoubleArray& points, const IndexArray& tets, int threads) {
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

py::dict triangle_quality_py(const DoubleArray& points, const IndexArray& triangles) {
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

void bind_cvt_mesh(py::module_& m) {
  m.def("cvt2d", &cvt2d, py::arg("domain"), py::arg("sites"), py::arg("method") = "lbfgs",
        py::arg("iterations") = 100, py::arg("tolerance") = 1e-4, py::arg("density") = py::none(),
        py::arg("callback") = py::none(), py::arg("threads") = 0);
  m.def("cvt3d", &cvt3d, py::arg("domain"), py::arg("sites"), py::arg("method") = "lbfgs",
        py::arg("iterations") = 100, py::arg("tolerance") = 1e-4, py::arg("density") = py::none(),
        py::arg("callback") = py::none(), py::arg("threads") = 0);
  m.def("mesh2d", &mesh2d, py::arg("domain"), py::arg("options") = py::dict(),
        py::arg("density") = py::none(), py::arg("callback") = py::none(), py::arg("threads") = 0);
  m.def("mesh3d", &mesh3d, py::arg("domain"), py::arg("options") = py::dict(),
        py::arg("callback") = py::none(), py::arg("threads") = 0);
  m.def("tet_quality", &tet_quality_py, py::arg("points"), py::arg("tets"), py::arg("threads") = 0);
  m.def("triangle_quality", &triangle_quality_py, py::arg("points"), py::arg("triangles"));
}

}  // namespace voroclip::python
