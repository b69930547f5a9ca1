// The events feature of the adapter (8.2.27-8.2.31): answers Register/Event
// and Unregister/Event, watches the registered items and publishes Event
// DTUs on Event/{dev}/{ex} (QoS 1, not retained).
//
// How values are watched (docs/events.md):
// - an item some running sample channel reads: from the sample stream
//   (SampleTap), every sampled row, at the channel's sample interval;
// - otherwise by polling: every EventsConfig::poll_interval one read of all
//   such items (driver items in one driver call with the driver deadline,
//   SDK-held items from the value store); poll_interval 0 turns polling off;
// - and whenever the driver pushes a value (Adapter::notify_value).
// At registration the current value is read once (from the driver or the
// store) and evaluated right after the response is published.
//
// Threads: requests on the adapter's request workers; ONE events thread
// evaluates every value and publishes every Event DTU (so a registration's
// events go out in order, after its response); the sample stream and
// notify_value only queue values for it. Time comes from the host's clock.
#pragma once

#include "feature/feature.hpp"

#include <nclink/feature_config.hpp>

#include <memory>

namespace nclink::events_detail {

class EventsService;

/// The service; `host` outlives it. `config`: the "events" section of the
/// configuration (this feature's own).
std::unique_ptr<feature_detail::Feature> make_events_service(feature_detail::FeatureHost& host, const EventsConfig& config);

/// The causes the service's add_drops adds, read back from its stats() JSON
/// (a statistics snapshot's "events"; null when absent: all 0).
void events_drops_from_stats(const Json& stats, feature_detail::DropCounts& out);

}  // namespace nclink::events_detail
