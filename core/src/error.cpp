#include "voroclip/core.h"
#include "voroclip_version.h"

namespace voroclip {

const char* version() { return VOROCLIP_VERSION_STRING; }

}  // namespace voroclip
