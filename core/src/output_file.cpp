// Output files that appear whole or not at all (write_file_atomically,
// write_files_atomically), the checks made before any work (check_output_path), and
// whether two paths name one file (same_file).
#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>
#ifdef __linux__
#include <linux/fs.h>
#endif

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "voroclip/core.h"

namespace voroclip {

namespace {

// Beside the target, so that rename() never crosses file systems.
std::string temporary_of(const std::string& path) { return path + ".voroclip-tmp"; }

// Writes the content of `write` to `tmp`, the temporary of `path`; on any failure the
// temporary is removed and the exception thrown (an Error naming `path`, or the writer's).
void write_temporary(const std::string& path, const std::string& tmp,
                     const std::function<void(std::ostream&)>& write) {
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

bool path_exists(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0;
}

}  // namespace

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  write_files_atomically({{path, write}});
}

void write_files_atomically(const std::vector<FileWriter>& files) {
  for (std::size_t k = 0; k < files.size(); ++k) {
    if (files[k].path.empty()) throw Error("output file name is empty");
    for (std::size_t j = 0; j < k; ++j) {
      if (same_file(files[j].path, files[k].path)) {
        throw Error("cannot write '" + files[k].path + "': it is the same file as '" +
                    files[j].path + "', written too");
      }
    }
  }
  std::vector<std::string> tmp;
  tmp.reserve(files.size());
  try {
    for (const FileWriter& f : files) {
      tmp.push_back(temporary_of(f.path));
      write_temporary(f.path, tmp.back(), f.write);
    }
  } catch (...) {
    // The temporary of the file that failed is gone already; the others go now.
    for (std::size_t j = 0; j + 1 < tmp.size(); ++j) std::remove(tmp[j].c_str());
    throw;
  }
  // Every file is written: the renames. Which targets existed before, for the undo.
  std::vector<char> existed(files.size());
  for (std::size_t k = 0; k < files.size(); ++k) existed[k] = path_exists(files[k].path) ? 1 : 0;
  for (std::size_t k = 0; k < files.size(); ++k) {
    if (std::rename(tmp[k].c_str(), files[k].path.c_str()) != 0) {
      const int err = errno;
      for (std::size_t j = 0; j < k; ++j) {
        if (!existed[j]) std::remove(files[j].path.c_str());
      }
      for (std::size_t j = k; j < files.size(); ++j) std::remove(tmp[j].c_str());
      throw Error("cannot write '" + files[k].path + "': " + std::strerror(err));
    }
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
  // access() answers for the permission bits only, which root passes: the temporary itself
  // is created and removed, so that /proc, /sys or a read-only file system fail here and
  // not after the work.
  const std::string tmp = temporary_of(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd >= 0) {
    ::close(fd);
    ::unlink(tmp.c_str());
  } else if (errno == EEXIST) {
    // Left by an interrupted run: write_file_atomically truncates it. It must open.
    const int old = ::open(tmp.c_str(), O_WRONLY | O_CLOEXEC | O_NONBLOCK);
    if (old < 0) {
      throw Error("cannot write '" + path + "': cannot write its temporary file '" + tmp + "' (" +
                  std::strerror(errno) + ")");
    }
    ::close(old);
  } else {
    throw Error("cannot write '" + path + "': no file can be created in '" + dir.string() + "' (" +
                std::strerror(errno) + ")");
  }
#ifdef __linux__
  // rename() cannot replace an immutable or append-only file (chattr +i / +a), root or not.
  if (fs::is_regular_file(fs::path(path), ec)) {
    const int file = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    int flags = 0;
    const bool got = file >= 0 && ::ioctl(file, FS_IOC_GETFLAGS, &flags) == 0;
    if (file >= 0) ::close(file);
    if (got && (flags & (FS_IMMUTABLE_FL | FS_APPEND_FL)) != 0) {
      throw Error(
          "cannot write '" + path + "': the file is " +
          ((flags & FS_IMMUTABLE_FL) != 0 ? "immutable (chattr +i)" : "append-only (chattr +a)") +
          " and cannot be replaced");
    }
  }
#endif
}

bool same_file(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  namespace fs = std::filesystem;
  const auto normal = [](const std::string& p) {
    std::error_code ec;
    fs::path absolute = fs::absolute(fs::path(p), ec);
    if (ec) absolute = fs::path(p);
    fs::path canonical = fs::weakly_canonical(absolute, ec);
    return ec ? absolute.lexically_normal() : canonical;
  };
  if (normal(a) == normal(b)) return true;
  std::error_code ec;
  return fs::equivalent(fs::path(a), fs::path(b), ec) && !ec;
}

}  // namespace voroclip
