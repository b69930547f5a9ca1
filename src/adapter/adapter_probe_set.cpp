// Probe/Set (8.2.9, 8.2.10): a new model from an application, validated like
// a model file, persisted atomically, swapped in, announced with
// Probe/Version, and handed to the features and listeners.
#include "adapter/adapter_impl.hpp"
#include "adapter/request_handlers.hpp"

namespace nclink {

ProbeSetResponse Adapter::Impl::probe_set(const ProbeSetRequest& request) {
    auto response = make_reply<ProbeSetResponse>(request, dev);
    const std::string text = request.probe.is_string() ? request.probe.get<std::string>()
                                                       : request.probe.dump(-1, ' ', false, Json::error_handler_t::replace);
    LoadResult loaded = parse_model(text);
    const std::string refused = detail::refusal_reasons(loaded, config.strict);
    if (!refused.empty()) {
        // Every problem in `reason` (docs/wire.md: the sender fixes all in one round).
        response.status = ResponseStatus::failure(refused, to_int(ErrorCode::syntax_error));
        return response;
    }
    auto built = host.build(loaded, config.device_id, *driver);
    if (!built) {
        response.status = ResponseStatus(built.error());
        return response;
    }
    const std::string new_dev = resolve_dev_uuid(*built.value()->device, config.dev_uuid);
    if (new_dev != dev)
        logger.warn("the new model names the device {}, this adapter keeps answering as {}", new_dev, dev);
    if (auto persisted = host.persist_model(serialize_model(*built.value()->model)); !persisted) {
        response.status = ResponseStatus(persisted.error());
        return response;
    }
    host.install(built.value());
    logger.info("model replaced by Probe/Set: version {}", built.value()->device->version);
    std::vector<ModelListener> to_call;
    {
        std::lock_guard<std::mutex> lock(mutex);
        to_call = listeners;
    }
    for (auto& feature : features) feature->on_model(built.value());
    for (auto& listener : to_call) listener(built.value()->model);
    publish_version();
    return response;
}

}  // namespace nclink
