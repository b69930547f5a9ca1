#include "sampling/dynamic_channels.hpp"

#include <nclink/topics.hpp>

namespace nclink::sampling_detail {
namespace {

Json refuse(SampleRegisterResponse response, ErrorCode code) {
    response.status = ResponseStatus::failure(code);
    return to_json(response);
}

Json refuse(SampleUnregisterResponse response, ErrorCode code) {
    response.status = ResponseStatus::failure(code);
    return to_json(response);
}

/// QoS of the channel's Sample DTUs: privateInfo {"qos": 0|1} of the request
/// (an nclink extension), else the adapter's sampling.qos (docs/delivery.md).
int requested_qos(const std::optional<Json>& private_info, int fallback) {
    if (!private_info || !private_info->is_object()) return fallback;
    auto it = private_info->find("qos");
    if (it == private_info->end() || !it->is_number_integer()) return fallback;
    return it->get<int>() >= 1 ? 1 : 0;
}

}  // namespace

DynamicChannels::DynamicChannels(feature_detail::FeatureHost& host, SamplingEngine& engine, const SamplingConfig& config)
    : host_(host), engine_(engine), config_(config) {}

bool DynamicChannels::handles(TopicKind kind) const {
    return kind == TopicKind::sample_register_request || kind == TopicKind::sample_unregister_request;
}

void DynamicChannels::handle(const ParsedTopic& topic, const std::string& payload) {
    Json reply;
    if (topic.kind == TopicKind::sample_register_request) {
        auto request = decode<SampleRegisterRequest>(payload);
        reply = request ? register_channel(topic, request.value())
                        : *make_error_reply(topic.kind, peek_message_id(payload), host_.dev, request.error());
    } else {
        auto request = decode<SampleUnregisterRequest>(payload);
        reply = request ? unregister_channel(topic, request.value())
                        : *make_error_reply(topic.kind, peek_message_id(payload), host_.dev, request.error());
    }
    if (reply.value("code", "") != "OK") {
        std::lock_guard<std::mutex> lock(mutex_);
        ++refused_;
    }
    host_.respond(topic, reply);
}

Json DynamicChannels::register_channel(const ParsedTopic& topic, const SampleRegisterRequest& request) {
    auto response = make_reply<SampleRegisterResponse>(request, host_.dev);
    if (!topic.ex || topic.ex->empty()) {
        host_.logger.info("Register/Sample without an ex_cid in the topic refused (414)");
        return refuse(response, ErrorCode::unsupported_terminal_id);
    }
    if (request.ids.empty()) return refuse(response, ErrorCode::parameter_missing);
    const auto state = host_.model.current();
    if (!state) return refuse(response, ErrorCode::unavailable);
    ChannelSpec spec;
    for (const auto& id : request.ids) {
        const DataObject* item = state->item(id);
        if (!item || item->config) {
            host_.logger.info("Register/Sample from {} refused: {} is not a data item of {} (401)", *topic.ex, id, host_.dev);
            return refuse(response, ErrorCode::node_not_exists);
        }
        spec.points.push_back(PointRef{item->id, item->kind});
    }
    if (!(request.sample_interval > 0) || !(request.upload_interval > 0) || request.upload_interval < request.sample_interval) {
        host_.logger.info("Register/Sample from {} refused: sampleInterval {} / uploadInterval {} (411)", *topic.ex,
                          request.sample_interval, request.upload_interval);
        return refuse(response, ErrorCode::attribute_error);
    }
    spec.sample_interval_ms = request.sample_interval;
    spec.upload_interval_ms = request.upload_interval;
    spec.owner_ex = *topic.ex;
    spec.qos = requested_qos(request.private_info, config_.qos);

    std::lock_guard<std::mutex> lock(mutex_);
    if (owners_.size() >= config_.max_dynamic_channels) {
        host_.logger.info("Register/Sample from {} refused: {} dynamic channel(s) in use (415)", *topic.ex, owners_.size());
        return refuse(response, ErrorCode::insufficient_dynamic_sampling);
    }
    do {
        spec.id = "dyn" + std::to_string(next_id_++);
    } while (engine_.has_channel(spec.id));
    spec.topic = topics::dynamic_sample(host_.dev, *topic.ex, spec.id);
    const std::string id = spec.id;
    if (auto added = engine_.add_channel(std::move(spec)); !added) {
        host_.logger.warn("Register/Sample from {}: the engine refused channel {}: {}", *topic.ex, id, added.error().describe());
        return refuse(response, added.error().code);
    }
    owners_[id] = *topic.ex;
    items_[id] = request.ids;
    ++registered_;
    host_.logger.info("dynamic channel {} for {}: {} item(s), sample {} ms, upload {} ms", id, *topic.ex, request.ids.size(),
                      request.sample_interval, request.upload_interval);
    response.id = id;
    return to_json(response);
}

Json DynamicChannels::unregister_channel(const ParsedTopic& topic, const SampleUnregisterRequest& request) {
    auto response = make_reply<SampleUnregisterResponse>(request, host_.dev);
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = owners_.find(request.id);
    if (it == owners_.end()) {
        // A model channel exists but is not the application's to remove.
        return refuse(response, engine_.has_channel(request.id) ? ErrorCode::permission_denied : ErrorCode::node_not_exists);
    }
    if (!topic.ex || *topic.ex != it->second) {
        host_.logger.info("Unregister/Sample of {} by {} refused: it belongs to {} (301)", request.id,
                          topic.ex.value_or("(no ex_cid)"), it->second);
        return refuse(response, ErrorCode::permission_denied);
    }
    engine_.remove_channel(request.id);
    items_.erase(request.id);
    owners_.erase(it);
    ++unregistered_;
    host_.logger.info("dynamic channel {} of {} unregistered", request.id, *topic.ex);
    return to_json(response);
}

void DynamicChannels::on_model(const std::shared_ptr<const feature_detail::ModelState>& state) {
    if (!state) return;
    std::vector<std::pair<std::string, std::string>> released;  // channel, owner
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto it = items_.begin(); it != items_.end();) {
            bool resolves = true;
            for (const auto& id : it->second) {
                const DataObject* item = state->item(id);
                if (!item || item->config) resolves = false;
            }
            if (resolves) {
                ++it;
                continue;
            }
            engine_.remove_channel(it->first);
            released.emplace_back(it->first, owners_[it->first]);
            owners_.erase(it->first);
            ++released_;
            it = items_.erase(it);
        }
    }
    for (const auto& [channel, owner] : released) {
        host_.logger.info("dynamic channel {} of {} released: an item of it is gone from the new model (401)", channel, owner);
        SampleRegisterResponse response;
        response.guid = host_.dev;
        response.id = channel;
        response.status = ResponseStatus::failure(ErrorCode::node_not_exists);
        ParsedTopic request;
        request.kind = TopicKind::sample_register_request;
        request.dev = host_.dev;
        request.ex = owner;
        host_.respond(request, to_json(response));
    }
}

void DynamicChannels::on_application_gone(const std::string& ex_cid) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = owners_.begin(); it != owners_.end();) {
        if (it->second == ex_cid) {
            engine_.remove_channel(it->first);
            host_.logger.info("dynamic channel {} released: {} is gone", it->first, ex_cid);
            ++released_;
            items_.erase(it->first);
            it = owners_.erase(it);
        } else {
            ++it;
        }
    }
}

std::vector<std::string> DynamicChannels::channels_of(const std::string& ex_cid) const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> out;
    for (const auto& [id, owner] : owners_)
        if (owner == ex_cid) out.push_back(id);
    return out;
}

Json DynamicChannels::stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    Json owners = Json::object();
    for (const auto& [id, owner] : owners_) owners[id] = owner;
    return Json{{"channels", owners_.size()},
                {"max_channels", config_.max_dynamic_channels},
                {"registered", registered_},
                {"unregistered", unregistered_},
                {"released", released_},
                {"refused", refused_},
                {"owners", owners}};
}

std::unique_ptr<SamplingExtension> make_dynamic_channels(feature_detail::FeatureHost& host, SamplingEngine& engine,
                                                         const SamplingConfig& config) {
    return std::make_unique<DynamicChannels>(host, engine, config);
}

}  // namespace nclink::sampling_detail
