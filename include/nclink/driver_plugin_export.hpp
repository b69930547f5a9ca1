// Export a C++ nclink::Driver as a plugin (driver_plugin.h) with one line:
//
//     NCLINK_EXPORT_DRIVER(MyDriver)
//
// in one .cpp of the plugin's shared library. MyDriver must be default
// constructible; its open() receives the configuration given to the loader.
// Header-only on purpose: a plugin need not link libnclink (nlohmann-json
// headers and libfmt, which Logger formats with), so the host and the plugin
// never carry two copies.
#pragma once

#include <nclink/driver.hpp>
#include <nclink/driver_plugin.h>

#include <string>

namespace nclink::plugin_export {

inline void put_text(const nclink_text_output* out, const std::string& text) {
    if (out && out->put) out->put(out->context, text.data(), text.size());
}

inline Logger host_logger(const nclink_host* host) {
    if (!host || !host->log) return Logger();
    nclink_host copy = *host;
    return Logger([copy](LogLevel level, std::string_view message) {
        copy.log(copy.context, static_cast<int>(level), std::string(message).c_str());
    }, LogLevel::trace);
}

class ControlBridge final : public MethodControl {
public:
    explicit ControlBridge(const nclink_method_control* c) : c_(c) {}
    void progress(double percent) override {
        if (c_ && c_->progress) c_->progress(c_->context, percent);
    }
    bool cancelled() const override { return c_ && c_->cancelled && c_->cancelled(c_->context) != 0; }
    bool checkpoint() override { return !c_ || !c_->checkpoint || c_->checkpoint(c_->context) != 0; }

private:
    const nclink_method_control* c_;
};

inline std::string error_text(const Error& e) {
    return e.message.empty() ? std::to_string(static_cast<int>(e.code)) : e.message;
}

template <class DriverType>
const nclink_driver_descriptor* descriptor(std::uint32_t flags) {
    static const DriverInfo info = DriverType().info();
    static const nclink_driver_descriptor d = {
        NCLINK_DRIVER_ABI_VERSION,
        info.name.c_str(),
        info.version.c_str(),
        flags | (info.concurrent ? NCLINK_DRIVER_CONCURRENT : 0u),
        // create
        [](const char* config_json, const nclink_host* host, const nclink_text_output* error) -> void* {
            try {
                auto driver = std::make_unique<DriverType>();
                DriverContext context;
                context.config = Json::parse(config_json ? config_json : "null", nullptr, false);
                if (context.config.is_discarded()) {
                    put_text(error, "configuration is not valid JSON");
                    return nullptr;
                }
                context.logger = host_logger(host);
                auto opened = driver->open(context);
                if (!opened.ok()) {
                    put_text(error, error_text(opened.error()));
                    return nullptr;
                }
                return driver.release();
            } catch (const std::exception& e) {
                put_text(error, e.what());
                return nullptr;
            }
        },
        // destroy
        [](void* instance) {
            auto* driver = static_cast<DriverType*>(instance);
            driver->close();
            delete driver;
        },
        // read
        [](void* instance, const char* const* ids, const int* kinds, size_t count, const nclink_read_output* out) {
            std::vector<PointRef> points(count);
            for (size_t i = 0; i < count; ++i) {
                points[i].id = ids[i];
                points[i].kind = kinds[i] == NCLINK_KIND_LIST   ? DataKind::list
                                 : kinds[i] == NCLINK_KIND_DICT ? DataKind::dict
                                                                : DataKind::single;
            }
            std::vector<Result<Json>> results(count, Result<Json>(make_error(ErrorCode::unavailable)));
            static_cast<DriverType*>(instance)->read(points, results);
            for (size_t i = 0; i < count; ++i) {
                if (results[i].ok()) {
                    const std::string text = results[i].value().dump(-1, ' ', false, Json::error_handler_t::replace);
                    out->value(out->context, i, text.data(), text.size());
                } else {
                    out->error(out->context, i, static_cast<int>(results[i].error().code),
                               results[i].error().message.c_str());
                }
            }
        },
        // write
        [](void* instance, const char* id, int kind, const char* params_json, const char* new_value_json,
           const nclink_text_output* detail) -> int {
            WriteRequest request;
            request.id = id;
            request.kind = kind == NCLINK_KIND_LIST ? DataKind::list : kind == NCLINK_KIND_DICT ? DataKind::dict : DataKind::single;
            request.params = Json::parse(params_json ? params_json : "null", nullptr, false);
            request.new_value = Json::parse(new_value_json ? new_value_json : "null", nullptr, false);
            if (request.params.is_discarded() || request.new_value.is_discarded()) return static_cast<int>(ErrorCode::syntax_error);
            auto r = static_cast<DriverType*>(instance)->write(request);
            if (r.ok()) return 0;
            put_text(detail, r.error().message);
            return static_cast<int>(r.error().code);
        },
        // call_method
        [](void* instance, const char* method_id, const char* args_json, const nclink_method_control* control,
           const nclink_text_output* result) -> int {
            const Json args = Json::parse(args_json ? args_json : "null", nullptr, false);
            if (args.is_discarded()) return static_cast<int>(ErrorCode::syntax_error);
            ControlBridge bridge(control);
            auto r = static_cast<DriverType*>(instance)->call_method(method_id, args, bridge);
            if (!r.ok()) {
                put_text(result, r.error().message);
                return static_cast<int>(r.error().code);
            }
            put_text(result, r.value().dump(-1, ' ', false, Json::error_handler_t::replace));
            return 0;
        },
        // claims
        [](void* instance, const char* id) -> int {
            return static_cast<DriverType*>(instance)->claims(id ? id : "") ? 1 : 0;
        },
    };
    return &d;
}

}  // namespace nclink::plugin_export

#define NCLINK_EXPORT_DRIVER(DriverType)                                                            \
    extern "C" __attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { \
        return ::nclink::plugin_export::descriptor<DriverType>(0u);                                   \
    }
