// What the adapter counts, as AdapterStats and as the JSON of the
// statistics item and `nclink stats` (docs/sampling.md).
#include "adapter/adapter_impl.hpp"

namespace nclink {

AdapterStats Adapter::stats() const {
    AdapterStats s;
    s.requests = impl_->requests;
    s.ignored_retained = impl_->ignored_retained;
    s.ignored_duplicates = impl_->ignored_duplicates;
    s.rejected = impl_->rejected;
    s.driver_timeouts = (impl_->runner ? impl_->runner->timeouts() : 0) + impl_->affine_timeouts;
    s.registered = impl_->registration.registered();
    s.state = state();
    if (impl_->transport) s.transport = impl_->transport->stats();
    for (const auto& service : impl_->features) s.features[std::string(service->name())] = service->stats();
    return s;
}

Json to_json(const AdapterStats& s) {
    const auto& t = s.transport;
    return Json{{"requests", s.requests},
                {"ignored_retained", s.ignored_retained},
                {"ignored_duplicates", s.ignored_duplicates},
                {"rejected", s.rejected},
                {"driver_timeouts", s.driver_timeouts},
                {"registered", s.registered},
                {"state", std::string(to_string(s.state))},
                {"transport", {{"published", t.published}, {"received", t.received}, {"dropped", t.dropped},
                               {"dropped_bytes", t.dropped_bytes}, {"connects", t.connects}, {"buffered", t.buffered},
                               {"buffered_bytes", t.buffered_bytes}, {"in_flight", t.in_flight}}},
                {"features", s.features}};
}

}  // namespace nclink
