// The JSON value type of nclink's public API: item values, DTU payloads and
// models are nlohmann::json values (Debian's nlohmann-json3-dev).
#pragma once

#include <nlohmann/json.hpp>

namespace nclink {
using Json = nlohmann::json;
}  // namespace nclink
