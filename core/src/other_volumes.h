// core/src/other_volumes.h — the volume elements a tet mesh reader does not read
// (tetmesh_io.cpp's Medit, Gmsh and legacy VTK readers, vtu_io.cpp's .vtu reader; internal
// to the core module).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "voroclip/core.h"

namespace voroclip::detail {

// Volume elements that are not read as tetrahedra (hexahedra, prisms, pyramids, ...). A
// mesh with any is refused: its tets alone are part of its volume, and reading them
// without a word would give a wrong domain. Counted per kind, the first of each kind kept
// as the file numbers it (`where`: "element 7, type 5", "Hexahedra entry 1", "cell 3, type
// 12") with its line (0 in binary data).
class OtherVolumes {
 public:
  void add(std::string_view kind, std::string_view kinds, std::uint32_t line,
           const std::function<std::string()>& where) {
    for (Kind& k : kinds_) {
      if (k.kind == kind) {
        ++k.count;
        return;
      }
    }
    kinds_.push_back({std::string(kind), std::string(kinds), where(), line, 1});
  }
  // Throws when any was added: "path:line: what" at the line of the first one ("path: what"
  // for line 0).
  void check(const std::string& path) const {
    if (kinds_.empty()) return;
    std::string what;
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < kinds_.size(); ++i) {
      const Kind& k = kinds_[i];
      what += i == 0 ? "" : i + 1 == kinds_.size() ? " and " : ", ";
      what += std::to_string(k.count) + " " + (k.count == 1 ? k.kind : k.kinds) + " (" +
              (k.count == 1 ? "" : "the first ") + k.where + ")";
      total += k.count;
    }
    const std::uint32_t line = kinds_.front().line;
    throw Error(path + (line == 0 ? std::string() : ":" + std::to_string(line)) + ": " + what +
                (total == 1 ? " is not a tetrahedron" : " are not tetrahedra") +
                ": only tetrahedral volume meshes are read; give the boundary surface "
                "(.obj/.stl/.ply/.off) or a tet mesh");
  }

 private:
  struct Kind {
    std::string kind, kinds, where;
    std::uint32_t line;
    std::uint64_t count;
  };
  std::vector<Kind> kinds_;
};

}  // namespace voroclip::detail
