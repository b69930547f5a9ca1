// Which model file a start serves (adapter_model_load.hpp).
#include "adapter/adapter_model_load.hpp"

#include "adapter/request_handlers.hpp"

#include <nclink/model_version.hpp>

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace nclink::adapter_detail {

namespace {

/// The first device's version of a model file, "" when it cannot be read.
std::string device_version_of(const LoadResult& loaded, const std::string& device_id) {
    if (!loaded.model || loaded.model->devices().empty()) return {};
    const Device* device = device_id.empty() ? &loaded.model->devices().front() : loaded.model->device(device_id);
    return device ? device->version : std::string();
}

}  // namespace

// Which model to serve: the one a Probe/Set or replace_model() persisted
// (it is the current one for this device), unless the vendor ships a model
// with a newer version (a firmware update): then the shipped one wins and
// replaces the persisted file. Equal, older, or versions that cannot be
// ordered keep the persisted one. The log says which was used and why.
Result<LoadResult> load_adapter_model(const AdapterConfig& config, const ModelHost& host, const Logger& logger) {
    std::string path = config.model_path;
    const std::string persisted = host.persisted_model_path();
    LoadResult loaded;
    bool adopt_shipped = false;
    if (!persisted.empty()) {
        LoadResult kept = host.load_file(persisted);
        LoadResult shipped = config.model_path.empty() ? LoadResult{} : host.load_file(config.model_path);
        const std::string kept_version = device_version_of(kept, config.device_id);
        const std::string shipped_version = device_version_of(shipped, config.device_id);
        const auto order = compare_model_versions(shipped_version, kept_version);
        if (shipped.model && (!kept.model || (order && *order > 0))) {
            logger.info("using the shipped model {} (version {}): newer than the persisted {} (version {})", config.model_path,
                        shipped_version, persisted, kept_version.empty() ? "?" : kept_version);
            loaded = std::move(shipped);
            adopt_shipped = true;
        } else {
            logger.info("using the persisted model {} (version {}) of the last model change{}", persisted, kept_version,
                        shipped.model ? fmt::format("; the shipped {} has version {}", config.model_path, shipped_version)
                                      : std::string());
            path = persisted;
            loaded = std::move(kept);
        }
    } else {
        if (path.empty()) return make_error(ErrorCode::parameter_missing, "no model file configured");
        // A file that is not there is not a model with a syntax error: say so
        // with the system's reason, once (the caller logs the error).
        if (std::FILE* f = std::fopen(path.c_str(), "rb"); !f) {
            const int why = errno;
            return make_error(ErrorCode::unavailable, fmt::format("cannot read the model file {}: {}", path, std::strerror(why)));
        } else {
            std::fclose(f);
        }
        loaded = host.load_file(path);
        logger.info("using the model {} (version {})", path, device_version_of(loaded, config.device_id));
    }
    for (const auto& p : loaded.problems) {
        // What refuses the model is part of the error the caller reports.
        if (p.severity == Severity::fatal || (config.strict && p.severity == Severity::conformance)) continue;
        const auto level = p.severity == Severity::warning ? LogLevel::debug : LogLevel::warn;
        logger.log(level, "{}:{}: {}: {}", path, p.pointer.empty() ? "/" : p.pointer, to_string(p.severity), p.message);
    }
    const std::string refused = refusal_reasons(loaded, config.strict);
    if (!refused.empty() || !loaded.model)
        return make_error(ErrorCode::syntax_error,
                          fmt::format("model {} refused{}: {}", path, config.strict ? " (strict)" : "", refused));
    if (adopt_shipped) {
        // The persisted file is stale from now on: remove it so the next
        // start does not weigh it again.
        std::error_code ec;
        std::filesystem::remove(persisted, ec);
    }
    return loaded;
}

}  // namespace nclink::adapter_detail
