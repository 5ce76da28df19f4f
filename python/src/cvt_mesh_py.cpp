// python/src/cvt_mesh_py.cpp — CVT (cvt2d, cvt3d), meshing (mesh2d, mesh3d) and quality,
// with progress callbacks that can stop a run and Ctrl-C that cancels it.
#include <sstream>

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

py::dict mesh2d(const Domain2& domain, std::uint32_t vertices, double edge_length, double gradation,
                double corner_angle, double sharp_angle, bool fix_input_vertices, bool keep_gaps,
                std::uint64_t seed, const std::string& method,
                std::uint32_t unconstrained_iterations, std::uint32_t constrained_iterations,
                std::uint32_t repair_rounds, const py::object& density, const py::object& callback,
                int threads) {
  Mesh2Options o;
  o.nb_vertices = vertices;
  o.edge_length = edge_length;
  o.gradation = gradation;
  o.corner_angle_deg = corner_angle;
  o.sharp_angle_deg = sharp_angle;
  o.fix_input_vertices = fix_input_vertices;
  o.keep_gaps = keep_gaps;
  o.seed = seed;
  o.method = parse_method(method);
  o.unconstrained_iterations = unconstrained_iterations;
  o.constrained_iterations = constrained_iterations;
  o.repair_rounds = repair_rounds;
  std::shared_ptr<PyDensity> rho;
  o.density = density2(density, rho);
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
  py::dict s;
  s["sites"] = st.nb_sites;
  s["fixed_sites"] = st.nb_fixed;
  s["sliding_sites"] = st.nb_sliding;
  s["sharp_corners"] = st.nb_sharp_corners;
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
  r["stats"] = s;
  return r;
}

py::dict mesh3d(const Domain3& domain, std::uint32_t vertices, bool adaptive, bool features,
                double feature_angle, std::uint64_t seed, std::uint32_t unconstrained_iterations,
                std::uint32_t constrained_iterations, bool perturb, double sliver_angle,
                bool smooth_surface, double smooth_shape, bool exact_vertices,
                const py::object& callback, int threads) {
  Mesh3Options o;
  o.nb_vertices = vertices;
  o.adaptive = adaptive;
  o.features = features;
  o.feature_angle_deg = feature_angle;
  o.seed = seed;
  o.unconstrained_iterations = unconstrained_iterations;
  o.constrained_iterations = constrained_iterations;
  o.perturb = perturb;
  o.perturbation.target_dihedral_deg = sliver_angle;
  o.smooth_surface = smooth_surface;
  o.smooth_shape = smooth_shape;
  o.vertex_count =
      exact_vertices ? Mesh3Options::VertexCount::kExact : Mesh3Options::VertexCount::kRaise;
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
  m.def("mesh2d", &mesh2d, py::arg("domain"), py::arg("vertices") = 0, py::arg("edge_length") = 0.0,
        py::arg("gradation") = 0.3, py::arg("corner_angle") = 20.0, py::arg("sharp_angle") = 30.0,
        py::arg("fix_input_vertices") = false, py::arg("keep_gaps") = false, py::arg("seed") = 1,
        py::arg("method") = "lbfgs", py::arg("unconstrained_iterations") = 100,
        py::arg("constrained_iterations") = 200, py::arg("repair_rounds") = 4,
        py::arg("density") = py::none(), py::arg("callback") = py::none(), py::arg("threads") = 0);
  m.def("mesh3d", &mesh3d, py::arg("domain"), py::arg("vertices") = 10000,
        py::arg("adaptive") = false, py::arg("features") = true,
        py::arg("feature_angle") = kDefaultFeatureAngleDeg, py::arg("seed") = 1,
        py::arg("unconstrained_iterations") = 16, py::arg("constrained_iterations") = 30,
        py::arg("perturb") = true, py::arg("sliver_angle") = 30.0,
        py::arg("smooth_surface") = false, py::arg("smooth_shape") = 0.75,
        py::arg("exact_vertices") = false, py::arg("callback") = py::none(),
        py::arg("threads") = 0);
  m.def("tet_quality", &tet_quality_py, py::arg("points"), py::arg("tets"), py::arg("threads") = 0);
  m.def("triangle_quality", &triangle_quality_py, py::arg("points"), py::arg("triangles"));
}

}  // namespace voroclip::python
