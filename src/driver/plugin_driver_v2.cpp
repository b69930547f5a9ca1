// A plugin built for ABI version 2 (driver_plugin.h), adapted to the Driver
// interface. Every struct passed carries its size; the plugin's descriptor
// is copied into a full-size one with the fields its struct_size does not
// cover left null, so a plugin built against an older 2.x header needs no
// rebuild. Simple values arrive typed (no JSON text): read() makes Json of
// them, read_samples() puts them straight into the sample row.
#include "driver/plugin_common.hpp"
#include "driver/plugin_drivers.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

namespace nclink::driver_detail {
namespace {

// read(): Json values per point.
struct JsonSink {
    std::vector<Result<Json>>* results;
    std::vector<char> answered;

    // The first answer per point counts; out-of-range indexes are ignored.
    Result<Json>* slot(size_t index) {
        if (index >= results->size() || answered[index]) return nullptr;
        answered[index] = 1;
        return &(*results)[index];
    }
    static JsonSink& of(void* context) { return *static_cast<JsonSink*>(context); }
};

nclink_read_output json_output(JsonSink& sink) {
    nclink_read_output out{};
    out.struct_size = sizeof(nclink_read_output);
    out.context = &sink;
    out.null_value = [](void* c, size_t i) {
        if (auto* s = JsonSink::of(c).slot(i)) *s = Json(nullptr);
    };
    out.boolean = [](void* c, size_t i, int v) {
        if (auto* s = JsonSink::of(c).slot(i)) *s = Json(v != 0);
    };
    out.int64 = [](void* c, size_t i, int64_t v) {
        if (auto* s = JsonSink::of(c).slot(i)) *s = Json(v);
    };
    out.uint64 = [](void* c, size_t i, uint64_t v) {
        if (auto* s = JsonSink::of(c).slot(i)) *s = Json(v);
    };
    out.float64 = [](void* c, size_t i, double v) {
        if (auto* s = JsonSink::of(c).slot(i)) *s = std::isfinite(v) ? Json(v) : Json(nullptr);
    };
    out.text = [](void* c, size_t i, const char* text, size_t length) {
        if (auto* s = JsonSink::of(c).slot(i)) *s = Json(text ? std::string(text, length) : std::string());
    };
    out.json = [](void* c, size_t i, const char* text, size_t length) {
        auto* s = JsonSink::of(c).slot(i);
        if (!s) return;
        Json value = text ? Json::parse(text, text + length, nullptr, false) : Json(Json::value_t::discarded);
        *s = value.is_discarded() ? Result<Json>(make_error(ErrorCode::unavailable, "plugin returned invalid JSON"))
                                  : Result<Json>(std::move(value));
    };
    out.error = [](void* c, size_t i, int code, const char* reason) {
        if (auto* s = JsonSink::of(c).slot(i)) *s = plugin_error(code, reason ? reason : "");
    };
    return out;
}

// read_samples(): SampleValues per point. Texts are copied into `buffer`
// and lent to the row once the plugin returned (the buffer may grow during
// the call, so pointers are taken only at the end).
struct SampleSink {
    SampleValue* out;
    size_t count;
    std::string* buffer;
    struct Lent {
        size_t index, offset, length;
        bool json;
    };
    std::vector<Lent>* lent;
    std::vector<char> answered;

    SampleValue* slot(size_t index) {
        if (index >= count || answered[index]) return nullptr;
        answered[index] = 1;
        return &out[index];
    }
    void lend(size_t index, const char* text, size_t length, bool json) {
        if (!slot(index) || text == nullptr) return;  // stays null
        lent->push_back(Lent{index, buffer->size(), length, json});
        buffer->append(text, length);
    }
    static SampleSink& of(void* context) { return *static_cast<SampleSink*>(context); }
};

nclink_read_output sample_output(SampleSink& sink) {
    nclink_read_output out{};
    out.struct_size = sizeof(nclink_read_output);
    out.context = &sink;
    out.null_value = [](void* c, size_t i) { SampleSink::of(c).slot(i); };
    out.boolean = [](void* c, size_t i, int v) {
        if (auto* s = SampleSink::of(c).slot(i)) *s = SampleValue::boolean(v != 0);
    };
    out.int64 = [](void* c, size_t i, int64_t v) {
        if (auto* s = SampleSink::of(c).slot(i)) *s = SampleValue::int64(v);
    };
    out.uint64 = [](void* c, size_t i, uint64_t v) {
        if (auto* s = SampleSink::of(c).slot(i)) *s = SampleValue::uint64(v);
    };
    out.float64 = [](void* c, size_t i, double v) {
        if (auto* s = SampleSink::of(c).slot(i)) *s = SampleValue::float64(v);  // the encoder sends NaN/Inf as null
    };
    out.text = [](void* c, size_t i, const char* text, size_t length) { SampleSink::of(c).lend(i, text, length, false); };
    out.json = [](void* c, size_t i, const char* text, size_t length) {
        // Copied verbatim into the DTU: a broken text must not break the DTU.
        if (text != nullptr && Json::accept(text, text + length)) SampleSink::of(c).lend(i, text, length, true);
        else SampleSink::of(c).slot(i);  // null, a failed read
    };
    out.error = [](void* c, size_t i, int, const char*) { SampleSink::of(c).slot(i); };  // null in samples
    return out;
}

class PluginDriverV2 final : public Driver {
public:
    PluginDriverV2(std::shared_ptr<void> library, const nclink_driver_descriptor& d, void* instance,
                   std::unique_ptr<nclink_host> host, std::unique_ptr<Logger> logger)
        : library_(std::move(library)),
          d_(d),
          instance_(instance),
          host_(std::move(host)),
          logger_(std::move(logger)),
          info_(plugin_info(d_.name, d_.version, d_.flags, NCLINK_DRIVER_CONCURRENT)) {}
    ~PluginDriverV2() override { d_.destroy(instance_); }  // before library_ unloads

    DriverInfo info() const override { return info_; }

    Result<void> bind(const std::vector<BindPoint>& points, std::vector<PointHandle>& handles) override {
        if (!d_.bind) return ok_result();
        const std::size_t n = points.size();
        std::vector<const char*> ids(n), types(n), names(n), units(n), paths(n);
        std::vector<int> kinds(n), setable(n);
        std::vector<uint64_t> out(n, NCLINK_NO_HANDLE);
        for (std::size_t i = 0; i < n; ++i) {
            ids[i] = points[i].id.c_str();
            types[i] = points[i].type.c_str();
            names[i] = points[i].name.c_str();
            units[i] = points[i].units.c_str();
            paths[i] = points[i].path.c_str();
            kinds[i] = points[i].method ? NCLINK_KIND_METHOD : kind_to_c(points[i].kind);
            setable[i] = points[i].setable ? 1 : 0;
        }
        nclink_bind_request request{};
        request.struct_size = sizeof request;
        request.count = n;
        request.ids = ids.data();
        request.kinds = kinds.data();
        request.types = types.data();
        request.names = names.data();
        request.units = units.data();
        request.paths = paths.data();
        request.setable = setable.data();
        request.handles = out.data();
        std::string reason;
        const nclink_text_output reason_out = text_output(reason);
        const int code = d_.bind(instance_, &request, &reason_out);
        if (code != 0) return plugin_error(code, std::move(reason));
        handles.assign(out.begin(), out.end());
        return ok_result();
    }

    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        Request request(points, false);
        JsonSink sink{&results, std::vector<char>(points.size(), 0)};
        const nclink_read_output out = json_output(sink);
        d_.read(instance_, &request.c, &out);
        for (std::size_t i = 0; i < points.size(); ++i)
            if (!sink.answered[i]) results[i] = make_error(ErrorCode::unavailable, "plugin gave no value");
    }

    bool read_samples(const std::vector<PointRef>& points, SampleValue* out) override {
        // One buffer per sampling thread: the SDK copies a row's texts
        // before that thread reads again (Driver::read_samples), and a
        // concurrent plugin may be read from two threads at once.
        thread_local std::string buffer;
        thread_local std::vector<SampleSink::Lent> lent;
        buffer.clear();
        lent.clear();
        Request request(points, true);
        SampleSink sink{out, points.size(), &buffer, &lent, std::vector<char>(points.size(), 0)};
        const nclink_read_output c_out = sample_output(sink);
        d_.read(instance_, &request.c, &c_out);
        for (const auto& l : lent) {
            const std::string_view text(buffer.data() + l.offset, l.length);
            out[l.index] = l.json ? SampleValue::json(text) : SampleValue::text(text);
        }
        return true;
    }

    Result<void> write(const WriteRequest& request) override {
        if (!d_.write) return Driver::write(request);
        const std::string params = request.params.dump(-1, ' ', false, Json::error_handler_t::replace);
        const std::string value = request.new_value.dump(-1, ' ', false, Json::error_handler_t::replace);
        nclink_write_request c{};
        c.struct_size = sizeof c;
        c.id = request.id.c_str();
        c.kind = kind_to_c(request.kind);
        c.handle = request.handle;
        c.params_json = params.c_str();
        c.new_value_json = value.c_str();
        std::string reason;
        const nclink_text_output reason_out = text_output(reason);
        const int code = d_.write(instance_, &c, &reason_out);
        if (code == 0) return ok_result();
        return plugin_error(code, std::move(reason));
    }

    bool claims(std::string_view id) const override { return d_.claims && d_.claims(instance_, std::string(id).c_str()) != 0; }

    Result<Json> run_method(const PointRef& method, const Json& args, MethodControl& control) override {
        if (!d_.call_method) return Driver::run_method(method, args, control);
        nclink_method_control c{};
        c.struct_size = sizeof c;
        c.context = &control;
        c.progress = [](void* ctx, double percent) { static_cast<MethodControl*>(ctx)->progress(percent); };
        c.cancelled = [](void* ctx) -> int { return static_cast<MethodControl*>(ctx)->cancelled() ? 1 : 0; };
        c.checkpoint = [](void* ctx) -> int { return static_cast<MethodControl*>(ctx)->checkpoint() ? 1 : 0; };
        const std::string arg_text = args.dump(-1, ' ', false, Json::error_handler_t::replace);
        nclink_method_request request{};
        request.struct_size = sizeof request;
        request.id = method.id.c_str();
        request.handle = method.handle;
        request.args_json = arg_text.c_str();
        std::string result, reason;
        const nclink_text_output result_out = text_output(result);
        const nclink_text_output reason_out = text_output(reason);
        const int code = d_.call_method(instance_, &request, &c, &result_out, &reason_out);
        if (code != 0) return plugin_error(code, std::move(reason));
        if (result.empty()) return Json(nullptr);
        Json value = Json::parse(result, nullptr, false);
        if (value.is_discarded()) return make_error(ErrorCode::unavailable, "plugin method returned invalid JSON");
        return value;
    }

    MachineLinkStatus link() const override {
        if (!d_.link) return {};
        std::string reason;
        const nclink_text_output reason_out = text_output(reason);
        switch (d_.link(instance_, &reason_out)) {
            case NCLINK_LINK_CONNECTED: return {MachineLink::connected, {}};
            case NCLINK_LINK_DISCONNECTED: return {MachineLink::disconnected, std::move(reason)};
            default: return {};
        }
    }

private:
    // The C view of a read: ids, kinds and handles of `points`.
    struct Request {
        std::vector<const char*> ids;
        std::vector<int> kinds;
        std::vector<uint64_t> handles;
        nclink_read_request c{};
        Request(const std::vector<PointRef>& points, bool sampling)
            : ids(points.size()), kinds(points.size()), handles(points.size()) {
            for (std::size_t i = 0; i < points.size(); ++i) {
                ids[i] = points[i].id.c_str();
                kinds[i] = kind_to_c(points[i].kind);
                handles[i] = points[i].handle;
            }
            c.struct_size = sizeof c;
            c.count = points.size();
            c.ids = ids.data();
            c.kinds = kinds.data();
            c.handles = handles.data();
            c.sampling = sampling ? 1 : 0;
        }
    };

    static nclink_text_output text_output(std::string& into) {
        nclink_text_output out{};
        out.struct_size = sizeof out;
        out.context = &into;
        out.put = append_text;
        return out;
    }

    std::shared_ptr<void> library_;
    const nclink_driver_descriptor d_;
    void* instance_;
    std::unique_ptr<nclink_host> host_;
    std::unique_ptr<Logger> logger_;  // host_->context points here
    DriverInfo info_;
};

}  // namespace

Result<std::shared_ptr<Driver>> make_plugin_driver_v2(std::shared_ptr<void> library, const nclink_driver_descriptor& given,
                                                      const std::string& path, const Json& config, Logger logger) {
    // Fields beyond the plugin's struct_size stay null (driver_plugin.h, "Versions").
    constexpr std::size_t required = offsetof(nclink_driver_descriptor, read) + sizeof(nclink_driver_descriptor::read);
    if (given.struct_size < required)
        return make_error(ErrorCode::value_type,
                          fmt::format("{}: driver descriptor struct_size {} is too small for ABI version {} (at least {})", path,
                                      given.struct_size, NCLINK_DRIVER_ABI_VERSION, required));
    nclink_driver_descriptor d{};
    std::memcpy(&d, &given, std::min<std::size_t>(given.struct_size, sizeof d));
    d.struct_size = sizeof d;
    std::vector<std::string> missing;
    if (!d.create) missing.emplace_back("create");
    if (!d.destroy) missing.emplace_back("destroy");
    if (!d.read) missing.emplace_back("read");
    if (!missing.empty())
        return make_error(ErrorCode::parameter_missing, fmt::format("{}: driver '{}' lacks required function(s): {}", path,
                                                                    d.name ? d.name : "?", fmt::join(missing, ", ")));

    auto owned_logger = std::make_unique<Logger>(std::move(logger));
    auto host = std::make_unique<nclink_host>();
    host->struct_size = sizeof(nclink_host);
    host->context = owned_logger.get();
    host->log = [](void* ctx, int level, const char* message) {
        const int clamped = level < NCLINK_LOG_TRACE ? NCLINK_LOG_TRACE : level > NCLINK_LOG_ERROR ? NCLINK_LOG_ERROR : level;
        static_cast<Logger*>(ctx)->write(static_cast<LogLevel>(clamped), message ? message : "");
    };
    std::string reason;
    nclink_text_output reason_out{};
    reason_out.struct_size = sizeof reason_out;
    reason_out.context = &reason;
    reason_out.put = append_text;
    const std::string config_text = config.dump(-1, ' ', false, Json::error_handler_t::replace);
    void* instance = nullptr;
    const int code = d.create(config_text.c_str(), host.get(), &instance, &reason_out);
    if (code != 0 || instance == nullptr) {
        if (code == 0 && instance == nullptr) reason = "create() returned no instance";
        Error refused = plugin_error(code, "");
        refused.message = fmt::format("{}: driver '{}' refused to start: {}", path, d.name ? d.name : "?",
                                      reason.empty() ? "no reason given" : reason);
        return refused;
    }
    return std::shared_ptr<Driver>(
        std::make_shared<PluginDriverV2>(std::move(library), d, instance, std::move(host), std::move(owned_logger)));
}

}  // namespace nclink::driver_detail
