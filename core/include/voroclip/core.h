// voroclip/core.h — what every module shares: the one error type, the library version,
// and output files that appear whole or not at all.
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <stdexcept>
#include <string>

namespace voroclip {

/// The library's version, "MAJOR.MINOR.PATCH".
const char* version();

/// The single exception type the library throws for bad input or an impossible request.
/// The message names what is wrong and where (file, line, element) so a user can act on it;
/// the library never calls exit() or abort() on user data.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// Writes a file so that it is either complete or absent: the content goes to a temporary
/// file beside `path`, which is renamed over `path` only after `write` returned and the
/// stream was flushed without error. If `write` throws, or anything fails, the temporary is
/// removed, `path` is left as it was, and an Error naming the file is thrown (the exception
/// thrown by `write` is rethrown unchanged).
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

}  // namespace voroclip
