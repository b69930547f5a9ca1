#include "adapter/adapter_features.hpp"

#include "events/events_config.hpp"
#include "events/events_service.hpp"
#include "methods/methods_config.hpp"
#include "methods/methods_service.hpp"
#include "sampling/sampling_config.hpp"
#include "sampling/sampling_service.hpp"

namespace nclink::detail {

Result<void> read_feature_sections(ConfigReader& top, AdapterConfig& c) {
    if (const Json* section = top.object("sampling")) NCLINK_TRY(read_sampling_config(*section, c.sampling));
    if (const Json* section = top.object("events")) NCLINK_TRY(read_events_config(*section, c.events));
    if (const Json* section = top.object("methods")) NCLINK_TRY(read_methods_config(*section, c.methods));
    return ok_result();
}

void feature_config_changes(const AdapterConfig& a, const AdapterConfig& b, std::vector<std::string>& out) {
    sampling_config_changes(a.sampling, b.sampling, out);
    events_config_changes(a.events, b.events, out);
    methods_config_changes(a.methods, b.methods, out);
}

std::vector<std::unique_ptr<Feature>> make_features(FeatureHost& host, const AdapterConfig& config) {
    std::vector<std::unique_ptr<Feature>> features;
    features.push_back(make_sampling_service(host, config.sampling));
    features.push_back(make_methods_service(host, config.methods));
    features.push_back(make_events_service(host, config.events));
    return features;
}

void feature_drops_from_stats(const Json& features, DropCounts& out) {
    static const Json none;
    const auto of = [&](const char* name) -> const Json& {
        if (!features.is_object()) return none;
        const auto it = features.find(name);
        return it == features.end() ? none : *it;
    };
    sampling_drops_from_stats(of("sampling"), out);
    events_drops_from_stats(of("events"), out);
}

}  // namespace nclink::detail
