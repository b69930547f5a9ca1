#include "core/config_common.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace nclink::detail {

Result<Json> read_config_file(const std::string& path) {
    std::ifstream in(path);
    if (!in) return make_error(ErrorCode::unavailable, fmt::format("cannot read configuration file {}", path));
    std::stringstream text;
    text << in.rdbuf();
    Json json = Json::parse(text.str(), nullptr, false);
    if (json.is_discarded())
        return make_error(ErrorCode::syntax_error, fmt::format("configuration file {} is not valid JSON", path));
    return json;
}

void resolve_against(const std::string& config_path, std::string& p) {
    // Paths inside the file are relative to the file, not to where the program runs.
    if (p.empty() || !std::filesystem::path(p).is_relative()) return;
    p = (std::filesystem::path(config_path).parent_path() / p).lexically_normal().string();
}

void resolve_tls_paths(const std::string& config_path, std::optional<MqttTlsOptions>& tls) {
    if (!tls) return;
    resolve_against(config_path, tls->ca_file);
    resolve_against(config_path, tls->cert_file);
    resolve_against(config_path, tls->key_file);
}

Result<void> read_log_level(ConfigReader& top, LogLevel& out) {
    std::string level;
    NCLINK_TRY(top.str("log_level", level));
    if (level.empty()) return ok_result();
    auto parsed = log_level_from_string(level);
    if (!parsed)
        return make_error(ErrorCode::value_type,
                          fmt::format("configuration: log_level '{}' is not trace/debug/info/warn/error/off", level));
    out = *parsed;
    return ok_result();
}

Result<void> read_tls(ConfigReader& broker, std::optional<MqttTlsOptions>& tls) {
    const Json* section = broker.object("tls");
    if (!section) return ok_result();
    if (!section->is_object()) return make_error(ErrorCode::value_type, "configuration: broker.tls must be an object");
    ConfigReader t(*section, "broker.tls.");
    MqttTlsOptions o = tls.value_or(MqttTlsOptions{});
    NCLINK_TRY(t.str("ca_file", o.ca_file));
    NCLINK_TRY(t.str("cert_file", o.cert_file));
    NCLINK_TRY(t.str("key_file", o.key_file));
    NCLINK_TRY(t.str("key_password", o.key_password));
    NCLINK_TRY(t.boolean("verify", o.verify_server));
    NCLINK_TRY(t.no_unknown_keys());
    tls = o;
    return ok_result();
}

}  // namespace nclink::detail
