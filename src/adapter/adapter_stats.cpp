// What the adapter counts, as AdapterStats and as the JSON of the
// statistics item and `nclink stats` (docs/sampling.md).
#include "adapter/adapter_impl.hpp"
#include "adapter/adapter_features.hpp"

namespace nclink {

AdapterStats Adapter::stats() const {
    AdapterStats s;
    const bool composed = impl_->composed.load(std::memory_order_acquire);
    if (composed) {
        const auto c = impl_->requests->counts();
        s.requests = c.requests;
        s.ignored_retained = c.ignored_retained;
        s.ignored_duplicates = c.ignored_duplicates;
        s.rejected = c.rejected;
        s.driver_timeouts = c.affine_timeouts;
        s.shed = c.shed;
        s.oversized = c.oversized;
        s.pending_requests = c.pending;
        s.applications_released = impl_->applications->released();
        s.registered = impl_->link->registered();
    }
    if (impl_->runner) {
        s.driver_timeouts += impl_->runner->timeouts();
        s.machine_link = impl_->runner->link();
    }
    s.state = state();
    if (impl_->transport) s.transport = impl_->transport->stats();
    impl_->features.add_stats(s.features);
    s.values_refused = impl_->value_guard->refused();
    s.values_refused_items = impl_->value_guard->refused_items();
    return s;
}

namespace {

// The same counts read from a statistics snapshot (its features' JSON).
feature_detail::DropCounts feature_drops(const AdapterStats& s) {
    feature_detail::DropCounts d;
    adapter_detail::feature_drops_from_stats(s.features, d);
    return d;
}

}  // namespace

namespace adapter_detail {

// The adapter's own causes of the "drops" object, beside the features'.
void add_adapter_drops(feature_detail::DropCounts& out, std::uint64_t offline_buffer_full, std::uint64_t requests_shed) {
    out.add("offline_buffer_full", offline_buffer_full);
    // Requests beyond max_pending_requests: dropped unanswered (the
    // requester's timeout, 203, is its answer).
    out.add("requests_shed", requests_shed);
}

// Every place a DTU or a value can be lost, by cause (docs/delivery.md,
// "Counted drops"). Each is also logged, once per burst, where it happens.
Json drops_by_cause(const feature_detail::DropCounts& features, std::uint64_t offline_buffer_full, std::uint64_t requests_shed) {
    feature_detail::DropCounts all;
    add_adapter_drops(all, offline_buffer_full, requests_shed);
    for (const auto& [cause, count] : features.causes()) all.add(cause, count);  // each feature's own
    Json out = Json::object();
    for (const auto& [cause, count] : all.causes()) out[cause] = count;
    return out;
}

}  // namespace adapter_detail

// Straight from the counters: the housekeeping's once-a-second look, which
// building the whole statistics made a quarter of a 1,000-machine gateway's
// CPU (perf, docs/performance.md "Fleet").
void Adapter::Impl::add_drops_now(feature_detail::DropCounts& out) const {
    adapter_detail::add_adapter_drops(out, transport->stats().dropped, requests->shed());
    features.add_drops(out);
}

Json to_json(const AdapterStats& s) {
    const auto& t = s.transport;
    return Json{{"requests", s.requests},
                {"applications_released", s.applications_released},
                {"drops", adapter_detail::drops_by_cause(feature_drops(s), s.transport.dropped, s.shed)},
                {"ignored_retained", s.ignored_retained},
                {"ignored_duplicates", s.ignored_duplicates},
                {"rejected", s.rejected},
                {"driver_timeouts", s.driver_timeouts},
                {"machine_link", {{"state", std::string(to_string(s.machine_link.state))}, {"reason", s.machine_link.reason}}},
                {"shed", s.shed},
                {"oversized", s.oversized},
                {"pending_requests", s.pending_requests},
                {"registered", s.registered},
                {"state", std::string(to_string(s.state))},
                {"transport",
                 {{"published", t.published},
                  {"received", t.received},
                  {"dropped", t.dropped},
                  {"dropped_bytes", t.dropped_bytes},
                  {"connects", t.connects},
                  {"buffered", t.buffered},
                  {"buffered_bytes", t.buffered_bytes},
                  {"in_flight", t.in_flight},
                  {"sessions_lost", t.sessions_lost},
                  {"stalled_links", t.stalled_links},
                  {"failovers", t.failovers},
                  {"broker", t.broker}}},
                {"values", {{"refused", s.values_refused}, {"refused_items", s.values_refused_items}}},
                {"features", s.features}};
}

}  // namespace nclink
