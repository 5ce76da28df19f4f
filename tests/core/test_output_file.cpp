#include <catch2/catch.hpp>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "voroclip/core.h"

namespace {

bool exists(const std::string& path) { return std::ifstream(path).good(); }

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST_CASE("write_file_atomically writes the whole content", "[core]") {
  const std::string path = "test_core_atomic_ok.txt";
  std::remove(path.c_str());
  voroclip::write_file_atomically(path, [](std::ostream& out) { out << "hello\n"; });
  CHECK(slurp(path) == "hello\n");
  CHECK_FALSE(exists(path + ".voroclip-tmp"));
  std::remove(path.c_str());
}

TEST_CASE("write_file_atomically leaves no partial file when the writer throws", "[core]") {
  const std::string path = "test_core_atomic_throw.txt";
  std::remove(path.c_str());
  CHECK_THROWS_AS(voroclip::write_file_atomically(path,
                                                  [](std::ostream& out) {
                                                    out << "partial";
                                                    throw voroclip::Error("writer failed");
                                                  }),
                  voroclip::Error);
  CHECK_FALSE(exists(path));
  CHECK_FALSE(exists(path + ".voroclip-tmp"));
}

TEST_CASE("write_file_atomically keeps the previous file when the writer throws", "[core]") {
  const std::string path = "test_core_atomic_keep.txt";
  voroclip::write_file_atomically(path, [](std::ostream& out) { out << "old"; });
  CHECK_THROWS(
      voroclip::write_file_atomically(path, [](std::ostream&) { throw voroclip::Error("no"); }));
  CHECK(slurp(path) == "old");
  std::remove(path.c_str());
}

TEST_CASE("write_file_atomically names the file when the directory is missing", "[core]") {
  try {
    voroclip::write_file_atomically("no/such/dir/out.txt", [](std::ostream& out) { out << 1; });
    FAIL("expected an error");
  } catch (const voroclip::Error& e) {
    CHECK(std::string(e.what()).find("no/such/dir/out.txt") != std::string::npos);
  }
}

TEST_CASE("check_output_path: a missing, unwritable or file directory, a directory path",
          "[core]") {
  namespace fs = std::filesystem;
  const fs::path base =
      fs::temp_directory_path() / ("voroclip_check_output_path_" + std::to_string(::getpid()));
  fs::remove_all(base);
  fs::create_directories(base / "dir");
  const auto message = [](const std::string& path) -> std::string {
    try {
      voroclip::check_output_path(path);
    } catch (const voroclip::Error& e) {
      return e.what();
    }
    return "";
  };
  CHECK(message("") == "");
  CHECK(message((base / "out.mesh").string()) == "");
  CHECK(message("relative.mesh") == "");
  CHECK(message((base / "no" / "out.mesh").string()) ==
        "cannot write '" + (base / "no" / "out.mesh").string() + "': no directory '" +
            (base / "no").string() + "'");
  CHECK(message((base / "dir").string()).find("it is a directory") != std::string::npos);
  std::ofstream((base / "file").string()) << "x";
  CHECK(message((base / "file" / "out.mesh").string()).find("is not a directory") !=
        std::string::npos);
  // Read-only directories stop writers other than root; skip when running as root.
  fs::create_directories(base / "ro");
  fs::permissions(base / "ro", fs::perms::owner_read | fs::perms::owner_exec);
  if (::geteuid() != 0) {
    CHECK(message((base / "ro" / "out.mesh").string()).find("is not writable") !=
          std::string::npos);
  }
  fs::permissions(base / "ro", fs::perms::owner_all);
  fs::remove_all(base);
}

TEST_CASE("version is MAJOR.MINOR.PATCH", "[core]") {
  const std::string v = voroclip::version();
  CHECK(std::count(v.begin(), v.end(), '.') == 2);
  CHECK(v.front() >= '0');
  CHECK(v.front() <= '9');
}
