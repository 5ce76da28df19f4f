#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

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

}  // namespace voroclip
