// The bridge's configuration file (docs/bridge.md "Configuration").
#include "bridge/bridge.hpp"

#include "core/config_common.hpp"
#include "transport/broker_config.hpp"

namespace nclink::bridge {
using core_detail::ConfigReader;

Result<std::pair<std::string, int>> parse_host_port(const std::string& text) {
    const auto colon = text.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
        return make_error(ErrorCode::value_type, "'" + text + "' is not HOST:PORT");
    std::string host = text.substr(0, colon);
    if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    int port = 0;
    for (char c : text.substr(colon + 1)) {
        if (c < '0' || c > '9' || port > 65535) return make_error(ErrorCode::value_type, "'" + text + "': bad port");
        port = port * 10 + (c - '0');
    }
    if (port > 65535) return make_error(ErrorCode::value_type, "'" + text + "': port above 65535");
    return std::make_pair(host, port);
}

namespace {

Result<void> read_endpoint(ConfigReader& r, const char* key, std::string& host, int& port) {
    std::string text;
    NCLINK_TRY(r.str(key, text));
    if (text.empty()) return ok_result();
    auto parsed = parse_host_port(text);
    if (!parsed) return make_error(ErrorCode::value_type, std::string("configuration: ") + key + ": " + parsed.error().message);
    host = parsed->first;
    port = parsed->second;
    return ok_result();
}

}  // namespace

Result<BridgeConfig> bridge_config_from_json(const Json& json, BridgeConfig c) {
    if (!json.is_object()) return make_error(ErrorCode::syntax_error, "configuration: the file must hold a JSON object");
    ConfigReader top(json, "");
    if (const Json* broker = top.object("broker")) {
        if (!broker->is_object()) return make_error(ErrorCode::value_type, "configuration: broker must be an object");
        ConfigReader b(*broker, "broker.");
        NCLINK_TRY(transport_detail::read_broker_common(b, c));
        NCLINK_TRY(b.no_unknown_keys());
    }
    NCLINK_TRY(top.str("ex_cid", c.ex_cid));
    if (const Json* devices = top.object("devices")) {
        if (!devices->is_array()) return make_error(ErrorCode::value_type, "configuration: devices must be an array of strings");
        c.devices.clear();
        for (const auto& d : *devices) {
            if (!d.is_string() || d.get<std::string>().empty())
                return make_error(ErrorCode::value_type, "configuration: devices must be an array of strings");
            c.devices.push_back(d.get<std::string>());
        }
    }
    NCLINK_TRY(read_endpoint(top, "http", c.http_host, c.http_port));
    NCLINK_TRY(top.str("http_username", c.http_username));
    NCLINK_TRY(top.str("http_password", c.http_password));
    NCLINK_TRY(top.count("http_workers", c.http_workers));
    NCLINK_TRY(top.count("max_request_bytes", c.max_request_bytes));
    NCLINK_TRY(top.count("http_max_streams", c.http_max_streams));
    NCLINK_TRY(top.duration("http_header_timeout_ms", c.http_header_timeout));
    NCLINK_TRY(top.duration("http_keep_alive_ms", c.http_keep_alive));
    NCLINK_TRY(top.duration("http_read_timeout_ms", c.http_read_timeout));
    NCLINK_TRY(top.duration("http_write_timeout_ms", c.http_write_timeout));
    NCLINK_TRY(top.count("http_max_connections", c.http_max_connections));
    NCLINK_TRY(top.count("http_max_connections_per_peer", c.http_max_connections_per_peer));
    NCLINK_TRY(read_endpoint(top, "shdr", c.shdr_host, c.shdr_port));
    NCLINK_TRY(top.boolean("shdr_enabled", c.shdr_enabled));
    NCLINK_TRY(top.count("buffer_size", c.buffer_size));
    NCLINK_TRY(top.str("sender", c.sender));
    NCLINK_TRY(top.duration("poll_interval_ms", c.poll_interval));
    NCLINK_TRY(top.duration("discovery_interval_ms", c.discovery_interval));
    NCLINK_TRY(top.duration("adapter_liveness_ms", c.adapter_liveness));
    NCLINK_TRY(top.duration("request_timeout_ms", c.request_timeout));
    NCLINK_TRY(top.boolean("use_events", c.use_events));
    NCLINK_TRY(top.duration("heartbeat_ms", c.heartbeat));
    NCLINK_TRY(core_detail::read_log_level(top, c.log_level));
    NCLINK_TRY(top.no_unknown_keys());
    if (c.buffer_size < 1 || c.buffer_size > (1u << 26))
        return make_error(ErrorCode::out_of_range, "configuration: buffer_size must be 1..67108864");
    if (c.http_workers < 3) return make_error(ErrorCode::out_of_range, "configuration: http_workers must be at least 3");
    if (c.http_max_streams < 1) return make_error(ErrorCode::out_of_range, "configuration: http_max_streams must be at least 1");
    if (c.http_max_connections < 1)
        return make_error(ErrorCode::out_of_range, "configuration: http_max_connections must be at least 1");
    for (const auto& [key, value] :
         {std::pair{"http_header_timeout_ms", c.http_header_timeout}, std::pair{"http_keep_alive_ms", c.http_keep_alive},
          std::pair{"http_read_timeout_ms", c.http_read_timeout}, std::pair{"http_write_timeout_ms", c.http_write_timeout}})
        if (value.count() < 10)
            return make_error(ErrorCode::out_of_range, std::string("configuration: ") + key + " must be at least 10");
    if (c.request_timeout.count() <= 0)
        return make_error(ErrorCode::out_of_range, "configuration: request_timeout_ms must be positive");
    if (c.heartbeat.count() < 10) return make_error(ErrorCode::out_of_range, "configuration: heartbeat_ms must be at least 10");
    return c;
}

Result<BridgeConfig> load_bridge_config(const std::string& path, BridgeConfig defaults) {
    auto json = core_detail::read_config_file(path);
    if (!json) return std::move(json).error();
    auto config = bridge_config_from_json(*json, std::move(defaults));
    if (!config) return config;
    transport_detail::resolve_tls_paths(path, config->tls);
    return config;
}

}  // namespace nclink::bridge
