#include <nclink/version.hpp>

#define NCLINK_STR2(x) #x
#define NCLINK_STR(x) NCLINK_STR2(x)

namespace nclink {
const char* library_version() noexcept {
    return NCLINK_STR(NCLINK_VERSION_MAJOR) "." NCLINK_STR(NCLINK_VERSION_MINOR) "." NCLINK_STR(NCLINK_VERSION_PATCH);
}
}  // namespace nclink
