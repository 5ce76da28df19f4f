// libFuzzer target: the bytes as a .vtk file, through read_tet_mesh(std::istream&, name).
#include <sstream>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  voroclip::fuzz::expect_only_error([&] {
    std::istringstream in(voroclip::fuzz::bytes(data, size));
    voroclip::fuzz::check_mesh(voroclip::read_tet_mesh(in, "fuzz.vtk"));
  });
  return 0;
}
