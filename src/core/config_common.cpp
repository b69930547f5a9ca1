#include "core/config_common.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace nclink::detail {

Result<Json> read_config_file(const std::string& path) {
    errno = 0;
    std::ifstream in(path);
    if (!in) {
        const int why = errno;
        return make_error(ErrorCode::unavailable, fmt::format("cannot read configuration file {}: {}", path,
                                                              why != 0 ? std::strerror(why) : "cannot open it"));
    }
    std::stringstream text;
    text << in.rdbuf();
    Json json = Json::parse(text.str(), nullptr, false);
    if (json.is_discarded())
        return make_error(ErrorCode::syntax_error, fmt::format("configuration file {} is not valid JSON", path));
    return json;
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
        return make_error(ErrorCode::value_type,
                          fmt::format("configuration: log_level '{}' is not trace/debug/info/warn/error/off", level));
    out = *parsed;
    return ok_result();
}

}  // namespace nclink::detail
