// The methods feature of the adapter (8.2.22-8.2.26): Method/Call and
// Method/Control. See docs/methods.md.
#pragma once

#include "feature/feature.hpp"

#include <memory>

namespace nclink::detail {

/// Runs accepted calls on method threads of their own (up to
/// MethodsConfig::max_running), beside the driver runner's read()/write()
/// worker: a long method never holds up Query, Set or sampling.
std::unique_ptr<Feature> make_methods_service(FeatureHost& host);

}  // namespace nclink::detail
