// Which keys of an adapter configuration differ between two configurations,
// named by their dotted path in the file ("broker.url", "sampling.qos"):
// what Adapter::reload reports (docs/configuration.md, "Reloading").
#pragma once

#include <nclink/adapter_config.hpp>

#include <string>
#include <vector>

namespace nclink::adapter_detail {

std::vector<std::string> adapter_config_changes(const AdapterConfig& a, const AdapterConfig& b);

}  // namespace nclink::adapter_detail
