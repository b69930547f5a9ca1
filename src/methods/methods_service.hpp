// The methods feature of the adapter (8.2.22-8.2.26): Method/Call and
// Method/Control. See docs/methods.md.
#pragma once

#include "feature/feature.hpp"

#include <nclink/feature_config.hpp>

#include <memory>

namespace nclink::methods_detail {

/// Runs accepted calls on method threads of their own (up to
/// MethodsConfig::max_running), beside the driver runner's read()/write()
/// worker: a long method never holds up Query, Set or sampling.
/// `config`: the "methods" section of the configuration (this feature's own).
std::unique_ptr<feature_detail::Feature> make_methods_service(feature_detail::FeatureHost& host, const MethodsConfig& config);

}  // namespace nclink::methods_detail
