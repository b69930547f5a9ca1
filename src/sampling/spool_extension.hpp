// Plugs the sample spool (sample_spool.hpp) into the sampling service: wraps
// the engine's sink, follows the link, reports "spool" statistics.
#pragma once

#include "sampling/sampling_service.hpp"

#include <memory>

namespace nclink::sampling_detail {

/// Wraps `service`'s sink at once (call from the service's constructor).
std::unique_ptr<SamplingExtension> make_spool_extension(feature_detail::FeatureHost& host, SamplingService& service);

}  // namespace nclink::sampling_detail
