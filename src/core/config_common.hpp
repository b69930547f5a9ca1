// The parts every configuration file shares: reading the file (syntax errors
// located by line and column), locating a reader's error in the file, the log
// level, and paths relative to the file (the broker section is
// transport/broker_config.hpp).
#pragma once

#include "core/config_reader.hpp"

#include <nclink/http_limits.hpp>
#include <nclink/log.hpp>

#include <optional>
#include <string>

namespace nclink::core_detail {

/// A configuration file: its text (to locate errors in) and its JSON.
struct ConfigDocument {
    std::string path;
    std::string text;
    Json json;
};

/// Reads and parses a configuration file: 202 when unreadable; 412 with
/// "path:line:column: ..." when it is not valid JSON.
Result<ConfigDocument> read_config_document(const std::string& path);
/// The same, for readers that need only the JSON.
Result<Json> read_config_file(const std::string& path);

/// `error` (from a reader of `doc.json`) prefixed with where it is:
/// "path:line:column: message" when its pointer is found in the text, else
/// "path: message". The pointer is kept.
Error located(const ConfigDocument& doc, Error error);

/// Makes `p` absolute against the directory of `config_path` when relative.
void resolve_against(const std::string& config_path, std::string& p);
/// "log_level": trace/debug/info/warn/error/off.
Result<void> read_log_level(ConfigReader& top, LogLevel& out);
/// The "metrics" section (include/nclink/http_limits.hpp): the bridge's
/// http_* keys for a program's /metrics endpoint. Unknown keys 413; a worker
/// or connection count of 0 or a deadline of 0 is refused (out of range).
Result<void> read_http_limits(ConfigReader& top, const char* section, HttpLimits& out);

}  // namespace nclink::core_detail
