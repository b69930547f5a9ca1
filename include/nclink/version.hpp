// nclink library version (semantic versioning; the ABI follows the major).
#pragma once

#include <nclink/export.hpp>
#define NCLINK_VERSION_MAJOR 0
#define NCLINK_VERSION_MINOR 1
#define NCLINK_VERSION_PATCH 0

namespace nclink {
/// "0.1.0": the version of the library actually linked (may differ from the
/// header's macros when linking a shared library).
NCLINK_API const char* library_version() noexcept;
}  // namespace nclink
