// python/src/common.h — what the binding's source files share: numpy conversions (zero-copy
// in, owned arrays out), the thread-count arena, and the bridge from C++ progress callbacks
// to Python (callbacks, Ctrl-C).
#pragma once

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "voroclip/clip.h"
#include "voroclip/core.h"

namespace voroclip::python {

namespace py = pybind11;

// A float64 C-contiguous array: pybind11 passes such an array through without copying and
// converts anything else (other dtypes, strides, lists) to a new one.
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// Checks that `a` is an (n, dim) array with n < 2^32 and returns n. Throws voroclip::Error
// "what: expected an (n, dim) array, got shape (...)" otherwise.
std::uint32_t rows(const py::array& a, int dim, const char* what);

// An owned numpy array that takes over `v` (no copy): its base is a capsule holding the
// vector.
template <class T>
py::array_t<T> to_array(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* owner = new std::vector<T>(std::move(v));
  py::capsule base(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(std::move(shape), owner->data(), base);
}
template <class T>
py::array_t<T> to_array(std::vector<T>&& v) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return to_array(std::move(v), {n});
}

// ---- Arguments from Python, checked here: a bad value throws Error naming the argument
// and the value, never pybind11's TypeError listing C++ signatures. An integer is a Python
// int or anything with __index__ (numpy integers, bool), not a float.

// v as an integer in [0, max]: "what: expected an integer in [0, max], got v".
std::uint64_t count_arg(const py::handle& v, const char* what, std::uint64_t max);
// v as an index in [0, count): "what: no <noun> v (<noun>s 0 to count - 1)".
std::uint32_t index_arg(const py::handle& v, std::uint32_t count, const char* what,
                        const char* noun);
// v as a float64 (int64) C-contiguous array: passed through when it is one, else
// converted by numpy; "what: expected an array of numbers, got <type> <repr> (numpy's
// reason)" when numpy cannot.
DoubleArray double_array(const py::handle& v, const char* what);
IndexArray index_array(const py::handle& v, const char* what);

// The `threads` argument of every call that takes one: None or 0 for all cores, n >= 1 for
// min(n, tbb::global_control::max_allowed_parallelism) threads (the cores, unless the
// process set a lower limit): TBB runs no more at once, and an arena of 100,000 slots
// crashed inside TBB. A negative count or a non-integer throws Error.
int thread_count(const py::handle& threads);

// Runs f with the GIL released, on thread_count(threads) TBB threads. Every parallel loop
// of the library runs inside that arena.
void run_released(const py::handle& threads, const std::function<void()>& f);

// The bridge between a C++ progress callback (called on the computing thread, the GIL
// released) and Python: check() takes the GIL, runs the user's callback if any (a false
// return stops the run) and PyErr_CheckSignals (Ctrl-C stops it and is re-raised by
// rethrow()). Any Python exception stops the run and is re-raised.
class Progress {
 public:
  explicit Progress(py::object callback) : callback_(std::move(callback)) {}
  // Returns false to stop. `info` builds the dict handed to the callback.
  bool check(const std::function<py::dict()>& info);
  // After the run, with the GIL held: raises the stored Python exception, if any.
  void rethrow();
  bool stopped_by_error() const { return static_cast<bool>(error_); }

 private:
  py::object callback_;
  std::unique_ptr<py::error_already_set> error_;
};

// A Python density callback called from the library's worker threads: each call takes the
// GIL. The first Python exception is kept (and 1.0 returned from then on) and re-raised by
// rethrow() after the computation. A value that is not finite and positive throws Error
// naming the point and the value at once (the library stops the run), as the CLI's
// --density formulas do.
class PyDensity {
 public:
  // `what` names the value in messages ("density", or "sizing" for an edge length h).
  // `vectorized`: f takes numpy arrays (x, y[, z]) of n points and returns n values (see
  // batch()); operator() then calls it with arrays of one point.
  explicit PyDensity(py::object f, std::string what = "density", bool vectorized = false)
      : f_(std::move(f)), what_(std::move(what)), vectorized_(vectorized) {}
  bool vectorized() const { return vectorized_; }
  // The values at n points (xyz: dim coordinates each) in one call of a vectorized f: it
  // gets float64 arrays x, y[, z] of shape (n,) (copies, its to keep) and returns an
  // array of shape (n,) or one number for all. After a Python error, 1.0 everywhere.
  // Another shape, or a value that is not finite and positive, throws Error naming it.
  void batch(const double* xyz, std::size_t n, double* out, int dim);
  // Called from worker threads. The GIL is all the locking: error_ is read and written only
  // while this thread holds it, between Python calls (the interpreter may hand the GIL to
  // another thread while f_ runs, so a second lock taken after the GIL would deadlock with
  // a thread that holds it and waits for the GIL). The first error is kept.
  double operator()(double x, double y, double z, int dim) {
    if (vectorized_) {
      const double p[3] = {x, y, z};
      double v = 1.0;
      batch(p, 1, &v, dim);
      return v;
    }
    py::gil_scoped_acquire acquire;
    if (error_) return 1.0;
    double v = 1.0;
    try {
      v = (dim == 2 ? f_(x, y) : f_(x, y, z)).cast<double>();
    } catch (py::error_already_set& e) {
      keep(e);
      return 1.0;
    } catch (py::cast_error&) {
      if (!error_) {
        PyErr_SetString(PyExc_TypeError, (what_ + ": the function must return a number").c_str());
        error_ = std::make_unique<py::error_already_set>();
      }
      return 1.0;
    }
    if (!(v > 0) || !std::isfinite(v)) {
      const double p[3] = {x, y, z};
      bad_value(v, p, dim);
    }
    return v;
  }
  void rethrow() {
    if (error_) {
      py::error_already_set e = std::move(*error_);
      error_.reset();
      throw e;
    }
  }

 private:
  // Keeps the first Python error (the GIL held).
  void keep(py::error_already_set& e) {
    if (!error_) error_ = std::make_unique<py::error_already_set>(std::move(e));
  }
  [[noreturn]] void bad_value(double v, const double* p, int dim) const;

  py::object f_;
  std::string what_;
  bool vectorized_ = false;
  std::unique_ptr<py::error_already_set> error_;
};

// A callable marked as vectorized (the Python functions' `vectorized=True`, which wrap it
// in _core.Vectorized): PyDensity calls it with arrays of points.
struct Vectorized {
  py::object f;
};
// `v`'s callable when it is a Vectorized (its f), else nullopt.
std::optional<py::object> vectorized_callable(const py::object& v);

// The library's density from a Python value: None (1), a number, a callable rho(x, y[, z])
// (called from worker threads; kept alive in `callback`, whose rethrow() the caller must
// call after the computation) or a Vectorized callable (in 3D evaluated in batches of
// points, Density3::batch_function; in 2D a point at a time), in 2D a grid tuple (values[ny, nx],
// lo, hi), in 3D one value per vertex of the tet mesh.
Density2 density2(const py::object& density, std::shared_ptr<PyDensity>& callback);
Density3 density3(const py::object& density, std::shared_ptr<PyDensity>& callback);

void bind_delaunay(py::module_& m);
void bind_domains(py::module_& m);
void bind_clip(py::module_& m);
void bind_cvt_mesh(py::module_& m);
void bind_predicates(py::module_& m);

}  // namespace voroclip::python
