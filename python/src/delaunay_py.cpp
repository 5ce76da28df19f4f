// python/src/delaunay_py.cpp — Delaunay2 / Delaunay3 with scipy.spatial.Delaunay's
// conventions, and the vectorised exact predicates.
#include <algorithm>

#include "common.h"
#include "voroclip/delaunay.h"
#include "voroclip/predicates.h"

namespace voroclip::python {

namespace {

// ---- Predicates: each argument an (n, d) array or one point (d,) / (1, d), broadcast.
struct Rows {
  DoubleArray a;
  std::uint32_t n = 0;
  const double* row(std::uint32_t i, int dim) const {
    return a.data() + (n == 1 ? 0 : static_cast<std::size_t>(i) * static_cast<std::size_t>(dim));
  }
};

Rows as_rows(const py::handle& v, int dim, const char* what) {
  const DoubleArray a = double_array(v, what);
  Rows r;
  if (a.ndim() == 1) {
    r.a = py::cast<DoubleArray>(a.attr("reshape")(1, a.shape(0)));
  } else {
    r.a = a;
  }
  r.n = rows(r.a, dim, what);
  return r;
}

template <int kArgs, class F>
py::array_t<std::int8_t> vectorised(const std::vector<py::object>& args, int dim, F&& predicate) {
  std::vector<Rows> r;
  std::uint32_t n = 1;
  static const char* const kNames[] = {"a", "b", "c", "d", "e"};
  for (int k = 0; k < kArgs; ++k) {
    r.push_back(as_rows(args[static_cast<std::size_t>(k)], dim, kNames[k]));
    if (r.back().n != 1) {
      if (n != 1 && r.back().n != n) {
        throw Error(std::string(kNames[k]) + ": " + std::to_string(r.back().n) +
                    " points, the other arguments have " + std::to_string(n));
      }
      n = r.back().n;
    }
  }
  std::vector<std::int8_t> out(n);
  {
    py::gil_scoped_release release;
    for (std::uint32_t i = 0; i < n; ++i) {
      const double* p[kArgs];
      for (int k = 0; k < kArgs; ++k) {
        p[k] = r[static_cast<std::size_t>(k)].row(i, dim);
        for (int c = 0; c < dim; ++c) {
          if (!std::isfinite(p[k][c])) {
            throw Error(std::string(kNames[k]) + "[" + std::to_string(i) +
                        "]: a coordinate is not a finite number");
          }
        }
      }
      out[i] = static_cast<std::int8_t>(predicate(p));
    }
  }
  return to_array(std::move(out));
}

// ---- Triangulations. The points are copied: the C++ triangulation reads its point array
// for as long as it lives, and a caller's numpy array may change.
struct PyDelaunay2 {
  std::vector<double> xy;
  Delaunay2 dt;
};

struct PyDelaunay3 {
  std::vector<double> xyz;
  Delaunay3 dt;
  std::vector<std::int32_t> finite_index;  // per slot: index among the finite tets, or -1
  std::vector<std::uint32_t> finite_slot;  // per finite tet: its slot
};

// Query points the scipy way (scipy.spatial.Delaunay.find_simplex): xi of shape (..., dim),
// one point (dim,) included, read as n = xi.size / dim rows; the answers take the shape
// xi.shape[:-1] (a 0-d array for one point, as scipy's).
struct Queries {
  Queries(const py::object& xi_arg, int dim) : xi(double_array(xi_arg, "xi")) {
    const py::ssize_t nd = xi.ndim();
    if (nd == 0 || xi.shape(nd - 1) != dim) {
      std::string got;
      for (py::ssize_t k = 0; k < nd; ++k) got += (k ? ", " : "") + std::to_string(xi.shape(k));
      throw Error("xi: expected an (n, " + std::to_string(dim) + ") array or one point (" +
                  std::to_string(dim) + ",), got shape (" + got + (nd == 1 ? ",)" : ")"));
    }
    shape.assign(xi.shape(), xi.shape() + nd - 1);
    const py::ssize_t count = xi.size() / dim;
    if (count >= py::ssize_t{0xffffffff}) throw Error("xi: more than 2^32 - 2 points");
    n = static_cast<std::uint32_t>(count);
  }
  DoubleArray xi;  // C-contiguous: point i at xi.data() + dim * i
  std::uint32_t n = 0;
  std::vector<py::ssize_t> shape;  // of the answers
};

std::int32_t as_simplex(std::uint32_t t, std::uint32_t nb_finite) {
  return t < nb_finite ? static_cast<std::int32_t>(t) : -1;
}

template <class Dt>
py::tuple neighbor_vertices(const Dt& dt, std::uint32_t n) {
  std::vector<std::int32_t> indptr(std::size_t{n} + 1, 0);
  std::vector<std::int32_t> indices;
  std::vector<std::uint32_t> around;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (dt.duplicate_of(v) == v) {
      dt.vertex_neighbors(v, around);
      for (const std::uint32_t w : around) indices.push_back(static_cast<std::int32_t>(w));
    }
    indptr[v + 1] = static_cast<std::int32_t>(indices.size());
  }
  return py::make_tuple(to_array(std::move(indptr)), to_array(std::move(indices)));
}

}  // namespace

void bind_predicates(py::module_& m) {
  m.def(
      "orient2d",
      [](const py::object& a, const py::object& b, const py::object& c) {
        return vectorised<3>({a, b, c}, 2, [](const double* const* p) {
          return static_cast<int>(orient2d(p[0], p[1], p[2]));
        });
      },
      py::arg("a"), py::arg("b"), py::arg("c"));
  m.def(
      "incircle",
      [](const py::object& a, const py::object& b, const py::object& c, const py::object& d) {
        return vectorised<4>({a, b, c, d}, 2, [](const double* const* p) {
          return static_cast<int>(incircle(p[0], p[1], p[2], p[3]));
        });
      },
      py::arg("a"), py::arg("b"), py::arg("c"), py::arg("d"));
  m.def(
      "orient3d",
      [](const py::object& a, const py::object& b, const py::object& c, const py::object& d) {
        return vectorised<4>({a, b, c, d}, 3, [](const double* const* p) {
          return static_cast<int>(orient3d(p[0], p[1], p[2], p[3]));
        });
      },
      py::arg("a"), py::arg("b"), py::arg("c"), py::arg("d"));
  m.def(
      "insphere",
      [](const py::object& a, const py::object& b, const py::object& c, const py::object& d,
         const py::object& e) {
        return vectorised<5>({a, b, c, d, e}, 3, [](const double* const* p) {
          return static_cast<int>(insphere(p[0], p[1], p[2], p[3], p[4]));
        });
      },
      py::arg("a"), py::arg("b"), py::arg("c"), py::arg("d"), py::arg("e"));
}

void bind_delaunay(py::module_& m) {
  py::class_<PyDelaunay2>(m, "Delaunay2")
      .def(py::init([](const py::object& points_arg, const py::object& threads) {
             const DoubleArray points = double_array(points_arg, "points");
             const std::uint32_t n = rows(points, 2, "points");
             if (n > Delaunay2::kMaxPoints) throw Error("points: more than 2^29 points");
             auto d = std::make_unique<PyDelaunay2>();
             d->xy.assign(points.data(), points.data() + 2 * std::size_t{n});
             run_released(threads, [&] { d->dt.build(d->xy.data(), n); });
             return d;
           }),
           py::arg("points"), py::arg("threads") = 0)
      .def_property_readonly("npoints", [](const PyDelaunay2& d) { return d.dt.nb_points(); })
      .def_property_readonly("ndim", [](const PyDelaunay2&) { return 2; })
      .def_property_readonly("nsimplex", [](const PyDelaunay2& d) { return d.dt.nb_triangles(); })
      .def_property_readonly("points",
                             [](const PyDelaunay2& d) {
                               std::vector<double> xy = d.xy;
                               const auto n = static_cast<py::ssize_t>(xy.size() / 2);
                               return to_array(std::move(xy), {n, 2});
                             })
      .def_property_readonly(
          "simplices",
          [](const PyDelaunay2& d) {
            const std::uint32_t nt = d.dt.nb_triangles();
            std::vector<std::int32_t> s(3 * std::size_t{nt});
            for (std::size_t k = 0; k < s.size(); ++k) {
              s[k] = static_cast<std::int32_t>(d.dt.tri_vertices()[k]);
            }
            return to_array(std::move(s), {py::ssize_t{nt}, 3});
          },
          "(m, 3) int32: the triangles' point indices, counter-clockwise "
          "(orient2d(p0, p1, p2) = +1).")
      .def_property_readonly("neighbors",
                             [](const PyDelaunay2& d) {
                               const std::uint32_t nt = d.dt.nb_triangles();
                               std::vector<std::int32_t> s(3 * std::size_t{nt});
                               for (std::uint32_t t = 0; t < nt; ++t) {
                                 for (int k = 0; k < 3; ++k) {
                                   s[3 * std::size_t{t} + static_cast<std::size_t>(k)] =
                                       as_simplex(d.dt.tri_adjacent(t, k), nt);
                                 }
                               }
                               return to_array(std::move(s), {py::ssize_t{nt}, 3});
                             })
      .def_property_readonly("duplicate_of",
                             [](const PyDelaunay2& d) {
                               std::vector<std::int32_t> s(d.dt.nb_points());
                               for (std::uint32_t i = 0; i < d.dt.nb_points(); ++i) {
                                 s[i] = static_cast<std::int32_t>(d.dt.duplicate_of(i));
                               }
                               return to_array(std::move(s));
                             })
      .def_property_readonly(
          "convex_hull",
          [](const PyDelaunay2& d) {
            std::vector<std::uint32_t> e = d.dt.hull_edges();
            std::vector<std::int32_t> s(e.begin(), e.end());
            const auto ne = static_cast<py::ssize_t>(s.size() / 2);
            return to_array(std::move(s), {ne, 2});
          },
          "(h, 2) int32: the hull's edges (u, w), counter-clockwise (the inside on the left), "
          "in hull order from the smallest vertex; points on a hull edge are vertices of it.")
      .def_property_readonly(
          "hull_vertices",
          [](const PyDelaunay2& d) {
            std::vector<std::uint32_t> h = d.dt.hull_vertices();
            return to_array(std::vector<std::int32_t>(h.begin(), h.end()));
          },
          "(h,) int32: the hull's vertices counter-clockwise from the smallest index, points "
          "on a hull edge included (scipy.spatial.ConvexHull.vertices: the same cycle, "
          "without them, from another start).")
      .def_property_readonly(
          "vertex_neighbor_vertices",
          [](const PyDelaunay2& d) { return neighbor_vertices(d.dt, d.dt.nb_points()); })
      .def(
          "find_simplex",
          [](const PyDelaunay2& d, const py::object& xi_arg) {
            const Queries queries(xi_arg, 2);
            const DoubleArray& xi = queries.xi;
            const std::uint32_t n = queries.n;
            std::vector<std::int32_t> out(n);
            const double* p = xi.data();
            {
              py::gil_scoped_release release;
              std::uint32_t hint = Delaunay2::kNone;
              for (std::uint32_t i = 0; i < n; ++i) {
                const double x = p[2 * std::size_t{i}], y = p[2 * std::size_t{i} + 1];
                if (!std::isfinite(x) || !std::isfinite(y)) {
                  out[i] = -1;
                  continue;
                }
                const std::uint32_t t = d.dt.locate(x, y, hint);
                hint = t;
                out[i] = as_simplex(t, d.dt.nb_triangles());
              }
            }
            return to_array(std::move(out), queries.shape);
          },
          py::arg("xi"))
      .def(
          "nearest_vertex",
          [](const PyDelaunay2& d, const py::object& xi_arg) {
            const Queries queries(xi_arg, 2);
            const DoubleArray& xi = queries.xi;
            const std::uint32_t n = queries.n;
            std::vector<std::int32_t> out(n);
            const double* p = xi.data();
            {
              py::gil_scoped_release release;
              std::uint32_t hint = Delaunay2::kNone;
              for (std::uint32_t i = 0; i < n; ++i) {
                const double x = p[2 * std::size_t{i}], y = p[2 * std::size_t{i} + 1];
                if (!std::isfinite(x) || !std::isfinite(y)) {
                  throw Error("xi[" + std::to_string(i) + "]: a coordinate is not a finite number");
                }
                const std::uint32_t v = d.dt.nearest_vertex(x, y, hint);
                hint = d.dt.vertex_triangle(v);
                out[i] = static_cast<std::int32_t>(v);
              }
            }
            return to_array(std::move(out), queries.shape);
          },
          py::arg("xi"))
      .def(
          "vertex_neighbors",
          [](const PyDelaunay2& d, const py::object& point) {
            const std::uint32_t v = index_arg(point, d.dt.nb_points(), "vertex_neighbors", "point");
            std::vector<std::uint32_t> around;
            if (d.dt.duplicate_of(v) == v) d.dt.vertex_neighbors(v, around);
            return to_array(std::vector<std::int32_t>(around.begin(), around.end()));
          },
          py::arg("v"))
      .def("check", [](const PyDelaunay2& d) {
        std::string s = d.dt.check_topology();
        if (s.empty()) s = d.dt.check_delaunay();
        return s;
      });

  py::class_<PyDelaunay3>(m, "Delaunay3")
      .def(py::init([](const py::object& points_arg, const py::object& threads) {
             const DoubleArray points = double_array(points_arg, "points");
             const std::uint32_t n = rows(points, 3, "points");
             auto d = std::make_unique<PyDelaunay3>();
             d->xyz.assign(points.data(), points.data() + 3 * std::size_t{n});
             run_released(threads, [&] { d->dt.build(d->xyz.data(), n); });
             d->finite_index.assign(d->dt.nb_tet_slots(), -1);
             for (std::uint32_t t = 0; t < d->dt.nb_tet_slots(); ++t) {
               if (!d->dt.is_infinite(t)) {
                 d->finite_index[t] = static_cast<std::int32_t>(d->finite_slot.size());
                 d->finite_slot.push_back(t);
               }
             }
             return d;
           }),
           py::arg("points"), py::arg("threads") = 0)
      .def_property_readonly("npoints", [](const PyDelaunay3& d) { return d.dt.nb_points(); })
      .def_property_readonly("ndim", [](const PyDelaunay3&) { return 3; })
      .def_property_readonly("nsimplex", [](const PyDelaunay3& d) { return d.finite_slot.size(); })
      .def_property_readonly("points",
                             [](const PyDelaunay3& d) {
                               std::vector<double> xyz = d.xyz;
                               const auto n = static_cast<py::ssize_t>(xyz.size() / 3);
                               return to_array(std::move(xyz), {n, 3});
                             })
      .def_property_readonly(
          "simplices",
          [](const PyDelaunay3& d) {
            const std::size_t nt = d.finite_slot.size();
            std::vector<std::int32_t> s(4 * nt);
            for (std::size_t i = 0; i < nt; ++i) {
              for (int k = 0; k < 4; ++k) {
                s[4 * i + static_cast<std::size_t>(k)] =
                    static_cast<std::int32_t>(d.dt.tet_vertex(d.finite_slot[i], k));
              }
            }
            return to_array(std::move(s), {static_cast<py::ssize_t>(nt), 4});
          },
          "(m, 4) int32: the tets' point indices, with det(p1 - p0, p2 - p0, p3 - p0) < 0 "
          "(orient3d(p0, p1, p2, p3) = +1 in Shewchuk's convention), exactly: the opposite "
          "of Mesh.cells (and VTK), whose tets have det > 0; simplices[:, [1, 0, 2, 3]] turns "
          "them so.")
      .def_property_readonly("neighbors",
                             [](const PyDelaunay3& d) {
                               const std::size_t nt = d.finite_slot.size();
                               std::vector<std::int32_t> s(4 * nt);
                               for (std::size_t i = 0; i < nt; ++i) {
                                 for (int k = 0; k < 4; ++k) {
                                   s[4 * i + static_cast<std::size_t>(k)] =
                                       d.finite_index[d.dt.tet_adjacent(d.finite_slot[i], k)];
                                 }
                               }
                               return to_array(std::move(s), {static_cast<py::ssize_t>(nt), 4});
                             })
      .def_property_readonly("duplicate_of",
                             [](const PyDelaunay3& d) {
                               std::vector<std::int32_t> s(d.dt.nb_points());
                               for (std::uint32_t i = 0; i < d.dt.nb_points(); ++i) {
                                 s[i] = static_cast<std::int32_t>(d.dt.duplicate_of(i));
                               }
                               return to_array(std::move(s));
                             })
      .def_property_readonly(
          "hull_vertices",
          [](const PyDelaunay3& d) {
            std::vector<std::uint32_t> h = d.dt.hull_vertices();
            return to_array(std::vector<std::int32_t>(h.begin(), h.end()));
          },
          "(h,) int32: the hull's vertices, sorted (scipy.spatial.ConvexHull.vertices' order "
          "in 3D), points on the hull's faces and edges included.")
      .def_property_readonly(
          "convex_hull",
          [](const PyDelaunay3& d) {
            // The hull facet of an infinite tet is its vertices 0, 1, 2, which appear
            // counter-clockwise from inside the hull (orient3d(v0, v1, v2, inside) = -1 in
            // Shewchuk's convention): v1, v0, v2 is counter-clockwise seen from outside.
            // Coplanar points on the hull are triangulated within the facet (delaunay.h).
            std::vector<std::int32_t> s;
            for (std::uint32_t t = 0; t < d.dt.nb_tet_slots(); ++t) {
              if (!d.dt.is_infinite(t)) continue;
              for (const int k : {1, 0, 2}) {
                s.push_back(static_cast<std::int32_t>(d.dt.tet_vertex(t, k)));
              }
            }
            const auto nf = static_cast<py::ssize_t>(s.size() / 3);
            return to_array(std::move(s), {nf, 3});
          },
          "(h, 3) int32: the hull's triangles, counter-clockwise seen from outside (the "
          "right-hand normal points out), in slot order; coplanar points on the hull are "
          "vertices of it, their faces triangulated.")
      .def_property_readonly(
          "vertex_neighbor_vertices",
          [](const PyDelaunay3& d) { return neighbor_vertices(d.dt, d.dt.nb_points()); })
      .def(
          "find_simplex",
          [](const PyDelaunay3& d, const py::object& xi_arg) {
            const Queries queries(xi_arg, 3);
            const DoubleArray& xi = queries.xi;
            const std::uint32_t n = queries.n;
            std::vector<std::int32_t> out(n);
            const double* p = xi.data();
            {
              py::gil_scoped_release release;
              std::uint32_t hint = Delaunay3::kNoTet;
              for (std::uint32_t i = 0; i < n; ++i) {
                const double* q = p + 3 * std::size_t{i};
                if (!std::isfinite(q[0]) || !std::isfinite(q[1]) || !std::isfinite(q[2])) {
                  out[i] = -1;
                  continue;
                }
                const std::uint32_t t = d.dt.locate(q, hint);
                hint = t;
                out[i] = d.finite_index[t];
              }
            }
            return to_array(std::move(out), queries.shape);
          },
          py::arg("xi"))
      .def(
          "nearest_vertex",
          [](const PyDelaunay3& d, const py::object& xi_arg) {
            const Queries queries(xi_arg, 3);
            const DoubleArray& xi = queries.xi;
            const std::uint32_t n = queries.n;
            std::vector<std::int32_t> out(n);
            const double* p = xi.data();
            {
              py::gil_scoped_release release;
              std::uint32_t hint = Delaunay3::kNoTet;
              for (std::uint32_t i = 0; i < n; ++i) {
                const std::uint32_t v = d.dt.nearest_vertex(p + 3 * std::size_t{i}, hint);
                hint = d.dt.vertex_tet(v);
                out[i] = static_cast<std::int32_t>(v);
              }
            }
            return to_array(std::move(out), queries.shape);
          },
          py::arg("xi"))
      .def(
          "vertex_neighbors",
          [](const PyDelaunay3& d, const py::object& point) {
            const std::uint32_t v = index_arg(point, d.dt.nb_points(), "vertex_neighbors", "point");
            std::vector<std::uint32_t> around;
            if (d.dt.duplicate_of(v) == v) d.dt.vertex_neighbors(v, around);
            return to_array(std::vector<std::int32_t>(around.begin(), around.end()));
          },
          py::arg("v"))
      .def("check", [](const PyDelaunay3& d) {
        std::string s = d.dt.check_topology();
        if (s.empty()) s = d.dt.check_delaunay();
        return s;
      });
}

}  // namespace voroclip::python
