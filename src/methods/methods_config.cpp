#include "methods/methods_config.hpp"

#include "core/config_reader.hpp"

namespace nclink::methods_detail {

Result<void> read_methods_config(const Json& section, MethodsConfig& out) {
    core_detail::ConfigReader r(section, "methods.");
    if (!section.is_object()) return r.fail(ErrorCode::value_type, "", "must be an object");
    NCLINK_TRY(r.count("max_running", out.max_running));
    NCLINK_TRY(r.duration("status_period_ms", out.status_period));
    NCLINK_TRY(r.duration("stop_grace_ms", out.stop_grace));
    NCLINK_TRY(r.no_unknown_keys());
    // A zero period would publish Method/Status in a busy loop.
    if (out.status_period.count() <= 0) return r.fail(ErrorCode::out_of_range, "status_period_ms", "must be positive");
    return ok_result();
}

void methods_config_changes(const MethodsConfig& a, const MethodsConfig& b, std::vector<std::string>& out) {
    const auto key = [&](bool same, const char* name) {
        if (!same) out.emplace_back(name);
    };
    key(a.max_running == b.max_running, "methods.max_running");
    key(a.status_period == b.status_period, "methods.status_period_ms");
    key(a.stop_grace == b.stop_grace, "methods.stop_grace_ms");
}

}  // namespace nclink::methods_detail
