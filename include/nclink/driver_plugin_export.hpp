// Export a C++ nclink::Driver as a plugin (driver_plugin.h, ABI version 2)
// with one line:
//
//     NCLINK_EXPORT_DRIVER(MyDriver)
//
// in one .cpp of the plugin's shared library. MyDriver must be default
// constructible; its open() receives the configuration given to the loader.
// Its bind() handles, typed read_samples(), vendor error codes/reasons and
// link() all cross the boundary.
// Header-only on purpose: a plugin need not link libnclink (nlohmann-json
// headers and libfmt, which Logger formats with), so the host and the plugin
// never carry two copies.
#pragma once

#include <nclink/driver.hpp>
#include <nclink/driver_plugin.h>

#include <cstdint>
#include <string>
#include <vector>

namespace nclink::plugin_export {

inline void put_text(const nclink_text_output* out, const std::string& text) {
    if (out && out->put && !text.empty()) out->put(out->context, text.data(), text.size());
}

inline Logger host_logger(const nclink_host* host) {
    if (!host || !host->log) return Logger();
    nclink_host copy = *host;
    return Logger(
        [copy](LogLevel level, std::string_view message) {
            copy.log(copy.context, static_cast<int>(level), std::string(message).c_str());
        },
        LogLevel::trace);
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

inline DataKind kind_from_c(int kind) {
    return kind == NCLINK_KIND_LIST ? DataKind::list : kind == NCLINK_KIND_DICT ? DataKind::dict : DataKind::single;
}

inline Json parse_or_null(const char* text) {
    Json value = Json::parse(text ? text : "null", nullptr, false);
    return value.is_discarded() ? Json(nullptr) : value;
}

// One read answer through the typed functions: no JSON text for simple values.
inline void put_value(const nclink_read_output* out, size_t i, const Json& value) {
    switch (value.type()) {
        case Json::value_t::null: out->null_value(out->context, i); break;
        case Json::value_t::boolean: out->boolean(out->context, i, value.get<bool>() ? 1 : 0); break;
        case Json::value_t::number_integer: out->int64(out->context, i, value.get<std::int64_t>()); break;
        case Json::value_t::number_unsigned: out->uint64(out->context, i, value.get<std::uint64_t>()); break;
        case Json::value_t::number_float: out->float64(out->context, i, value.get<double>()); break;
        case Json::value_t::string: {
            const auto& text = value.get_ref<const std::string&>();
            out->text(out->context, i, text.data(), text.size());
            break;
        }
        default: {
            const std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
            out->json(out->context, i, text.data(), text.size());
        }
    }
}

inline void put_sample(const nclink_read_output* out, size_t i, const SampleValue& value) {
    switch (value.kind()) {
        case SampleValue::Kind::boolean: out->boolean(out->context, i, value.as_bool() ? 1 : 0); break;
        case SampleValue::Kind::int64: out->int64(out->context, i, value.as_int64()); break;
        case SampleValue::Kind::uint64: out->uint64(out->context, i, value.as_uint64()); break;
        case SampleValue::Kind::float64: out->float64(out->context, i, value.as_double()); break;
        case SampleValue::Kind::text: out->text(out->context, i, value.as_text().data(), value.as_text().size()); break;
        case SampleValue::Kind::json: out->json(out->context, i, value.as_text().data(), value.as_text().size()); break;
        default: out->null_value(out->context, i);
    }
}

inline int put_error(const nclink_text_output* reason, const Error& e) {
    put_text(reason, e.message);
    const int code = static_cast<int>(e.code);
    return code == 0 ? NCLINK_E_UNAVAILABLE : code;
}

template <class DriverType>
const nclink_driver_descriptor* descriptor(std::uint32_t flags) {
    static const DriverInfo info = DriverType().info();
    static const nclink_driver_descriptor d = {
        NCLINK_DRIVER_ABI_VERSION,
        sizeof(nclink_driver_descriptor),
        info.name.c_str(),
        info.version.c_str(),
        flags | (info.concurrent ? NCLINK_DRIVER_CONCURRENT : 0u),
        // create: construct and open()
        [](const char* config_json, const nclink_host* host, void** instance, const nclink_text_output* reason) -> int {
            try {
                auto driver = std::make_unique<DriverType>();
                DriverContext context;
                context.config = Json::parse(config_json ? config_json : "null", nullptr, false);
                if (context.config.is_discarded()) {
                    put_text(reason, "configuration is not valid JSON");
                    return NCLINK_E_VALUE_TYPE;
                }
                context.logger = host_logger(host);
                auto opened = driver->open(context);
                if (!opened.ok()) return put_error(reason, opened.error());
                *instance = driver.release();
                return NCLINK_OK;
            } catch (const std::exception& e) {
                put_text(reason, e.what());
                return NCLINK_E_UNAVAILABLE;
            }
        },
        // destroy: close() and delete
        [](void* instance) {
            auto* driver = static_cast<DriverType*>(instance);
            driver->close();
            delete driver;
        },
        // read: read_samples() when it feeds a channel and the driver has it, else read()
        [](void* instance, const nclink_read_request* request, const nclink_read_output* out) {
            auto* driver = static_cast<DriverType*>(instance);
            const size_t count = request->count;
            std::vector<PointRef> points(count);
            for (size_t i = 0; i < count; ++i) {
                points[i].id = request->ids[i];
                points[i].kind = kind_from_c(request->kinds[i]);
                points[i].handle = request->handles ? request->handles[i] : no_handle;
            }
            try {
                if (request->sampling) {
                    std::vector<SampleValue> row(count);
                    if (driver->read_samples(points, row.data())) {
                        for (size_t i = 0; i < count; ++i) put_sample(out, i, row[i]);
                        return;
                    }
                }
                std::vector<Result<Json>> results(count, Result<Json>(make_error(ErrorCode::unavailable)));
                driver->read(points, results);
                for (size_t i = 0; i < count; ++i) {
                    if (results[i].ok()) put_value(out, i, results[i].value());
                    else
                        out->error(out->context, i, static_cast<int>(results[i].error().code), results[i].error().message.c_str());
                }
            } catch (const std::exception& e) {
                for (size_t i = 0; i < count; ++i) out->error(out->context, i, NCLINK_E_UNAVAILABLE, e.what());
            }
        },
        // bind
        [](void* instance, const nclink_bind_request* request, const nclink_text_output* reason) -> int {
            try {
                std::vector<BindPoint> points(request->count);
                for (size_t i = 0; i < request->count; ++i) {
                    BindPoint& p = points[i];
                    p.id = request->ids[i];
                    p.method = request->kinds[i] == NCLINK_KIND_METHOD;
                    p.kind = kind_from_c(request->kinds[i]);
                    p.type = request->types[i];
                    p.name = request->names[i];
                    p.units = request->units[i];
                    p.path = request->paths[i];
                    p.setable = request->setable[i] != 0;
                }
                std::vector<PointHandle> handles(request->count, no_handle);
                auto bound = static_cast<DriverType*>(instance)->bind(points, handles);
                if (!bound.ok()) return put_error(reason, bound.error());
                for (size_t i = 0; i < request->count && i < handles.size(); ++i) request->handles[i] = handles[i];
                return NCLINK_OK;
            } catch (const std::exception& e) {
                put_text(reason, e.what());
                return NCLINK_E_UNAVAILABLE;
            }
        },
        // write
        [](void* instance, const nclink_write_request* c, const nclink_text_output* reason) -> int {
            WriteRequest request;
            request.id = c->id;
            request.kind = kind_from_c(c->kind);
            request.handle = c->handle;
            request.params = Json::parse(c->params_json ? c->params_json : "null", nullptr, false);
            request.new_value = Json::parse(c->new_value_json ? c->new_value_json : "null", nullptr, false);
            if (request.params.is_discarded() || request.new_value.is_discarded()) {
                put_text(reason, "params or value is not valid JSON");
                return static_cast<int>(ErrorCode::syntax_error);
            }
            try {
                auto r = static_cast<DriverType*>(instance)->write(request);
                return r.ok() ? NCLINK_OK : put_error(reason, r.error());
            } catch (const std::exception& e) {
                put_text(reason, e.what());
                return NCLINK_E_UNAVAILABLE;
            }
        },
        // call_method: run_method() with the bound handle
        [](void* instance, const nclink_method_request* c, const nclink_method_control* control, const nclink_text_output* result,
           const nclink_text_output* reason) -> int {
            const Json args = Json::parse(c->args_json ? c->args_json : "null", nullptr, false);
            if (args.is_discarded()) {
                put_text(reason, "args are not valid JSON");
                return static_cast<int>(ErrorCode::syntax_error);
            }
            ControlBridge bridge(control);
            try {
                auto r = static_cast<DriverType*>(instance)->run_method(PointRef{c->id, DataKind::single, c->handle}, args, bridge);
                if (!r.ok()) return put_error(reason, r.error());
                if (!r.value().is_null()) put_text(result, r.value().dump(-1, ' ', false, Json::error_handler_t::replace));
                return NCLINK_OK;
            } catch (const std::exception& e) {
                put_text(reason, e.what());
                return NCLINK_E_UNAVAILABLE;
            }
        },
        // claims
        [](void* instance, const char* id) -> int { return static_cast<DriverType*>(instance)->claims(id ? id : "") ? 1 : 0; },
        // link
        [](void* instance, const nclink_text_output* reason) -> int {
            const MachineLinkStatus link = static_cast<DriverType*>(instance)->link();
            if (link.state == MachineLink::disconnected) {
                put_text(reason, link.reason);
                return NCLINK_LINK_DISCONNECTED;
            }
            return link.state == MachineLink::connected ? NCLINK_LINK_CONNECTED : NCLINK_LINK_UNKNOWN;
        },
    };
    return &d;
}

}  // namespace nclink::plugin_export

#define NCLINK_EXPORT_DRIVER(DriverType)                                                                          \
    extern "C" __attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { \
        return ::nclink::plugin_export::descriptor<DriverType>(0u);                                               \
    }
