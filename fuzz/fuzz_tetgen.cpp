// libFuzzer target: TetGen .node/.ele/.face through read_tetgen_mesh. The input is the
// three files one after the other, separated by a NUL byte: "node\0ele[\0face]" (no
// second NUL: no .face file).
#include <sstream>
#include <string>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string all = voroclip::fuzz::bytes(data, size);
  const std::size_t a = all.find('\0');
  if (a == std::string::npos) return 0;
  const std::size_t b = all.find('\0', a + 1);
  std::istringstream node(all.substr(0, a));
  std::istringstream ele(all.substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1));
  std::istringstream face(b == std::string::npos ? std::string() : all.substr(b + 1));
  voroclip::fuzz::expect_only_error([&] {
    voroclip::fuzz::check_mesh(
        voroclip::read_tetgen_mesh(node, ele, b == std::string::npos ? nullptr : &face, "fuzz"));
  });
  return 0;
}
