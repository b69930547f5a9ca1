#include "adapter/adapter_features.hpp"

#include "events/events_config.hpp"
#include "events/events_metrics.hpp"
#include "events/events_service.hpp"
#include "methods/methods_config.hpp"
#include "methods/methods_metrics.hpp"
#include "methods/methods_service.hpp"
#include "sampling/sampling_config.hpp"
#include "sampling/sampling_metrics.hpp"
#include "sampling/sampling_service.hpp"

#include <fmt/format.h>

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
    sampling_drops_from_stats(json_member(features, "sampling"), out);
    events_drops_from_stats(json_member(features, "events"), out);
}

void feature_metrics_from_stats(PrometheusText& out, const MetricLabels& device, const Json& features,
                                const SamplingStats& sampling) {
    add_sampling_metrics(out, {device, json_member(features, "sampling")}, sampling);
    add_events_metrics(out, {device, json_member(features, "events")});
    add_methods_metrics(out, {device, json_member(features, "methods")});
}

Result<void> FeatureSet::start(FeatureHost host, const AdapterConfig& config) {
    host_ = std::make_unique<FeatureHost>(std::move(host));
    features_ = make_features(*host_, config);
    for (std::size_t i = 0; i < features_.size(); ++i) {
        if (auto begun = features_[i]->start(); !begun) {
            for (std::size_t j = i; j-- > 0;) features_[j]->stop();
            const std::string name(features_[i]->name());
            features_.clear();
            return make_error(begun.error().code, fmt::format("{} failed to start: {}", name, begun.error().message));
        }
    }
    ready_.store(true, std::memory_order_release);  // notify_value may reach them now
    return ok_result();
}

void FeatureSet::stop() {
    for (auto it = features_.rbegin(); it != features_.rend(); ++it) (*it)->stop();
}

bool FeatureSet::handle(const ParsedTopic& topic, const std::string& payload) {
    for (auto& feature : features_) {
        if (feature->handles(topic.kind)) {
            feature->handle(topic, payload);
            return true;
        }
    }
    return false;
}

void FeatureSet::on_link(LinkState link) {
    for (auto& feature : features_) feature->on_link(link);
}

void FeatureSet::on_model(const std::shared_ptr<const ModelState>& state) {
    for (auto& feature : features_) feature->on_model(state);
}

void FeatureSet::on_application_gone(const std::string& ex_cid) {
    for (auto& feature : features_) feature->on_application_gone(ex_cid);
}

void FeatureSet::on_value(const std::string& id, const Json& value) {
    if (!ready()) return;
    for (auto& feature : features_) feature->on_value(id, value);
}

void FeatureSet::add_stats(Json& out) const {
    for (const auto& feature : features_) out[std::string(feature->name())] = feature->stats();
}

void FeatureSet::add_drops(DropCounts& out) const {
    for (const auto& feature : features_) feature->add_drops(out);
}

}  // namespace nclink::detail
