// dlopen()s a driver plugin and hands it to the adapter of its ABI version
// (driver_plugin.h, "Versions"): 2 is the only one; anything else (also 1,
// removed before the first release, docs/abi.md) is refused in one line
// that names the version.
#include "driver/plugin_drivers.hpp"

#include <nclink/driver_plugin_loader.hpp>

#include <dlfcn.h>
#include <filesystem>
#include <fmt/format.h>

namespace nclink {

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
    // Every version's descriptor starts with abi_version: read it alone first.
    const void* entry_result = reinterpret_cast<const void* (*)(void)>(symbol)();
    if (!entry_result)
        return make_error(ErrorCode::unavailable, fmt::format("{}: {}() returned no descriptor", path, NCLINK_DRIVER_ENTRY_SYMBOL));
    const std::uint32_t version = *static_cast<const std::uint32_t*>(entry_result);
    if (version == NCLINK_DRIVER_ABI_VERSION)
        return driver_detail::make_plugin_driver_v2(
            std::move(library), *static_cast<const nclink_driver_descriptor*>(entry_result), path, config, std::move(logger));
    return make_error(ErrorCode::value_type,
                      fmt::format("{}: driver ABI version {} is not supported (this nclink loads version {})", path, version,
                                  NCLINK_DRIVER_ABI_VERSION));
}

}  // namespace nclink
