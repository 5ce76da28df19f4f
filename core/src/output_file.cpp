#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "voroclip/core.h"

namespace voroclip {

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  if (path.empty()) throw Error("output file name is empty");
  // Same directory as the target, so that rename() never crosses file systems.
  const std::string tmp = path + ".voroclip-tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw Error("cannot write '" + path + "': " + std::strerror(errno));
    }
    try {
      write(out);
      out.flush();
    } catch (...) {
      out.close();
      std::remove(tmp.c_str());
      throw;
    }
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw Error("error while writing '" + path + "' (disk full?)");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw Error("cannot write '" + path + "': " + std::strerror(err));
  }
}

void check_output_path(const std::string& path) {
  if (path.empty()) return;
  namespace fs = std::filesystem;
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::exists(dir, ec)) {
    throw Error("cannot write '" + path + "': no directory '" + dir.string() + "'");
  }
  if (!fs::is_directory(dir, ec)) {
    throw Error("cannot write '" + path + "': '" + dir.string() + "' is not a directory");
  }
  if (fs::is_directory(fs::path(path), ec)) {
    throw Error("cannot write '" + path + "': it is a directory");
  }
  // The temporary file goes beside `path`: the directory must take new files.
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    throw Error("cannot write '" + path + "': directory '" + dir.string() + "' is not writable (" +
                std::strerror(errno) + ")");
  }
}

}  // namespace voroclip
