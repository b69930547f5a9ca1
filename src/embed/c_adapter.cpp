// nclink.h: creating, starting, stopping and destroying an adapter whose
// driver is a C descriptor (driver_plugin.h) handed over by the firmware.
#include "embed/c_boundary.hpp"
#include "embed/c_handles.hpp"

#include "driver/plugin_drivers.hpp"

#include <nclink/adapter_config.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

namespace nclink::embed {
namespace {

constexpr std::size_t kOptionsV1 = offsetof(nclink_adapter_options, log_context) + sizeof(void*);

/// The configuration from exactly one of config_json and config_path.
Result<AdapterConfig> read_config(const nclink_adapter_options& o) {
    if ((o.config_json == nullptr) == (o.config_path == nullptr))
        return make_error(ErrorCode::parameter_missing,
                          o.config_json ? "give config_json or config_path, not both" : "give config_json or config_path");
    if (o.config_path) return load_adapter_config(o.config_path);
    const Json json = Json::parse(o.config_json, nullptr, false);
    if (json.is_discarded()) return make_error(ErrorCode::syntax_error, "config_json is not JSON text");
    return adapter_config_from_json(json);
}

Logger make_logger(const nclink_adapter_options& o, LogLevel level) {
    if (o.log == nullptr) return Logger();
    auto log = o.log;
    void* context = o.log_context;
    return Logger(
        [log, context](LogLevel l, std::string_view message) {
            const std::string line(message);  // NUL-terminated for C
            log(context, static_cast<int>(l), line.c_str());
        },
        level);
}

int create(const nclink_adapter_options* options, nclink_adapter** out, nclink_error* error) {
    if (out == nullptr) return report(error, to_int(ErrorCode::parameter_missing), "adapter (the out pointer) is NULL");
    *out = nullptr;
    if (options == nullptr) return report(error, to_int(ErrorCode::parameter_missing), "options is NULL");
    if (int code = check_struct_size(error, "nclink_adapter_options", options->struct_size, kOptionsV1)) return code;
    // Fields past the caller's struct_size keep their defaults (nclink.h, "Growth").
    nclink_adapter_options o = NCLINK_ADAPTER_OPTIONS_INIT;
    std::memcpy(&o, options, std::min<std::size_t>(options->struct_size, sizeof o));

    const nclink_driver_descriptor* d = o.driver;
    if (d == nullptr) return report(error, to_int(ErrorCode::parameter_missing), "options.driver is NULL");
    if (d->abi_version != NCLINK_DRIVER_ABI_VERSION)
        return report(error, to_int(ErrorCode::value_type),
                      fmt::format("options.driver: driver ABI version {} is not supported (this nclink loads version {})",
                                  d->abi_version, NCLINK_DRIVER_ABI_VERSION));
    if (int code = check_struct_size(error, "nclink_driver_descriptor", d->struct_size,
                                     offsetof(nclink_driver_descriptor, read) + sizeof d->read))
        return code;

    auto config = read_config(o);
    if (!config) return report(error, config.error());
    if (!config->driver_plugin.empty())
        return report(error, to_int(ErrorCode::keys_of_arguments),
                      "configuration: driver.plugin is not used here: the driver is options.driver");
    if (o.model_path) config->model_path = o.model_path;
    if (config->model_path.empty())
        return report(error, to_int(ErrorCode::parameter_missing),
                      "no model: give options.model_path or \"model\" in the configuration");

    Logger logger = make_logger(o, config->log_level);
    const std::string name = d->name ? d->name : "driver";
    auto driver = driver_detail::make_plugin_driver_v2(nullptr, *d, "C driver " + name, config->driver_config, logger);
    if (!driver) return report(error, driver.error());
    auto handle = std::make_unique<nclink_adapter>();
    handle->adapter = std::make_unique<Adapter>(std::move(config).value(), std::move(driver).value(), std::move(logger));
    *out = handle.release();
    return report_ok(error);
}

}  // namespace
}  // namespace nclink::embed

using nclink::embed::guarded;
using nclink::embed::report;

extern "C" {

int nclink_adapter_create(const nclink_adapter_options* options, nclink_adapter** adapter, nclink_error* error) {
    return guarded(error, [&] { return nclink::embed::create(options, adapter, error); });
}

int nclink_adapter_start(nclink_adapter* adapter, nclink_error* error) {
    return guarded(error, [&] {
        if (adapter == nullptr) return report(error, nclink::to_int(nclink::ErrorCode::parameter_missing), "adapter is NULL");
        auto started = adapter->adapter->start();
        if (!started) return report(error, started.error());
        return nclink::embed::report_ok(error);
    });
}

int nclink_adapter_stop(nclink_adapter* adapter, uint32_t flush_timeout_ms) {
    return guarded(nullptr, [&] {
        if (adapter == nullptr) return nclink::to_int(nclink::ErrorCode::parameter_missing);
        adapter->adapter->stop(std::chrono::milliseconds(flush_timeout_ms));
        return 0;
    });
}

void nclink_adapter_destroy(nclink_adapter* adapter) {
    (void)guarded(nullptr, [&] {
        delete adapter;  // ~Adapter stops it if it runs; the driver's destroy() follows
        return 0;
    });
}

int nclink_adapter_state(const nclink_adapter* adapter) {
    if (adapter == nullptr) return -1;
    try {
        return static_cast<int>(adapter->adapter->state());  // NCLINK_STATE_* follow AdapterState
    } catch (...) {
        return -1;
    }
}

}  // extern "C"
