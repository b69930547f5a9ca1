// Loading driver plugins (driver_plugin.h) with dlopen.
#pragma once

#include <nclink/driver.hpp>
#include <nclink/export.hpp>

#include <memory>
#include <string>

namespace nclink {

/// Loads the plugin at `path`, checks its ABI version and function table, and
/// creates its driver with `config`. The returned Driver keeps the library
/// loaded while it lives. Errors say exactly what is wrong (missing file,
/// missing entry symbol, ABI version mismatch, missing function, refused by
/// create) with ErrorCode::unavailable / value_type / parameter_missing.
/// Thread-safe (dlopen is).
NCLINK_API Result<std::shared_ptr<Driver>> load_driver_plugin(const std::string& path, const Json& config = nullptr,
                                                              Logger logger = {});

}  // namespace nclink
