// python/src/module.cpp — the compiled core of the `voroclip` Python package
// (voroclip._core): the error type, shared helpers, and the module definition. The Python
// layer (python/voroclip/*.py) turns user inputs into the arrays these functions take and
// their dicts of arrays into result objects.
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <utility>

#include "common.h"

namespace voroclip::python {

std::uint32_t rows(const py::array& a, int dim, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != dim) {
    std::ostringstream s;
    s << what << ": expected an (n, " << dim << ") array, got shape (";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s << (k ? ", " : "") << a.shape(k);
    s << (a.ndim() == 1 ? ",)" : ")");
    throw Error(s.str());
  }
  if (a.shape(0) >= py::ssize_t{0xffffffff}) {
    throw Error(std::string(what) + ": more than 2^32 - 2 points");
  }
  return static_cast<std::uint32_t>(a.shape(0));
}

namespace {

// "type repr" of a value for a message, the repr cut at 60 characters.
std::string describe(const py::handle& v) {
  std::string r = py::repr(v).cast<std::string>();
  if (r.size() > 60) r = r.substr(0, 57) + "...";
  return std::string(Py_TYPE(v.ptr())->tp_name) + " " + r;
}

// v through __index__, or Error "what: expected an integer, got <type> <repr>".
py::int_ as_int(const py::handle& v, const char* what) {
  PyObject* i = PyNumber_Index(v.ptr());
  if (i == nullptr) {
    PyErr_Clear();
    throw Error(std::string(what) + ": expected an integer, got " + describe(v));
  }
  return py::reinterpret_steal<py::int_>(i);
}

std::string bound_text(std::uint64_t max) {
  if (max == UINT64_MAX) return "2^64 - 1";
  if (max == UINT32_MAX) return "2^32 - 1";
  return std::to_string(max);
}

// numpy's reason for not converting v to dtype, for a message.
std::string numpy_refusal(const py::handle& v, const char* dtype) {
  try {
    py::module_::import("numpy").attr("asarray")(v, py::arg("dtype") = dtype);
  } catch (py::error_already_set& e) {
    return py::str(e.value()).cast<std::string>();
  }
  return "not convertible";
}

}  // namespace

std::uint64_t count_arg(const py::handle& v, const char* what, std::uint64_t max) {
  const py::int_ i = as_int(v, what);
  const unsigned long long x = PyLong_AsUnsignedLongLong(i.ptr());
  const bool overflow = x == static_cast<unsigned long long>(-1) && PyErr_Occurred() != nullptr;
  if (overflow) PyErr_Clear();
  if (overflow || x > max) {
    throw Error(std::string(what) + ": expected an integer in [0, " + bound_text(max) + "], got " +
                py::repr(i).cast<std::string>());
  }
  return x;
}

std::uint32_t index_arg(const py::handle& v, std::uint32_t count, const char* what,
                        const char* noun) {
  const py::int_ i = as_int(v, what);
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow != 0 || x < 0 || x >= static_cast<long long>(count)) {
    throw Error(std::string(what) + ": no " + noun + " " + py::repr(i).cast<std::string>() +
                (count == 0
                     ? std::string(" (there is none)")
                     : " (" + std::string(noun) + "s 0 to " + std::to_string(count - 1) + ")"));
  }
  return static_cast<std::uint32_t>(x);
}

DoubleArray double_array(const py::handle& v, const char* what) {
  auto a = DoubleArray::ensure(v);
  if (!a) {
    throw Error(std::string(what) + ": expected an array of numbers, got " + describe(v) + " (" +
                numpy_refusal(v, "float64") + ")");
  }
  return a;
}

IndexArray index_array(const py::handle& v, const char* what) {
  auto a = IndexArray::ensure(v);
  if (!a) {
    throw Error(std::string(what) + ": expected an array of integers, got " + describe(v) + " (" +
                numpy_refusal(v, "int64") + ")");
  }
  return a;
}

int thread_count(const py::handle& threads) {
  if (threads.is_none()) return 0;
  const py::int_ i = as_int(threads, "threads");
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow < 0 || (overflow == 0 && x < 0)) {
    throw Error("threads: expected 0 or None (all cores) or a count >= 1, got " +
                py::repr(i).cast<std::string>());
  }
  const auto most = static_cast<long long>(
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  return static_cast<int>(overflow > 0 ? most : std::min(x, most));
}

void run_released(const py::handle& threads, const std::function<void()>& f) {
  const int n = thread_count(threads);
  py::gil_scoped_release release;
  if (n == 0) {
    f();
  } else {
    tbb::task_arena arena(n);
    arena.execute(f);
  }
}

bool Progress::check(const std::function<py::dict()>& info) {
  py::gil_scoped_acquire acquire;
  if (error_) return false;
  try {
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!callback_.is_none()) {
      // None (no return statement) continues; otherwise the truth value decides.
      const py::object r = callback_(info());
      if (r.is_none()) return true;
      const int truth = PyObject_IsTrue(r.ptr());
      if (truth < 0) throw py::error_already_set();
      return truth != 0;
    }
  } catch (py::error_already_set& e) {
    error_ = std::make_unique<py::error_already_set>(std::move(e));
    return false;
  }
  return true;
}

void Progress::rethrow() {
  if (error_) {
    py::error_already_set e = std::move(*error_);
    error_.reset();
    throw e;
  }
}

namespace {

// voroclip.Error, the type the translator below raises (the module holds it).
PyObject* error_type = nullptr;

// The library's message with the C++ names of what the caller can change replaced by what
// says the same in Python (as the command line's cli_message does with its options).
std::string python_message(std::string text) {
  static const std::pair<const char*, const char*> kNames[] = {
      {"Surface3Options::reorient, --reorient", "reorient=True"},
      {"ClippedVoronoi3::compute(domain, sites, n) takes them", "clip3d takes them"},
  };
  for (const auto& [api, python] : kNames) {
    const std::string from = api, to = python;
    for (std::size_t at = text.find(from); at != std::string::npos;
         at = text.find(from, at + to.size())) {
      text.replace(at, from.size(), to);
    }
  }
  return text;
}

}  // namespace

}  // namespace voroclip::python

PYBIND11_MODULE(_core, m) {
  namespace vp = voroclip::python;
  m.doc() =
      "The compiled core of voroclip: exact clipped Voronoi diagrams, CVT and CVT meshing. "
      "Use the functions of the `voroclip` package, which wrap these.";
  m.attr("__version__") = voroclip::version();
  // voroclip::Error -> voroclip.Error, a ValueError: bad input or an impossible request,
  // with the library's message.
  const auto error = vp::py::register_exception<voroclip::Error>(m, "Error", PyExc_ValueError);
  vp::error_type = error.ptr();
  vp::py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const voroclip::Error& e) {
      PyErr_SetString(vp::error_type, vp::python_message(e.what()).c_str());
    }
  });
  error.attr("__doc__") =
      "Bad input or an impossible request, with the library's message: it names the argument "
      "and the value, the file and the line, or the point. A ValueError (`except ValueError` "
      "catches it). The functions of voroclip raise it for bad input and for a clipping "
      "cancelled by its callback; Ctrl-C raises KeyboardInterrupt, and an exception raised "
      "by a callback (progress, density) is re-raised as itself.";
  vp::bind_predicates(m);
  vp::bind_delaunay(m);
  vp::bind_domains(m);
  vp::bind_clip(m);
  vp::bind_cvt_mesh(m);
}
