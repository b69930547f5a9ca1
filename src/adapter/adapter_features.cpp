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

namespace nclink::adapter_detail {

Result<void> read_feature_sections(core_detail::ConfigReader& top, AdapterConfig& c) {
    if (const Json* section = top.object("sampling")) NCLINK_TRY(sampling_detail::read_sampling_config(*section, c.sampling));
    if (const Json* section = top.object("events")) NCLINK_TRY(events_detail::read_events_config(*section, c.events));
    if (const Json* section = top.object("methods")) NCLINK_TRY(methods_detail::read_methods_config(*section, c.methods));
    return ok_result();
}

void feature_config_changes(const AdapterConfig& a, const AdapterConfig& b, std::vector<std::string>& out) {
    sampling_detail::sampling_config_changes(a.sampling, b.sampling, out);
    events_detail::events_config_changes(a.events, b.events, out);
    methods_detail::methods_config_changes(a.methods, b.methods, out);
}

std::vector<std::unique_ptr<feature_detail::Feature>> make_features(feature_detail::FeatureHost& host, const AdapterConfig& config) {
    std::vector<std::unique_ptr<feature_detail::Feature>> features;
    features.push_back(sampling_detail::make_sampling_service(host, config.sampling));
    features.push_back(methods_detail::make_methods_service(host, config.methods));
    features.push_back(events_detail::make_events_service(host, config.events));
    return features;
}

void feature_drops_from_stats(const Json& features, feature_detail::DropCounts& out) {
    sampling_detail::sampling_drops_from_stats(feature_detail::json_member(features, "sampling"), out);
    events_detail::events_drops_from_stats(feature_detail::json_member(features, "events"), out);
}

void feature_metrics_from_stats(core_detail::PrometheusText& out, const core_detail::MetricLabels& device, const Json& features,
                                const SamplingStats& sampling) {
    sampling_detail::add_sampling_metrics(out, {device, feature_detail::json_member(features, "sampling")}, sampling);
    events_detail::add_events_metrics(out, {device, feature_detail::json_member(features, "events")});
    methods_detail::add_methods_metrics(out, {device, feature_detail::json_member(features, "methods")});
}

Result<void> FeatureSet::start(feature_detail::FeatureHost host, const AdapterConfig& config) {
    host_ = std::make_unique<feature_detail::FeatureHost>(std::move(host));
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

void FeatureSet::on_model(const std::shared_ptr<const feature_detail::ModelState>& state) {
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

void FeatureSet::add_drops(feature_detail::DropCounts& out) const {
    for (const auto& feature : features_) feature->add_drops(out);
}

}  // namespace nclink::adapter_detail
