// The methods feature of the adapter (8.2.22-8.2.26): Method/Call and
// Method/Control. See docs/methods.md.
#pragma once

#include "adapter/adapter_service.hpp"

#include <memory>

namespace nclink::detail {

/// Runs accepted calls on method threads of their own (up to
/// MethodsConfig::max_running), beside the driver runner's read()/write()
/// worker: a long method never holds up Query, Set or sampling.
std::unique_ptr<AdapterService> make_methods_service(ServiceHost& host);

}  // namespace nclink::detail
