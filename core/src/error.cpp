#include <string>

#include "voroclip/core.h"
#include "voroclip_version.h"

namespace voroclip {

const char* version() { return VOROCLIP_VERSION_STRING; }

std::string count_of(std::uint64_t n, const std::string& singular, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural.empty() ? singular + "s" : plural);
}

}  // namespace voroclip
