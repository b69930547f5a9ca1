#include <nclink/driver_plugin.h>
#include <nclink/driver_plugin_loader.hpp>

#include <dlfcn.h>
#include <filesystem>
#include <fmt/format.h>

namespace nclink {
namespace {

int kind_to_c(DataKind kind) {
    return kind == DataKind::list ? NCLINK_KIND_LIST : kind == DataKind::dict ? NCLINK_KIND_DICT : NCLINK_KIND_SINGLE;
}

ErrorCode code_from_plugin(int code) {
    if (auto known = error_code_from_int(code); known && *known != ErrorCode::success) return *known;
    return ErrorCode::unavailable;  // user-defined (negative) or unknown codes
}

void append_text(void* context, const char* text, size_t length) {
    static_cast<std::string*>(context)->append(text, length);
}

struct ReadSink {
    std::vector<Result<Json>>* results;
    std::vector<bool> answered;
};

class PluginDriver final : public Driver {
public:
    PluginDriver(std::shared_ptr<void> library, const nclink_driver_descriptor* d, void* instance,
                 std::unique_ptr<nclink_host> host, std::unique_ptr<Logger> logger)
        : library_(std::move(library)), d_(d), instance_(instance), host_(std::move(host)), logger_(std::move(logger)) {
        info_.name = d_->name ? d_->name : "plugin";
        info_.version = d_->version ? d_->version : "0";
        info_.concurrent = (d_->flags & NCLINK_DRIVER_CONCURRENT) != 0;
    }
    ~PluginDriver() override { d_->destroy(instance_); }  // before library_ unloads

    DriverInfo info() const override { return info_; }

    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        std::vector<const char*> ids(points.size());
        std::vector<int> kinds(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) {
            ids[i] = points[i].id.c_str();
            kinds[i] = kind_to_c(points[i].kind);
        }
        ReadSink sink{&results, std::vector<bool>(points.size(), false)};
        nclink_read_output out{
            &sink,
            [](void* ctx, size_t index, const char* json, size_t length) {
                auto* s = static_cast<ReadSink*>(ctx);
                if (index >= s->results->size()) return;
                Json value = Json::parse(json, json + length, nullptr, false);
                (*s->results)[index] = value.is_discarded()
                                           ? Result<Json>(make_error(ErrorCode::unavailable, "plugin returned invalid JSON"))
                                           : Result<Json>(std::move(value));
                s->answered[index] = true;
            },
            [](void* ctx, size_t index, int code, const char* detail) {
                auto* s = static_cast<ReadSink*>(ctx);
                if (index >= s->results->size()) return;
                (*s->results)[index] = make_error(code_from_plugin(code), detail ? detail : "");
                s->answered[index] = true;
            }};
        d_->read(instance_, ids.data(), kinds.data(), ids.size(), &out);
        for (std::size_t i = 0; i < points.size(); ++i)
            if (!sink.answered[i]) results[i] = make_error(ErrorCode::unavailable, "plugin gave no value");
    }

    Result<void> write(const WriteRequest& request) override {
        if (!d_->write) return Driver::write(request);
        std::string detail;
        nclink_text_output out{&detail, append_text};
        const std::string params = request.params.dump(-1, ' ', false, Json::error_handler_t::replace);
        const std::string value = request.new_value.dump(-1, ' ', false, Json::error_handler_t::replace);
        const int code = d_->write(instance_, request.id.c_str(), kind_to_c(request.kind), params.c_str(), value.c_str(), &out);
        if (code == 0) return ok_result();
        return make_error(code_from_plugin(code), detail);
    }

    bool claims(std::string_view id) const override {
        return d_->claims && d_->claims(instance_, std::string(id).c_str()) != 0;
    }

    Result<Json> call_method(const std::string& method_id, const Json& args, MethodControl& control) override {
        if (!d_->call_method) return Driver::call_method(method_id, args, control);
        std::string text;
        nclink_text_output out{&text, append_text};
        nclink_method_control c{
            &control,
            [](void* ctx, double percent) { static_cast<MethodControl*>(ctx)->progress(percent); },
            [](void* ctx) -> int { return static_cast<MethodControl*>(ctx)->cancelled() ? 1 : 0; },
            [](void* ctx) -> int { return static_cast<MethodControl*>(ctx)->checkpoint() ? 1 : 0; }};
        const std::string arg_text = args.dump(-1, ' ', false, Json::error_handler_t::replace);
        const int code = d_->call_method(instance_, method_id.c_str(), arg_text.c_str(), &c, &out);
        if (code != 0) return make_error(code_from_plugin(code), text);
        if (text.empty()) return Json(nullptr);
        Json value = Json::parse(text, nullptr, false);
        if (value.is_discarded()) return make_error(ErrorCode::unavailable, "plugin method returned invalid JSON");
        return value;
    }

private:
    std::shared_ptr<void> library_;
    const nclink_driver_descriptor* d_;
    void* instance_;
    std::unique_ptr<nclink_host> host_;
    std::unique_ptr<Logger> logger_;  // host_->context points here
    DriverInfo info_;
};

}  // namespace

Result<std::shared_ptr<Driver>> load_driver_plugin(const std::string& path, const Json& config, Logger logger) {
    // A path with a directory names a file: say plainly when it is not
    // there (dlerror()'s "cannot open shared object file" does not say where
    // it looked). A bare name is searched on the library path by dlopen().
    if (path.find('/') != std::string::npos) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec))
            return make_error(ErrorCode::unavailable,
                              fmt::format("driver plugin {} does not exist (a relative driver.plugin is resolved "
                                          "against the directory of the configuration file)",
                                          path));
    }
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* why = ::dlerror();
        return make_error(ErrorCode::unavailable, fmt::format("cannot load driver plugin {}: {}", path, why ? why : "?"));
    }
    std::shared_ptr<void> library(handle, [](void* h) { ::dlclose(h); });
    void* symbol = ::dlsym(handle, NCLINK_DRIVER_ENTRY_SYMBOL);
    if (!symbol)
        return make_error(ErrorCode::unavailable,
                          fmt::format("{} is not an nclink driver plugin: no '{}' symbol", path, NCLINK_DRIVER_ENTRY_SYMBOL));
    auto entry = reinterpret_cast<nclink_driver_entry_fn>(symbol);
    const nclink_driver_descriptor* d = entry();
    if (!d) return make_error(ErrorCode::unavailable, fmt::format("{}: {}() returned no descriptor", path, NCLINK_DRIVER_ENTRY_SYMBOL));
    if (d->abi_version != NCLINK_DRIVER_ABI_VERSION)
        return make_error(ErrorCode::value_type,
                          fmt::format("{}: driver ABI version {} is not supported (this nclink speaks version {})", path,
                                      d->abi_version, NCLINK_DRIVER_ABI_VERSION));
    std::vector<std::string> missing;
    if (!d->create) missing.emplace_back("create");
    if (!d->destroy) missing.emplace_back("destroy");
    if (!d->read) missing.emplace_back("read");
    if (!missing.empty())
        return make_error(ErrorCode::parameter_missing,
                          fmt::format("{}: driver '{}' lacks required function(s): {}", path, d->name ? d->name : "?",
                                      fmt::join(missing, ", ")));

    auto owned_logger = std::make_unique<Logger>(std::move(logger));
    auto host = std::make_unique<nclink_host>();
    host->context = owned_logger.get();
    host->log = [](void* ctx, int level, const char* message) {
        const int clamped = level < 0 ? 0 : level > 4 ? 4 : level;
        static_cast<Logger*>(ctx)->write(static_cast<LogLevel>(clamped), message ? message : "");
    };
    std::string error;
    nclink_text_output error_out{&error, append_text};
    const std::string config_text = config.dump(-1, ' ', false, Json::error_handler_t::replace);
    void* instance = d->create(config_text.c_str(), host.get(), &error_out);
    if (!instance)
        return make_error(ErrorCode::unavailable,
                          fmt::format("{}: driver '{}' refused to start: {}", path, d->name ? d->name : "?",
                                      error.empty() ? "no reason given" : error));
    return std::shared_ptr<Driver>(
        std::make_shared<PluginDriver>(std::move(library), d, instance, std::move(host), std::move(owned_logger)));
}

}  // namespace nclink
