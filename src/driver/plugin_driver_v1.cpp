// A plugin built for ABI version 1 (driver_plugin_v1.h), adapted to the
// Driver interface: ids and JSON text both ways, as that version defined.
// Handles, typed reads and link() are version 2's, so such a driver keeps
// the defaults (every point by id, reads through JSON, link unknown).
#include "driver/plugin_common.hpp"
#include "driver/plugin_drivers.hpp"

#include <fmt/format.h>

namespace nclink::detail {
namespace {

struct ReadSink {
    std::vector<Result<Json>>* results;
    std::vector<char> answered;
};

class PluginDriverV1 final : public Driver {
public:
    PluginDriverV1(std::shared_ptr<void> library, const nclink_driver_descriptor_v1& d, void* instance,
                   std::unique_ptr<nclink_host_v1> host, std::unique_ptr<Logger> logger)
        : library_(std::move(library)),
          d_(d),
          instance_(instance),
          host_(std::move(host)),
          logger_(std::move(logger)),
          info_(plugin_info(d_.name, d_.version, d_.flags, NCLINK_DRIVER_CONCURRENT)) {}
    ~PluginDriverV1() override { d_.destroy(instance_); }  // before library_ unloads

    DriverInfo info() const override { return info_; }

    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        std::vector<const char*> ids(points.size());
        std::vector<int> kinds(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) {
            ids[i] = points[i].id.c_str();
            kinds[i] = kind_to_c(points[i].kind);
        }
        ReadSink sink{&results, std::vector<char>(points.size(), 0)};
        nclink_read_output_v1 out{
            &sink,
            [](void* ctx, size_t index, const char* json, size_t length) {
                auto* s = static_cast<ReadSink*>(ctx);
                if (index >= s->results->size() || json == nullptr) return;
                Json value = Json::parse(json, json + length, nullptr, false);
                (*s->results)[index] = value.is_discarded()
                                           ? Result<Json>(make_error(ErrorCode::unavailable, "plugin returned invalid JSON"))
                                           : Result<Json>(std::move(value));
                s->answered[index] = 1;
            },
            [](void* ctx, size_t index, int code, const char* detail) {
                auto* s = static_cast<ReadSink*>(ctx);
                if (index >= s->results->size()) return;
                (*s->results)[index] = plugin_error(code, detail ? detail : "");
                s->answered[index] = 1;
            }};
        d_.read(instance_, ids.data(), kinds.data(), ids.size(), &out);
        for (std::size_t i = 0; i < points.size(); ++i)
            if (!sink.answered[i]) results[i] = make_error(ErrorCode::unavailable, "plugin gave no value");
    }

    Result<void> write(const WriteRequest& request) override {
        if (!d_.write) return Driver::write(request);
        std::string detail;
        nclink_text_output_v1 out{&detail, append_text};
        const std::string params = request.params.dump(-1, ' ', false, Json::error_handler_t::replace);
        const std::string value = request.new_value.dump(-1, ' ', false, Json::error_handler_t::replace);
        const int code = d_.write(instance_, request.id.c_str(), kind_to_c(request.kind), params.c_str(), value.c_str(), &out);
        if (code == 0) return ok_result();
        return plugin_error(code, std::move(detail));
    }

    bool claims(std::string_view id) const override {
        return d_.claims && d_.claims(instance_, std::string(id).c_str()) != 0;
    }

    Result<Json> call_method(const std::string& method_id, const Json& args, MethodControl& control) override {
        if (!d_.call_method) return Driver::call_method(method_id, args, control);
        std::string text;
        nclink_text_output_v1 out{&text, append_text};
        nclink_method_control_v1 c{
            &control,
            [](void* ctx, double percent) { static_cast<MethodControl*>(ctx)->progress(percent); },
            [](void* ctx) -> int { return static_cast<MethodControl*>(ctx)->cancelled() ? 1 : 0; },
            [](void* ctx) -> int { return static_cast<MethodControl*>(ctx)->checkpoint() ? 1 : 0; }};
        const std::string arg_text = args.dump(-1, ' ', false, Json::error_handler_t::replace);
        const int code = d_.call_method(instance_, method_id.c_str(), arg_text.c_str(), &c, &out);
        if (code != 0) return plugin_error(code, std::move(text));  // version 1: the detail shares the result text
        if (text.empty()) return Json(nullptr);
        Json value = Json::parse(text, nullptr, false);
        if (value.is_discarded()) return make_error(ErrorCode::unavailable, "plugin method returned invalid JSON");
        return value;
    }

private:
    std::shared_ptr<void> library_;
    const nclink_driver_descriptor_v1 d_;
    void* instance_;
    std::unique_ptr<nclink_host_v1> host_;
    std::unique_ptr<Logger> logger_;  // host_->context points here
    DriverInfo info_;
};

}  // namespace

Result<std::shared_ptr<Driver>> make_plugin_driver_v1(std::shared_ptr<void> library, const nclink_driver_descriptor_v1& d,
                                                      const std::string& path, const Json& config, Logger logger) {
    std::vector<std::string> missing;
    if (!d.create) missing.emplace_back("create");
    if (!d.destroy) missing.emplace_back("destroy");
    if (!d.read) missing.emplace_back("read");
    if (!missing.empty())
        return make_error(ErrorCode::parameter_missing,
                          fmt::format("{}: driver '{}' lacks required function(s): {}", path, d.name ? d.name : "?",
                                      fmt::join(missing, ", ")));
    auto owned_logger = std::make_unique<Logger>(std::move(logger));
    auto host = std::make_unique<nclink_host_v1>();
    host->context = owned_logger.get();
    host->log = [](void* ctx, int level, const char* message) {
        const int clamped = level < 0 ? 0 : level > 4 ? 4 : level;
        static_cast<Logger*>(ctx)->write(static_cast<LogLevel>(clamped), message ? message : "");
    };
    std::string error;
    nclink_text_output_v1 error_out{&error, append_text};
    const std::string config_text = config.dump(-1, ' ', false, Json::error_handler_t::replace);
    void* instance = d.create(config_text.c_str(), host.get(), &error_out);
    if (!instance)
        return make_error(ErrorCode::unavailable, fmt::format("{}: driver '{}' refused to start: {}", path,
                                                              d.name ? d.name : "?", error.empty() ? "no reason given" : error));
    return std::shared_ptr<Driver>(
        std::make_shared<PluginDriverV1>(std::move(library), d, instance, std::move(host), std::move(owned_logger)));
}

}  // namespace nclink::detail
