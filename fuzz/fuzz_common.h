// Shared by the libFuzzer targets of fuzz/: what counts as a finding. A target hands the
// library the fuzzer's bytes; the library may refuse them with voroclip::Error (bad input
// gets a message, that is the contract), and everything else is a finding: a crash, a
// sanitizer report, another exception, a hang (libFuzzer's -timeout) or a large
// allocation (-malloc_limit_mb). Not installed, not part of the library.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>
#include <utility>

#include "voroclip/core.h"

namespace voroclip::fuzz {

// Runs `f`; returns normally when it returns or throws voroclip::Error, aborts (a finding
// libFuzzer reports with the input) on any other exception.
template <class F>
void expect_only_error(F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const voroclip::Error&) {
    // Refused with a message: fine.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "voroclip fuzz: exception other than voroclip::Error: %s\n", e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "voroclip fuzz: exception of an unknown type\n");
    std::abort();
  }
}

inline std::string bytes(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// A finding that is not a crash: an invariant the library promises does not hold.
[[noreturn]] inline void finding(const char* what) {
  std::fprintf(stderr, "voroclip fuzz: %s\n", what);
  std::abort();
}

// What read_tet_mesh promises of a mesh it returns: at least one tet, indices in range,
// finite coordinates, arrays of agreeing sizes.
inline void check_mesh(const TetMeshInput& mesh) {
  const std::uint32_t nv = mesh.nb_vertices();
  if (mesh.xyz.size() % 3 != 0 || mesh.tets.size() % 4 != 0 || mesh.triangles.size() % 3 != 0 ||
      mesh.tets.empty() || mesh.tet_line.size() != mesh.nb_tets() ||
      (!mesh.tet_ref.empty() && mesh.tet_ref.size() != mesh.nb_tets()) ||
      (!mesh.triangle_ref.empty() && mesh.triangle_ref.size() != mesh.nb_triangles())) {
    finding("mesh arrays of inconsistent sizes");
  }
  for (const std::uint32_t v : mesh.tets) {
    if (v >= nv) finding("a tet vertex index out of range");
  }
  for (const std::uint32_t v : mesh.triangles) {
    if (v >= nv) finding("a triangle vertex index out of range");
  }
  for (const double x : mesh.xyz) {
    if (!std::isfinite(x)) finding("a coordinate that is not finite");
  }
}

}  // namespace voroclip::fuzz
