// python/src/clip_py.cpp — Domain2 / Domain3 and the clipped Voronoi diagrams (clip2d,
// clip3d) as dicts of owned numpy arrays.
#include <algorithm>
#include <chrono>

#include "common.h"
#include "voroclip/clip.h"
#include "voroclip/cvt.h"
#include "voroclip/mesh.h"

namespace voroclip::python {

namespace {

std::vector<std::uint32_t> as_u32(const IndexArray& a, std::size_t limit, const char* what) {
  std::vector<std::uint32_t> out(static_cast<std::size_t>(a.size()));
  const std::int64_t* p = a.data();
  for (std::size_t k = 0; k < out.size(); ++k) {
    if (p[k] < 0 || static_cast<std::uint64_t>(p[k]) >= limit) {
      throw Error(std::string(what) + ": index " + std::to_string(p[k]) + " at position " +
                  std::to_string(k) + " is out of range [0, " + std::to_string(limit) + ")");
    }
    out[k] = static_cast<std::uint32_t>(p[k]);
  }
  return out;
}

std::vector<std::int32_t> as_tags(const IndexArray& a, std::size_t count, const char* what) {
  if (a.size() == 0) return {};
  if (static_cast<std::size_t>(a.size()) != count) {
    throw Error(std::string(what) + ": expected " + std::to_string(count) + " tags, got " +
                std::to_string(a.size()));
  }
  std::vector<std::int32_t> out(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::int64_t t = a.data()[k];
    if (t < INT32_MIN || t > INT32_MAX) {
      throw Error(std::string(what) + ": tag " + std::to_string(t) + " at position " +
                  std::to_string(k) + " is not a 32-bit integer");
    }
    out[k] = static_cast<std::int32_t>(t);
  }
  return out;
}

std::uint32_t index_rows(const IndexArray& a, int dim, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != dim) {
    throw Error(std::string(what) + ": expected an (n, " + std::to_string(dim) +
                ") array of indices");
  }
  return static_cast<std::uint32_t>(a.shape(0));
}

py::array_t<std::int8_t> locate_all(const DoubleArray& points, int dim,
                                    const std::function<Sign(const double*)>& locate) {
  const std::uint32_t n = rows(points, dim, "points");
  std::vector<std::int8_t> out(n);
  const double* p = points.data();
  {
    py::gil_scoped_release release;
    for (std::uint32_t i = 0; i < n; ++i) {
      out[i] = static_cast<std::int8_t>(locate(p + static_cast<std::size_t>(dim) * i));
    }
  }
  return to_array(std::move(out));
}

// The given sites the CLI's clip / clip3d warn about (python/voroclip/_api.py turns these
// into a SiteWarning): those strictly outside the domain (exact location), and those
// repeating an earlier site (equal coordinates; all but the first in input order, whose cell
// they leave empty). Input indices, increasing.
struct SiteCheck {
  std::vector<std::int32_t> outside, repeated;

  template <class Domain>
  void find_outside(const Domain& domain, const double* sites, std::uint32_t n, int dim) {
    for (std::uint32_t i = 0; i < n; ++i) {
      if (domain.locate(sites + static_cast<std::size_t>(dim) * i) == Sign::negative) {
        outside.push_back(static_cast<std::int32_t>(i));
      }
    }
  }
  // Delaunay2 numbers its points as given (auxiliary sites from n on): the smallest index of
  // equal ones is the vertex.
  void find_repeated(const Delaunay2& dt, std::uint32_t n) {
    for (std::uint32_t i = 0; i < n; ++i) {
      if (dt.duplicate_of(i) != i) repeated.push_back(static_cast<std::int32_t>(i));
    }
  }
  // ClippedVoronoi3's triangulation holds the sites in its own order (point k is input site
  // site_order()[k], auxiliary sites from n on): the first in input order of each group of
  // equal points is found through the group's vertex.
  void find_repeated(const ClippedVoronoi3& cv, std::uint32_t n) {
    const Delaunay3& dt = cv.delaunay();
    const std::vector<std::uint32_t>& order = cv.site_order();
    const std::uint32_t np = dt.nb_points();
    if (dt.nb_unique_points() == np) return;
    std::vector<std::uint32_t> first(np, UINT32_MAX);
    for (std::uint32_t k = 0; k < np; ++k) {
      std::uint32_t& f = first[dt.duplicate_of(k)];
      f = std::min(f, order[k]);
    }
    for (std::uint32_t k = 0; k < np; ++k) {
      if (order[k] < n && order[k] != first[dt.duplicate_of(k)]) {
        repeated.push_back(static_cast<std::int32_t>(order[k]));
      }
    }
    std::sort(repeated.begin(), repeated.end());
  }
  void store(py::dict& r) {
    r["outside_sites"] = to_array(std::move(outside));
    r["repeated_sites"] = to_array(std::move(repeated));
  }
};

}  // namespace

std::optional<py::object> vectorized_callable(const py::object& v) {
  if (!py::isinstance<Vectorized>(v)) return std::nullopt;
  return v.cast<const Vectorized&>().f;
}

void PyDensity::bad_value(double v, const double* p, int dim) const {
  const auto r = [](double t) { return py::repr(py::float_(t)).cast<std::string>(); };
  throw Error(what_ + ": the callable returned " + r(v) + " at (" + r(p[0]) + ", " + r(p[1]) +
              (dim == 2 ? "" : ", " + r(p[2])) + "): the " + what_ +
              " must be finite and positive");
}

void PyDensity::batch(const double* xyz, std::size_t n, double* out, int dim) {
  py::gil_scoped_acquire acquire;
  std::fill(out, out + n, 1.0);
  if (error_ || n == 0) return;
  const auto count = static_cast<py::ssize_t>(n);
  py::array_t<double> c[3] = {py::array_t<double>(count), py::array_t<double>(count),
                              py::array_t<double>(count)};
  for (int k = 0; k < dim; ++k) {
    double* d = c[k].mutable_data();
    for (std::size_t i = 0; i < n; ++i) d[i] = xyz[static_cast<std::size_t>(dim) * i + k];
  }
  py::object r;
  try {
    r = dim == 2 ? f_(c[0], c[1]) : f_(c[0], c[1], c[2]);
  } catch (py::error_already_set& e) {
    keep(e);
    return;
  }
  const auto fail = [&](PyObject* type, const std::string& message) {
    if (!error_) {
      PyErr_SetString(type, message.c_str());
      error_ = std::make_unique<py::error_already_set>();
    }
  };
  const DoubleArray a = DoubleArray::ensure(r);
  if (!a) {
    PyErr_Clear();
    fail(PyExc_TypeError, what_ +
                              ": the vectorized callable must return an array of numbers, got " +
                              py::repr(r).cast<std::string>());
    return;
  }
  if (a.ndim() == 0) {
    std::fill(out, out + n, a.data()[0]);
  } else if (a.ndim() == 1 && a.shape(0) == count) {
    std::copy(a.data(), a.data() + n, out);
  } else {
    std::string shape;
    for (py::ssize_t k = 0; k < a.ndim(); ++k) {
      shape += (k == 0 ? "" : ", ") + std::to_string(a.shape(k));
    }
    if (a.ndim() == 1) shape += ",";
    fail(PyExc_ValueError, what_ + ": the vectorized callable returned an array of shape (" +
                               shape + ") for " + std::to_string(n) + " points; expected (" +
                               std::to_string(n) + ",) or one number");
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!(out[i] > 0) || !std::isfinite(out[i])) {
      bad_value(out[i], xyz + static_cast<std::size_t>(dim) * i, dim);
    }
  }
}

Density2 density2(const py::object& density, std::shared_ptr<PyDensity>& callback) {
  if (density.is_none()) return Density2::constant(1.0);
  if (py::isinstance<py::float_>(density) || py::isinstance<py::int_>(density)) {
    const double v = density.cast<double>();
    if (!(v > 0) || !std::isfinite(v)) throw Error("density: expected a finite number > 0");
    return Density2::constant(v);
  }
  if (py::isinstance<py::tuple>(density)) {
    // (values (ny, nx), lo (2,), hi (2,)): piecewise linear on a grid.
    const auto t = density.cast<py::tuple>();
    if (t.size() != 3) throw Error("density: a grid is (values[ny, nx], lo[2], hi[2])");
    const auto values = double_array(t[0], "density: the grid's values");
    const auto lo = double_array(t[1], "density: the grid's lo");
    const auto hi = double_array(t[2], "density: the grid's hi");
    if (values.ndim() != 2 || values.shape(0) < 2 || values.shape(1) < 2 || lo.size() != 2 ||
        hi.size() != 2) {
      throw Error("density: a grid is (values[ny, nx] with nx, ny >= 2, lo[2], hi[2])");
    }
    const double l[2] = {lo.data()[0], lo.data()[1]};
    const double h[2] = {hi.data()[0], hi.data()[1]};
    return Density2::linear_grid(static_cast<std::uint32_t>(values.shape(1)),
                                 static_cast<std::uint32_t>(values.shape(0)), l, h,
                                 std::vector<double>(values.data(), values.data() + values.size()));
  }
  const std::optional<py::object> vectorized = vectorized_callable(density);
  if (vectorized || PyCallable_Check(density.ptr()) != 0) {
    // Density2 has no batch: a vectorized callable gets arrays of one point.
    callback = std::make_shared<PyDensity>(vectorized ? *vectorized : density, "density",
                                           vectorized.has_value());
    auto c = callback;
    return Density2::function([c](double x, double y) { return (*c)(x, y, 0, 2); });
  }
  throw Error("density: expected None, a number, a callable rho(x, y) or a grid tuple");
}

Density3 density3(const py::object& density, std::shared_ptr<PyDensity>& callback) {
  if (density.is_none()) return Density3::constant(1.0);
  if (py::isinstance<py::float_>(density) || py::isinstance<py::int_>(density)) {
    const double v = density.cast<double>();
    if (!(v > 0) || !std::isfinite(v)) throw Error("density: expected a finite number > 0");
    return Density3::constant(v);
  }
  if (const auto f = vectorized_callable(density)) {
    callback = std::make_shared<PyDensity>(*f, "density", true);
    auto c = callback;
    return Density3::batch_function(
        [c](const double* xyz, std::size_t n, double* out) { c->batch(xyz, n, out, 3); });
  }
  if (PyCallable_Check(density.ptr()) != 0) {
    callback = std::make_shared<PyDensity>(density);
    auto c = callback;
    return Density3::function([c](double x, double y, double z) { return (*c)(x, y, z, 3); });
  }
  const auto values = DoubleArray::ensure(density);
  if (!values || values.ndim() != 1) {
    throw Error(
        "density: expected None, a number, a callable rho(x, y, z) or one value per "
        "vertex of the tet mesh");
  }
  return Density3::vertex_linear(std::vector<double>(values.data(), values.data() + values.size()));
}

namespace {

// 2D neighbours from the cells' rings: the edge from ring vertex u to w of cell i lies on
// the domain's boundary when both are on a common domain edge, else on bisector(i, j) for
// the one site j other than i that both vertices are defined by (ClipVertex2).
void neighbors2(const Domain2& domain, const ClippedVoronoi2& cv, std::vector<std::int32_t>& indptr,
                std::vector<std::int32_t>& indices) {
  const std::uint32_t n = cv.nb_sites();
  const auto& vs = cv.vertices();
  const auto sites = [](const ClipVertex2& v, std::uint32_t s[3]) {
    switch (v.kind) {
      case ClipVertex2::Kind::kDomainVertex:
        return 0;
      case ClipVertex2::Kind::kEdgeBisector:
        s[0] = v.b, s[1] = v.c;
        return 2;
      case ClipVertex2::Kind::kVoronoi:
        s[0] = v.a, s[1] = v.b, s[2] = v.c;
        return 3;
    }
    return 0;
  };
  const auto edges = [&](const ClipVertex2& v, std::uint32_t e[2]) {
    switch (v.kind) {
      case ClipVertex2::Kind::kDomainVertex:
        e[0] = v.a, e[1] = domain.prev(v.a);
        return 2;
      case ClipVertex2::Kind::kEdgeBisector:
        e[0] = v.a;
        return 1;
      case ClipVertex2::Kind::kVoronoi:
        return 0;
    }
    return 0;
  };
  indptr.assign(std::size_t{n} + 1, 0);
  std::vector<std::uint32_t> cell;
  for (std::uint32_t i = 0; i < n; ++i) {
    cell.clear();
    for (std::uint32_t r = cv.cell_ring_begin(i); r < cv.cell_ring_begin(i + 1); ++r) {
      const std::uint32_t b = cv.ring_vertex_begin(r), e = cv.ring_vertex_begin(r + 1);
      for (std::uint32_t k = b; k < e; ++k) {
        const ClipVertex2& u = vs[k];
        const ClipVertex2& w = vs[k + 1 == e ? b : k + 1];
        std::uint32_t eu[2], ew[2], su[3], sw[3];
        const int neu = edges(u, eu), new_ = edges(w, ew);
        bool on_boundary = false;
        for (int x = 0; x < neu; ++x) {
          for (int y = 0; y < new_; ++y) on_boundary = on_boundary || eu[x] == ew[y];
        }
        if (on_boundary) continue;
        const int nsu = sites(u, su), nsw = sites(w, sw);
        for (int x = 0; x < nsu; ++x) {
          if (su[x] == i) continue;
          for (int y = 0; y < nsw; ++y) {
            if (su[x] == sw[y]) cell.push_back(su[x]);
          }
        }
      }
    }
    std::sort(cell.begin(), cell.end());
    cell.erase(std::unique(cell.begin(), cell.end()), cell.end());
    for (const std::uint32_t j : cell) indices.push_back(static_cast<std::int32_t>(j));
    indptr[i + 1] = static_cast<std::int32_t>(indices.size());
  }
}

// 3D neighbours: the sites across the faces of each cell's boundary.
void neighbors3(const ClippedVoronoi3& cv, const ClippedVoronoi3::Polygons& faces,
                std::vector<std::int32_t>& indptr, std::vector<std::int32_t>& indices) {
  const std::uint32_t n = cv.nb_sites();
  std::vector<std::vector<std::uint32_t>> adj(n);
  for (std::size_t f = 0; f < faces.site.size(); ++f) {
    const std::uint32_t j = faces.across[f];
    if (j < n) adj[faces.site[f]].push_back(j);
  }
  indptr.assign(std::size_t{n} + 1, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    std::sort(adj[i].begin(), adj[i].end());
    adj[i].erase(std::unique(adj[i].begin(), adj[i].end()), adj[i].end());
    for (const std::uint32_t j : adj[i]) indices.push_back(static_cast<std::int32_t>(j));
    indptr[i + 1] = static_cast<std::int32_t>(indices.size());
  }
}

// The library's clipping progress as the dict handed to a Python callback.
py::dict clip_progress_info(const ClipProgress& p) {
  py::dict d;
  d["phase"] = p.phase;
  d["done"] = p.done;
  d["total"] = p.total;
  d["seconds"] = p.seconds;
  return d;
}

// Runs a clipping with the GIL released; Ctrl-C or a callback's exception, which cancel it
// (the library then throws Error "cancelled"), are re-raised as themselves.
void run_clip(const py::object& threads, Progress& progress, const std::function<void()>& f) {
  try {
    run_released(threads, f);
  } catch (const Error&) {
    progress.rethrow();
    throw;
  }
  progress.rethrow();
}

py::dict clip2d(const Domain2& domain, const py::object& sites_arg, const py::object& density,
                bool geometry, bool neighbors, const py::object& callback_,
                const py::object& threads) {
  const DoubleArray sites = double_array(sites_arg, "sites");
  const std::uint32_t n = rows(sites, 2, "sites");
  if (n == 0) throw Error("sites: at least 1 site is needed, got 0");
  std::shared_ptr<PyDensity> callback;
  Clip2Options o;
  o.density = density2(density, callback);
  o.keep_geometry = geometry || neighbors;
  Progress progress(callback_);
  o.progress = [&](const ClipProgress& p) {
    return progress.check([&] { return clip_progress_info(p); });
  };
  ClippedVoronoi2 cv;
  SiteCheck check;
  run_clip(threads, progress, [&] {
    cv.compute(domain, sites.data(), n, o);
    check.find_outside(domain, sites.data(), n, 2);
    check.find_repeated(cv.delaunay(), n);
  });
  if (callback) callback->rethrow();
  std::vector<double> area(n), mass(n), energy(n), centroid(2 * std::size_t{n});
  std::vector<std::uint8_t> boundary(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    area[i] = cv.area(i);
    mass[i] = cv.mass(i);
    energy[i] = cv.energy(i);
    centroid[2 * std::size_t{i}] = cv.centroid(i)[0];
    centroid[2 * std::size_t{i} + 1] = cv.centroid(i)[1];
    boundary[i] = cv.is_boundary(i) ? 1 : 0;
  }
  py::dict r;
  r["areas"] = to_array(std::move(area));
  r["masses"] = to_array(std::move(mass));
  r["energies"] = to_array(std::move(energy));
  r["centroids"] = to_array(std::move(centroid), {py::ssize_t{n}, 2});
  r["boundary"] = to_array(std::move(boundary)).attr("astype")("bool");
  r["total_area"] = cv.total_area();
  r["total_mass"] = cv.total_mass();
  r["total_energy"] = cv.total_energy();
  r["nb_boundary"] = cv.nb_boundary_sites();
  check.store(r);
  if (o.keep_geometry) {  // the neighbours cost a pass over the geometry
    std::vector<std::int32_t> indptr, indices;
    neighbors2(domain, cv, indptr, indices);
    r["neighbors_indptr"] = to_array(std::move(indptr));
    r["neighbors_indices"] = to_array(std::move(indices));
  }
  if (geometry) {
    std::vector<std::int32_t> cell_ring(std::size_t{n} + 1), ring_vertex;
    for (std::uint32_t i = 0; i <= n; ++i) {
      cell_ring[i] = static_cast<std::int32_t>(cv.cell_ring_begin(i));
    }
    const std::uint32_t nr = cv.cell_ring_begin(n);
    ring_vertex.resize(std::size_t{nr} + 1);
    for (std::uint32_t k = 0; k <= nr; ++k) {
      ring_vertex[k] = static_cast<std::int32_t>(cv.ring_vertex_begin(k));
    }
    std::vector<double> xy = cv.vertex_coords();
    const auto nv = static_cast<py::ssize_t>(xy.size() / 2);
    r["cell_ring_begin"] = to_array(std::move(cell_ring));
    r["ring_vertex_begin"] = to_array(std::move(ring_vertex));
    r["vertices"] = to_array(std::move(xy), {nv, 2});
  }
  return r;
}

py::dict clip3d(const Domain3& domain, const py::object& sites_arg, const py::object& density,
                bool geometry, bool neighbors, const py::object& callback_,
                const py::object& threads) {
  const DoubleArray sites = double_array(sites_arg, "sites");
  const std::uint32_t n = rows(sites, 3, "sites");
  if (n < 1) throw Error("sites: at least 1 site is needed, got 0");
  std::shared_ptr<PyDensity> callback;
  Clip3Options o;
  o.density = density3(density, callback);
  o.keep_geometry = geometry || neighbors;
  Progress progress(callback_);
  o.progress = [&](const ClipProgress& p) {
    return progress.check([&] { return clip_progress_info(p); });
  };
  ClippedVoronoi3 cv;
  ClippedVoronoi3::Polygons faces;
  double seconds_compute = 0;
  SiteCheck check;
  run_clip(threads, progress, [&] {
    const auto t0 = std::chrono::steady_clock::now();
    cv.compute(domain, sites.data(), n, o);
    seconds_compute = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (o.keep_geometry) faces = cv.cell_boundaries();
    check.find_outside(domain, sites.data(), n, 3);
    check.find_repeated(cv, n);
  });
  if (callback) callback->rethrow();
  std::vector<double> volume(n), mass(n), energy(n), surface(n), centroid(3 * std::size_t{n});
  std::vector<std::uint8_t> boundary(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    volume[i] = cv.volume(i);
    mass[i] = cv.mass(i);
    energy[i] = cv.energy(i);
    surface[i] = cv.surface_area(i);
    for (int k = 0; k < 3; ++k) {
      centroid[3 * std::size_t{i} + static_cast<std::size_t>(k)] = cv.centroid(i)[k];
    }
    boundary[i] = cv.is_boundary(i) ? 1 : 0;
  }
  py::dict r;
  r["volumes"] = to_array(std::move(volume));
  r["masses"] = to_array(std::move(mass));
  r["energies"] = to_array(std::move(energy));
  r["surface_areas"] = to_array(std::move(surface));
  r["centroids"] = to_array(std::move(centroid), {py::ssize_t{n}, 3});
  r["boundary"] = to_array(std::move(boundary)).attr("astype")("bool");
  r["total_volume"] = cv.total_volume();
  r["total_mass"] = cv.total_mass();
  r["total_energy"] = cv.total_energy();
  r["total_surface_area"] = cv.total_surface_area();
  r["nb_boundary"] = cv.nb_boundary_sites();
  r["unique_sites"] = cv.delaunay().nb_unique_points();
  check.store(r);
  py::dict seconds;
  seconds["delaunay"] = cv.seconds_delaunay();
  seconds["surface_rvd"] = cv.seconds_surface();
  seconds["boundary_cells"] = cv.seconds_boundary_cells();
  seconds["inner_cells"] = cv.seconds_inner_cells();
  // The C++ call alone (ClippedVoronoi3::compute), as the CLI's --stats json "total".
  seconds["total"] = seconds_compute;
  r["seconds"] = seconds;
  if (o.keep_geometry) {  // the neighbours cost a pass over the geometry
    std::vector<std::int32_t> indptr, indices;
    neighbors3(cv, faces, indptr, indices);
    r["neighbors_indptr"] = to_array(std::move(indptr));
    r["neighbors_indices"] = to_array(std::move(indices));
  }
  if (geometry) {
    const std::size_t nf = faces.site.size();
    std::vector<std::int32_t> site(nf), across(nf), begin(faces.polygon_begin.size());
    for (std::size_t f = 0; f < nf; ++f) {
      site[f] = static_cast<std::int32_t>(faces.site[f]);
      across[f] = faces.across[f] < n ? static_cast<std::int32_t>(faces.across[f]) : -1;
    }
    for (std::size_t k = 0; k < begin.size(); ++k) {
      begin[k] = static_cast<std::int32_t>(faces.polygon_begin[k]);
    }
    // Outward, as the CLI's .vtu cells: the library's faces go clockwise seen from outside
    // their cell; each keeps its first point.
    for (std::size_t f = 0; f < nf; ++f) {
      for (std::size_t a = faces.polygon_begin[f] + 1, b = faces.polygon_begin[f + 1] - 1; a < b;
           ++a, --b) {
        for (std::size_t c = 0; c < 3; ++c) std::swap(faces.xyz[3 * a + c], faces.xyz[3 * b + c]);
      }
    }
    const auto np = static_cast<py::ssize_t>(faces.xyz.size() / 3);
    r["face_site"] = to_array(std::move(site));
    r["face_across"] = to_array(std::move(across));
    r["face_begin"] = to_array(std::move(begin));
    r["face_points"] = to_array(std::move(faces.xyz), {np, 3});
  }
  return r;
}

TriangleSurface make_surface(const DoubleArray& vertices, const IndexArray& triangles,
                             const std::string& source) {
  const std::uint32_t nv = rows(vertices, 3, "vertices");
  const std::uint32_t nt = index_rows(triangles, 3, "triangles");
  TriangleSurface s;
  s.source = source;
  s.xyz.assign(vertices.data(), vertices.data() + 3 * std::size_t{nv});
  s.triangles = as_u32(triangles, nv, "triangles");
  (void)nt;
  return s;
}

constexpr const char* kDomain2Doc = R"doc(A validated polygonal domain for clip2d, cvt2d and mesh2d.

Polygons, each an outer ring with holes, checked exactly: no ring crosses or touches
itself or another, every hole lies inside its polygon, the coordinates are finite
(voroclip.Error names the rings and the points otherwise).

Build one with voroclip.domain2(...) (a list of rings, ring 0 the outer boundary; one
(n, 2) ring alone; a .poly or .json path; a shapely-like polygon; the command line's
generators "annulus:R_IN,R_OUT,SEGMENTS" and "square-holes:K,FRACTION"), Domain2.read(path),
Domain2.annulus(r_inner, r_outer, segments=64) or Domain2.square_holes(k, fraction). The
functions take a Domain2 as it is: validate once for several calls.

source (the file, or "rings"), area (outer rings minus holes), nb_rings, bounds (xmin,
ymin, xmax, ymax); ring(r): the (k, 2) points of ring r, counter-clockwise around a
polygon and clockwise around a hole; is_hole(r); locate(points): per point +1 strictly
inside, 0 on the boundary, -1 outside, exactly.)doc";

constexpr const char* kDomain3Doc =
    R"doc(A validated 3D domain for clip3d, cvt3d, mesh3d and random_points.

The volume inside a closed triangle surface (one or more shells, cavities allowed),
checked exactly: closed, oriented outward, no pinched vertex, no self-intersection
(voroclip.Error names the faces otherwise); possibly with a tet mesh of it, whose region
and patch tags reach mesh3d's output.

Build one with voroclip.domain3(...) (a (vertices, triangles) pair, a surface or tet mesh
file, a meshio.Mesh), Domain3.read(path, reorient=False), Domain3.from_surface(vertices,
triangles, source, reorient=False) or Domain3.from_tets(...). The functions take a Domain3
as it is: validate once for several calls.

source, volume, area (of the surface), nb_shells, has_tets, nb_tets, bounds (xmin, ymin,
zmin, xmax, ymax, zmax); surface(): the boundary as (vertices (n, 3), triangles (m, 3)
int32), outward; locate(points): per point +1 strictly inside the volume, 0 on the
surface, -1 outside, exactly.)doc";

}  // namespace

void bind_domains(py::module_& m) {
  py::class_<Domain2>(m, "Domain2", kDomain2Doc)
      .def(py::init([](const py::object& xy_arg, const py::object& ring_begin_arg,
                       const py::object& ring_polygon_arg, const std::string& source) {
             const DoubleArray xy = double_array(xy_arg, "rings");
             const IndexArray ring_begin = index_array(ring_begin_arg, "ring_begin");
             const IndexArray ring_polygon = index_array(ring_polygon_arg, "ring_polygon");
             const std::uint32_t n = rows(xy, 2, "rings");
             PolygonRings rings;
             rings.source = source;
             rings.xy.assign(xy.data(), xy.data() + 2 * std::size_t{n});
             rings.ring_begin = as_u32(ring_begin, std::size_t{n} + 1, "ring_begin");
             if (rings.ring_begin.size() < 2 || rings.ring_begin.front() != 0 ||
                 rings.ring_begin.back() != n ||
                 !std::is_sorted(rings.ring_begin.begin(), rings.ring_begin.end())) {
               throw Error(source + ": ring offsets must increase from 0 to the point count");
             }
             const std::size_t nr = rings.ring_begin.size() - 1;
             rings.ring_polygon = as_tags(ring_polygon, nr, "ring_polygon");
             if (rings.ring_polygon.empty()) rings.ring_polygon.assign(nr, -1);
             rings.ring_line.assign(nr, 0);
             return Domain2(rings);
           }),
           py::arg("xy"), py::arg("ring_begin"), py::arg("ring_polygon"), py::arg("source"))
      .def_static(
          "read", [](const std::string& path) { return Domain2(read_polygon(path)); },
          "The domain of a .poly (Triangle) or .json polygon file.", py::arg("path"))
      .def_static(
          "annulus",
          [](double r_inner, double r_outer, std::uint32_t segments) {
            return Domain2(annulus_rings(r_inner, r_outer, segments));
          },
          "An annulus centred at the origin, each circle a regular polygon of `segments` "
          "vertices, the first at angle 0 (the command line's annulus:R_IN,R_OUT,SEGMENTS).",
          py::arg("r_inner"), py::arg("r_outer"), py::arg("segments") = 64)
      .def_static(
          "square_holes",
          [](std::uint32_t k, double fraction) { return Domain2(square_with_holes(k, fraction)); },
          "The unit square with a k x k grid of square holes of side fraction / k, each centred "
          "in its grid cell (the command line's square-holes:K,FRACTION).",
          py::arg("k"), py::arg("fraction"))
      .def_property_readonly("source", &Domain2::source)
      .def_property_readonly("area", &Domain2::area)
      .def_property_readonly("nb_rings", &Domain2::nb_rings)
      .def("__repr__",
           [](const Domain2& d) {
             return "Domain2(source=" + py::repr(py::str(d.source())).cast<std::string>() +
                    ", rings=" + std::to_string(d.nb_rings()) +
                    ", area=" + py::repr(py::float_(d.area())).cast<std::string>() + ")";
           })
      .def_property_readonly("bounds",
                             [](const Domain2& d) {
                               return py::make_tuple(d.bbox_lo()[0], d.bbox_lo()[1], d.bbox_hi()[0],
                                                     d.bbox_hi()[1]);
                             })
      .def(
          "ring",
          [](const Domain2& d, const py::object& ring) {
            const std::uint32_t r = index_arg(ring, d.nb_rings(), "ring", "ring");
            const double* b = d.vertex(d.ring_begin(r));
            std::vector<double> xy(b, b + 2 * std::size_t{d.ring_end(r) - d.ring_begin(r)});
            const auto nv = static_cast<py::ssize_t>(xy.size() / 2);
            return to_array(std::move(xy), {nv, 2});
          },
          "The (k, 2) points of ring r: counter-clockwise around a polygon, clockwise around a "
          "hole.",
          py::arg("r"))
      .def(
          "is_hole",
          [](const Domain2& d, const py::object& r) {
            return d.is_hole(index_arg(r, d.nb_rings(), "is_hole", "ring"));
          },
          "True when ring r bounds a hole.", py::arg("r"))
      .def(
          "locate",
          [](const Domain2& d, const py::object& p) {
            return locate_all(double_array(p, "points"), 2,
                              [&](const double* q) { return d.locate(q); });
          },
          "Per point of an (n, 2) array, exactly: +1 strictly inside, 0 on the boundary, -1 "
          "outside (int8).",
          py::arg("points"));

  py::class_<Domain3>(m, "Domain3", kDomain3Doc)
      .def_static(
          "from_surface",
          [](const py::object& vertices, const py::object& triangles, const std::string& source,
             bool reorient) {
            const TriangleSurface s = make_surface(double_array(vertices, "vertices"),
                                                   index_array(triangles, "triangles"), source);
            // (The library's Domain3 of nothing is an empty domain, which no function takes.)
            if (s.triangles.empty()) {
              throw Error((source.empty() ? std::string("from_surface") : source) +
                          ": no triangles; a domain is the volume inside a closed surface");
            }
            Surface3Options o;
            o.reorient = reorient;
            py::gil_scoped_release release;
            return Domain3(s, o);
          },
          "The volume inside a closed surface: (n, 3) vertices and (m, 3) triangles (vertex "
          "indices from 0) oriented outward (reorient=True turns inside-out shells); `source` "
          "names it in messages.",
          py::arg("vertices"), py::arg("triangles"), py::arg("source"), py::arg("reorient") = false)
      .def_static(
          "from_tets",
          [](const py::object& vertices_arg, const py::object& tets_arg,
             const py::object& triangles_arg, const py::object& tet_tags_arg,
             const py::object& triangle_tags_arg, const std::string& source,
             const std::vector<std::tuple<int, std::int32_t, std::string>>& tag_names) {
            const DoubleArray vertices = double_array(vertices_arg, "vertices");
            const IndexArray tets = index_array(tets_arg, "tets");
            const IndexArray triangles = index_array(triangles_arg, "triangles");
            const IndexArray tet_tags = index_array(tet_tags_arg, "tet_tags");
            const IndexArray triangle_tags = index_array(triangle_tags_arg, "triangle_tags");
            const std::uint32_t nv = rows(vertices, 3, "vertices");
            const std::uint32_t nt = index_rows(tets, 4, "tets");
            if (nt == 0) {
              throw Error((source.empty() ? std::string("from_tets") : source) +
                          ": no tets; a domain is the volume of a tet mesh's tets");
            }
            TetMeshInput mesh;
            mesh.source = source;
            mesh.xyz.assign(vertices.data(), vertices.data() + 3 * std::size_t{nv});
            mesh.tets = as_u32(tets, nv, "tets");
            mesh.tet_line.assign(nt, 0);
            if (triangles.size() > 0) {
              index_rows(triangles, 3, "triangles");
              mesh.triangles = as_u32(triangles, nv, "triangles");
            }
            mesh.tet_ref = as_tags(tet_tags, nt, "tet_tags");
            mesh.triangle_ref = as_tags(triangle_tags, mesh.nb_triangles(), "triangle_tags");
            for (const auto& [dimension, tag, name] : tag_names) {
              if (dimension != 2 && dimension != 3) {
                throw Error("tag_names: dimension " + std::to_string(dimension) + " of tag " +
                            std::to_string(tag) + "; expected 2 (patches) or 3 (regions)");
              }
              mesh.tag_names.push_back({dimension, tag, name});
            }
            py::gil_scoped_release release;
            return Domain3(mesh);
          },
          "The volume of a tet mesh: (n, 3) vertices, (t, 4) tets, (m, 3) boundary or "
          "interface triangles, t tet tags and m triangle tags (each may be empty); `source` "
          "names it in messages; `tag_names`: (dimension, tag, name) triples, dimension 2 "
          "for triangle tags and 3 for tet tags (as a Gmsh file's physical names).",
          py::arg("vertices"), py::arg("tets"), py::arg("triangles"), py::arg("tet_tags"),
          py::arg("triangle_tags"), py::arg("source"),
          py::arg("tag_names") = std::vector<std::tuple<int, std::int32_t, std::string>>{})
      .def_static(
          "read",
          [](const std::string& path, bool reorient) {
            Surface3Options o;
            o.reorient = reorient;
            py::gil_scoped_release release;
            return read_domain3(path, o);
          },
          "The domain of a surface file (.obj, .off, .stl, .ply) or a tet mesh file (.mesh, "
          ".node/.ele, .msh, .vtk, .vtu); reorient=True turns a surface's inside-out shells.",
          py::arg("path"), py::arg("reorient") = false)
      .def_property_readonly("source", &Domain3::source)
      .def_property_readonly("volume", &Domain3::volume)
      .def_property_readonly("area", [](const Domain3& d) { return d.surface().area(); })
      .def_property_readonly("has_tets", &Domain3::has_tets)
      .def_property_readonly("nb_tets", &Domain3::nb_tets)
      .def_property_readonly("nb_shells",
                             [](const Domain3& d) { return d.surface().shells().size(); })
      .def("__repr__",
           [](const Domain3& d) {
             return "Domain3(source=" + py::repr(py::str(d.source())).cast<std::string>() +
                    ", triangles=" + std::to_string(d.surface().nb_triangles()) +
                    (d.has_tets() ? ", tets=" + std::to_string(d.nb_tets()) : std::string()) +
                    ", volume=" + py::repr(py::float_(d.volume())).cast<std::string>() + ")";
           })
      .def_property_readonly("bounds",
                             [](const Domain3& d) {
                               const double *lo = d.bbox_lo(), *hi = d.bbox_hi();
                               return py::make_tuple(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
                             })
      .def(
          "surface",
          [](const Domain3& d) {
            TriangleSurface s = boundary_surface(d);
            const auto nv = static_cast<py::ssize_t>(s.xyz.size() / 3);
            const auto nt = static_cast<py::ssize_t>(s.triangles.size() / 3);
            std::vector<std::int32_t> t(s.triangles.begin(), s.triangles.end());
            return py::make_tuple(to_array(std::move(s.xyz), {nv, 3}),
                                  to_array(std::move(t), {nt, 3}));
          },
          "The boundary surface: (vertices (n, 3), triangles (m, 3) int32), outward.")
      .def(
          "locate",
          [](const Domain3& d, const py::object& p) {
            return locate_all(double_array(p, "points"), 3,
                              [&](const double* q) { return d.locate(q); });
          },
          "Per point of an (n, 3) array, exactly: +1 strictly inside the volume, 0 on the "
          "surface, -1 outside (int8).",
          py::arg("points"));
}

void bind_clip(py::module_& m) {
  py::class_<Vectorized>(m, "Vectorized",
                         "A density or sizing callable that takes arrays of points (the "
                         "functions' vectorized=True).")
      .def(py::init([](const py::object& f) {
             if (PyCallable_Check(f.ptr()) == 0) {
               throw Error("vectorized: expected a callable, got " +
                           py::repr(f).cast<std::string>());
             }
             return Vectorized{f};
           }),
           py::arg("f"))
      .def_property_readonly("f", [](const Vectorized& v) { return v.f; });
  m.def("clip2d", &clip2d, py::arg("domain"), py::arg("sites"), py::arg("density") = py::none(),
        py::arg("geometry") = false, py::arg("neighbors") = false, py::arg("callback") = py::none(),
        py::arg("threads") = 0);
  m.def(
      "random_points2",
      [](const Domain2& domain, const py::object& n_arg, const py::object& seed_arg,
         const py::object& density) {
        const auto n = static_cast<std::uint32_t>(count_arg(n_arg, "n", UINT32_MAX));
        const std::uint64_t seed = count_arg(seed_arg, "seed", UINT64_MAX);
        std::shared_ptr<PyDensity> callback;
        const Density2 rho = density2(density, callback);
        std::vector<double> xy;
        run_released(py::int_(0), [&] { xy = random_points2(domain, n, seed, rho); });
        if (callback) callback->rethrow();
        return to_array(std::move(xy), {py::ssize_t{n}, 2});
      },
      py::arg("domain"), py::arg("n"), py::arg("seed") = 1, py::arg("density") = py::none());
  m.def(
      "random_points3",
      [](const Domain3& domain, const py::object& n_arg, const py::object& seed_arg,
         const py::object& density, const py::object& threads) {
        const auto n = static_cast<std::uint32_t>(count_arg(n_arg, "n", UINT32_MAX));
        const std::uint64_t seed = count_arg(seed_arg, "seed", UINT64_MAX);
        std::shared_ptr<PyDensity> callback;
        const Density3 rho = density3(density, callback);
        std::vector<double> xyz;
        run_released(threads, [&] { xyz = random_points3(domain, n, seed, rho); });
        if (callback) callback->rethrow();
        return to_array(std::move(xyz), {py::ssize_t{n}, 3});
      },
      py::arg("domain"), py::arg("n"), py::arg("seed") = 1, py::arg("density") = py::none(),
      py::arg("threads") = 0);
  m.def("clip3d", &clip3d, py::arg("domain"), py::arg("sites"), py::arg("density") = py::none(),
        py::arg("geometry") = false, py::arg("neighbors") = false, py::arg("callback") = py::none(),
        py::arg("threads") = 0);
}

}  // namespace voroclip::python
