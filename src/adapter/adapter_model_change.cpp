// Model changes at run time (adapter_model_change.hpp): Probe/Set from an
// application, and Adapter::replace_model/patch_model from the firmware. One
// path for both: validated like a model file, persisted atomically, swapped
// in, announced with Probe/Version (8.2.5.3: "when the adapter changes the
// model file"; 8.2.9.3), and handed to the features (channels re-planned,
// registrations that no longer resolve released) and listeners.
#include "adapter/adapter_model_change.hpp"
#include "adapter/request_handlers.hpp"
#include "protocol/driver_failure.hpp"

namespace nclink::adapter_detail {

ModelChange::ModelChange(const AdapterConfig& config, const Logger& logger, std::string dev, ModelHost& host,
                         const Driver& driver, driver_detail::DriverRunner& runner, AdapterLink& link, FeatureSet& features,
                         ModelListeners& listeners, std::function<bool()> running)
    : config_(config),
      logger_(logger),
      dev_(std::move(dev)),
      host_(host),
      driver_(driver),
      runner_(runner),
      link_(link),
      features_(features),
      listeners_(listeners),
      running_(std::move(running)) {}

Result<std::string> ModelChange::adopt(const std::string& text, std::string_view origin) {
    if (!running_()) return make_error(ErrorCode::unavailable, "the adapter is not running");
    std::lock_guard<std::mutex> serial(serial_);
    LoadResult loaded = parse_model(text);
    const std::string refused = refusal_reasons(loaded, config_.strict);
    // Every problem in the reason: the sender fixes all in one round.
    if (!refused.empty()) return make_error(ErrorCode::syntax_error, refused);
    auto built = host_.build(loaded, config_.device_id, driver_);
    if (!built) return std::move(built).error();
    const std::string new_dev = resolve_dev_uuid(*built.value()->device, config_.dev_uuid);
    if (new_dev != dev_) logger_.warn("the new model names the device {}, this adapter keeps answering as {}", new_dev, dev_);
    // The driver sees the new model before it is persisted: a driver that
    // refuses it (or is too busy to be asked) leaves the old one in force.
    if (auto bound = ModelHost::bind(*built.value(), runner_); !bound) {
        logger_.info("{} refused by the driver's bind(): {}", origin, bound.error().describe());
        return std::move(bound).error();
    }
    // The text as sent: a restart serves (Probe/Query) the very model the application set.
    if (auto persisted = host_.persist_model(*built.value()->probe_text); !persisted) {
        rebind_current();  // the driver was bound to the model that is not installed
        return std::move(persisted).error();
    }
    const std::string old_version = host_.current() ? host_.current()->device->version : std::string();
    host_.install(built.value());
    const std::string version = built.value()->device->version;
    logger_.info("model replaced by {}: version {} -> {}", origin, old_version, version);
    if (version == old_version)
        logger_.warn("the new model keeps version {}: caches that compare versions (8.2.7.3) will not re-probe", version);
    const std::vector<ModelListener> to_call = listeners_.snapshot();
    features_.on_model(built.value());
    for (auto& listener : to_call) listener(built.value()->model);
    link_.fire(AdapterEvent::model_changed);  // Probe/Version now, or on reconnection
    return version;
}

ProbeSetResponse ModelChange::probe_set(const ProbeSetRequest& request) {
    auto response = make_reply<ProbeSetResponse>(request, dev_);
    const std::string text = request.probe.is_string() ? request.probe.get<std::string>()
                                                       : request.probe.dump(-1, ' ', false, Json::error_handler_t::replace);
    auto adopted = adopt(text, "Probe/Set");
    if (!adopted) {
        const auto& e = adopted.error();
        if (e.code == ErrorCode::syntax_error) {
            // `reason` is the table-19 string (table 20); every problem goes in
            // privateInfo.problems, so the sender fixes all in one round
            // (docs/wire.md, "Probe/Set").
            response.status = ResponseStatus::failure(ErrorCode::syntax_error);
            response.private_info = Json{{"problems", e.message}};
        } else {
            // The driver's refusal (bind()) or a persistence failure: the
            // table-19 status, the words in privateInfo (docs/wire.md,
            // "Vendor errors").
            const auto failure = protocol_detail::driver_failure(e);
            response.status = failure.status;
            response.private_info = failure.private_info;
        }
    }
    return response;
}

void ModelChange::rebind_current() {
    const auto current = host_.current();
    if (!current) return;
    // A copy of the model in force with fresh handles: snapshots still held
    // elsewhere keep working (the runner re-resolves their refs by id).
    auto again = std::make_shared<feature_detail::ModelState>(*current);
    if (auto bound = ModelHost::bind(*again, runner_); !bound) {
        logger_.error("could not bind the model in force again: {}", bound.error().describe());
        return;
    }
    host_.install(std::move(again));
}

}  // namespace nclink::adapter_detail
