// Model changes at run time: Probe/Set (8.2.9, 8.2.10) from an application,
// and Adapter::replace_model/patch_model from the firmware. One path for
// both: validated like a model file, persisted atomically, swapped in,
// announced with Probe/Version (8.2.5.3: "when the adapter changes the model
// file"; 8.2.9.3), and handed to the features (channels re-planned,
// registrations that no longer resolve released) and listeners.
#include "adapter/adapter_impl.hpp"
#include "adapter/request_handlers.hpp"
#include "protocol/driver_failure.hpp"

namespace nclink {

Result<std::string> Adapter::Impl::adopt_model(const std::string& text, std::string_view origin) {
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (!started || stopped || state == AdapterState::initial)
            return make_error(ErrorCode::unavailable, "the adapter is not running");
    }
    std::lock_guard<std::mutex> serial(model_change_mutex);
    LoadResult loaded = parse_model(text);
    const std::string refused = detail::refusal_reasons(loaded, config.strict);
    // Every problem in the reason: the sender fixes all in one round.
    if (!refused.empty()) return make_error(ErrorCode::syntax_error, refused);
    auto built = host.build(loaded, config.device_id, *driver);
    if (!built) return std::move(built).error();
    const std::string new_dev = resolve_dev_uuid(*built.value()->device, config.dev_uuid);
    if (new_dev != dev)
        logger.warn("the new model names the device {}, this adapter keeps answering as {}", new_dev, dev);
    // The driver sees the new model before it is persisted: a driver that
    // refuses it (or is too busy to be asked) leaves the old one in force.
    if (auto bound = detail::ModelHost::bind(*built.value(), *runner); !bound) {
        logger.info("{} refused by the driver's bind(): {}", origin, bound.error().describe());
        return std::move(bound).error();
    }
    // The text as sent: a restart serves (Probe/Query) the very model the application set.
    if (auto persisted = host.persist_model(*built.value()->probe_text); !persisted) {
        rebind_current();  // the driver was bound to the model that is not installed
        return std::move(persisted).error();
    }
    const std::string old_version = host.current() ? host.current()->device->version : std::string();
    host.install(built.value());
    const std::string version = built.value()->device->version;
    logger.info("model replaced by {}: version {} -> {}", origin, old_version, version);
    if (version == old_version)
        logger.warn("the new model keeps version {}: caches that compare versions (8.2.7.3) will not re-probe",
                    version);
    std::vector<ModelListener> to_call;
    {
        std::lock_guard<std::mutex> lock(mutex);
        to_call = listeners;
    }
    for (auto& feature : features) feature->on_model(built.value());
    for (auto& listener : to_call) listener(built.value()->model);
    fire(AdapterEvent::model_changed);  // Probe/Version now, or on reconnection
    return version;
}

ProbeSetResponse Adapter::Impl::probe_set(const ProbeSetRequest& request) {
    auto response = make_reply<ProbeSetResponse>(request, dev);
    const std::string text = request.probe.is_string() ? request.probe.get<std::string>()
                                                       : request.probe.dump(-1, ' ', false, Json::error_handler_t::replace);
    auto adopted = adopt_model(text, "Probe/Set");
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
            const auto failure = detail::driver_failure(e);
            response.status = failure.status;
            response.private_info = failure.private_info;
        }
    }
    return response;
}

Result<std::string> Adapter::replace_model(const std::string& model_json) {
    return impl_->adopt_model(model_json, "Adapter::replace_model");
}

Result<std::string> Adapter::patch_model(const Json& patch) {
    if (!patch.is_array()) return make_error(ErrorCode::value_type, "a JSON Patch is an array of operations");
    const auto current = impl_->host.current();
    if (!current) return make_error(ErrorCode::unavailable, "the adapter is not running");
    Json patched;
    try {
        patched = Json::parse(*current->probe_text).patch(patch);
    } catch (const std::exception& e) {
        return make_error(ErrorCode::keys_of_arguments, std::string("the patch does not apply: ") + e.what());
    }
    return impl_->adopt_model(patched.dump(), "Adapter::patch_model");
}

void Adapter::Impl::rebind_current() {
    const auto current = host.current();
    if (!current) return;
    // A copy of the model in force with fresh handles: snapshots still held
    // elsewhere keep working (the runner re-resolves their refs by id).
    auto again = std::make_shared<detail::ModelState>(*current);
    if (auto bound = detail::ModelHost::bind(*again, *runner); !bound) {
        logger.error("could not bind the model in force again: {}", bound.error().describe());
        return;
    }
    host.install(std::move(again));
}

}  // namespace nclink
