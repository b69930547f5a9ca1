#include "core/config_common.hpp"

#include "core/json_locate.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace nclink::core_detail {

Result<ConfigDocument> read_config_document(const std::string& path) {
    errno = 0;
    std::ifstream in(path);
    if (!in) {
        const int why = errno;
        return make_error(ErrorCode::unavailable, fmt::format("cannot read configuration file {}: {}", path,
                                                              why != 0 ? std::strerror(why) : "cannot open it"));
    }
    std::stringstream text;
    text << in.rdbuf();
    ConfigDocument doc{path, text.str(), nullptr};
    try {
        doc.json = Json::parse(doc.text);
    } catch (const Json::parse_error& e) {
        // e.byte is 1-based: the character the parser stopped at.
        const auto at = position_of_offset(doc.text, e.byte == 0 ? 0 : e.byte - 1);
        std::string what = e.what();
        // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ..." -> the part after the position
        if (const auto colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
        return make_error(ErrorCode::syntax_error, fmt::format("{}:{}:{}: not valid JSON: {}", path, at.line, at.column, what));
    }
    return doc;
}

Result<Json> read_config_file(const std::string& path) {
    auto doc = read_config_document(path);
    if (!doc) return std::move(doc).error();
    return std::move(doc->json);
}

Error located(const ConfigDocument& doc, Error error) {
    std::optional<TextPosition> at;
    if (!error.pointer.empty()) at = locate_pointer(doc.text, error.pointer);
    if (at) error.message = fmt::format("{}:{}:{}: {}", doc.path, at->line, at->column, error.message);
    else error.message = fmt::format("{}: {}", doc.path, error.message);
    return error;
}

void resolve_against(const std::string& config_path, std::string& p) {
    // Paths inside the file are relative to the file, not to where the program
    // runs (docs/configuration.md). A file named without a directory
    // ("adapter.json") lives in the current one: the result is made absolute
    // so that it still names a file when handed to dlopen(), which searches
    // the library path for a name without a slash ("acme-lathe.so").
    if (p.empty() || !std::filesystem::path(p).is_relative()) return;
    std::filesystem::path dir = std::filesystem::path(config_path).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    const auto absolute = std::filesystem::absolute(dir / p, ec);
    p = (ec ? dir / p : absolute).lexically_normal().string();
}

Result<void> read_log_level(ConfigReader& top, LogLevel& out) {
    std::string level;
    NCLINK_TRY(top.str("log_level", level));
    if (level.empty()) return ok_result();
    auto parsed = log_level_from_string(level);
    if (!parsed)
        return top.fail(ErrorCode::value_type, "log_level", fmt::format("'{}' is not trace/debug/info/warn/error/off", level));
    out = *parsed;
    return ok_result();
}

Result<void> read_http_limits(ConfigReader& top, const char* section, HttpLimits& out) {
    const Json* json = top.object(section);
    if (json == nullptr) return ok_result();
    if (!json->is_object()) return top.fail(ErrorCode::value_type, section, "must be an object");
    ConfigReader r(*json, top.where() + section + ".", pointer_append(top.pointer(), section));
    NCLINK_TRY(r.count("http_workers", out.workers));
    NCLINK_TRY(r.duration("http_header_timeout_ms", out.header_timeout));
    NCLINK_TRY(r.duration("http_keep_alive_ms", out.keep_alive));
    NCLINK_TRY(r.duration("http_write_timeout_ms", out.write_timeout));
    NCLINK_TRY(r.count("http_max_connections", out.max_connections));
    NCLINK_TRY(r.count("http_max_connections_per_peer", out.max_connections_per_peer));
    NCLINK_TRY(r.no_unknown_keys());
    // As the bridge's http_* keys: a server needs a worker and a connection,
    // and a deadline under 10 ms would close every client.
    if (out.workers < 1) return r.fail(ErrorCode::out_of_range, "http_workers", "must be at least 1");
    if (out.max_connections < 1) return r.fail(ErrorCode::out_of_range, "http_max_connections", "must be at least 1");
    for (const auto& [key, value] :
         {std::pair{"http_header_timeout_ms", out.header_timeout}, std::pair{"http_keep_alive_ms", out.keep_alive},
          std::pair{"http_write_timeout_ms", out.write_timeout}})
        if (value.count() < 10) return r.fail(ErrorCode::out_of_range, key, "must be at least 10");
    return ok_result();
}

}  // namespace nclink::core_detail
