#include <catch2/catch.hpp>
#include <fcntl.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
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

TEST_CASE("write_files_atomically: all the files or none", "[core][regression]") {
  namespace fs = std::filesystem;
  const fs::path base =
      fs::temp_directory_path() / ("voroclip_write_files_" + std::to_string(::getpid()));
  fs::remove_all(base);
  fs::create_directories(base);
  const std::string a = (base / "a.txt").string(), b = (base / "b.txt").string(),
                    c = (base / "c.txt").string();
  const auto text = [](const char* t) { return [t](std::ostream& out) { out << t; }; };
  SECTION("every writer succeeds") {
    voroclip::write_files_atomically({{a, text("A")}, {b, text("B")}, {c, text("C")}});
    CHECK(slurp(a) == "A");
    CHECK(slurp(b) == "B");
    CHECK(slurp(c) == "C");
  }
  SECTION("the second writer throws: no file, no temporary, the old file kept") {
    voroclip::write_file_atomically(c, text("old"));
    CHECK_THROWS_WITH(voroclip::write_files_atomically(
                          {{a, text("A")},
                           {b, [](std::ostream&) { throw voroclip::Error("writer failed"); }},
                           {c, text("C")}}),
                      "writer failed");
    CHECK_FALSE(exists(a));
    CHECK_FALSE(exists(b));
    CHECK(slurp(c) == "old");
  }
  SECTION("the last file cannot be created (a directory of that name)") {
    fs::create_directories(base / "c.txt");
    CHECK_THROWS_AS(
        voroclip::write_files_atomically({{a, text("A")}, {b, text("B")}, {c, text("C")}}),
        voroclip::Error);
    CHECK_FALSE(exists(a));
    CHECK_FALSE(exists(b));
  }
  SECTION("two writers of one file") {
    CHECK_THROWS_WITH(voroclip::write_files_atomically(
                          {{a, text("A")}, {(base / "." / "a.txt").string(), text("B")}}),
                      Catch::Contains("it is the same file as"));
    CHECK_FALSE(exists(a));
  }
  for (const fs::directory_entry& e : fs::directory_iterator(base)) {
    CHECK(e.path().string().find(".voroclip-tmp") == std::string::npos);
  }
  fs::remove_all(base);
}

TEST_CASE("same_file: one file under several names", "[core]") {
  namespace fs = std::filesystem;
  const fs::path base =
      fs::temp_directory_path() / ("voroclip_same_file_" + std::to_string(::getpid()));
  fs::remove_all(base);
  fs::create_directories(base / "sub");
  const std::string x = (base / "x.csv").string();
  CHECK(voroclip::same_file(x, x));
  CHECK(voroclip::same_file(x, (base / "sub" / ".." / "x.csv").string()));
  CHECK(voroclip::same_file(x, (base / "." / "x.csv").string()));
  CHECK_FALSE(voroclip::same_file(x, (base / "y.csv").string()));
  CHECK_FALSE(voroclip::same_file(x, ""));
  CHECK_FALSE(voroclip::same_file("", ""));
  // Through a symbolic link to the directory (the file need not exist), and a hard link.
  fs::create_directory_symlink(base / "sub", base / "link");
  CHECK(voroclip::same_file((base / "sub" / "z.csv").string(), (base / "link" / "z.csv").string()));
  std::ofstream(x) << "x";
  fs::create_hard_link(x, base / "hard.csv");
  CHECK(voroclip::same_file(x, (base / "hard.csv").string()));
  fs::remove_all(base);
}

TEST_CASE("check_output_path: where no file can be created, whoever runs it",
          "[core][regression]") {
  // access(dir, W_OK), the former test, passes for root in /proc; the temporary is now
  // created and removed, so the work does not run before a late failure.
  try {
    voroclip::check_output_path("/proc/out.mesh");
    FAIL("expected an error");
  } catch (const voroclip::Error& e) {
    CHECK(std::string(e.what()).rfind("cannot write '/proc/out.mesh': ", 0) == 0);
  }
  const std::string ok = "test_core_check_output_ok.mesh";
  voroclip::check_output_path(ok);
  CHECK_FALSE(exists(ok));
  CHECK_FALSE(exists(ok + ".voroclip-tmp"));
  // An immutable file (chattr +i) cannot be replaced, not even by root. Setting the flag
  // needs CAP_LINUX_IMMUTABLE and a file system that has it (ext4, xfs, btrfs).
  const std::string frozen = "test_core_check_output_immutable.mesh";
  std::ofstream(frozen) << "old";
  const int fd = ::open(frozen.c_str(), O_RDONLY);
  REQUIRE(fd >= 0);
  int flags = 0;
  const bool set = ::ioctl(fd, FS_IOC_GETFLAGS, &flags) == 0 &&
                   (flags |= FS_IMMUTABLE_FL, ::ioctl(fd, FS_IOC_SETFLAGS, &flags) == 0);
  if (set) {
    CHECK_THROWS_WITH(voroclip::check_output_path(frozen), Catch::Contains("immutable"));
    flags &= ~FS_IMMUTABLE_FL;
    ::ioctl(fd, FS_IOC_SETFLAGS, &flags);
  } else {
    WARN("the immutable flag cannot be set here: that case is not checked");
  }
  ::close(fd);
  std::remove(frozen.c_str());
}

TEST_CASE("version is MAJOR.MINOR.PATCH", "[core]") {
  const std::string v = voroclip::version();
  CHECK(std::count(v.begin(), v.end(), '.') == 2);
  CHECK(v.front() >= '0');
  CHECK(v.front() <= '9');
}
