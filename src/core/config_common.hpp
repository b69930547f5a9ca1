// The parts every configuration file shares: reading the file, the log
// level, and paths relative to the file (the broker section is
// transport/broker_config.hpp).
#pragma once

#include "core/config_reader.hpp"

#include <nclink/log.hpp>

#include <optional>
#include <string>

namespace nclink::detail {

/// Reads and parses a configuration file (unavailable / syntax_error with the path).
Result<Json> read_config_file(const std::string& path);

/// Makes `p` absolute against the directory of `config_path` when relative.
void resolve_against(const std::string& config_path, std::string& p);
/// "log_level": trace/debug/info/warn/error/off.
Result<void> read_log_level(ConfigReader& top, LogLevel& out);

}  // namespace nclink::detail
