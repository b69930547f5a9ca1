// The Driver adapter over a plugin's descriptor (driver_plugin.h, ABI
// version 2). The loader (plugin_loader.cpp) opens the library and checks
// abi_version first.
#pragma once

#include <nclink/driver.hpp>
#include <nclink/driver_plugin.h>

#include <memory>
#include <string>

namespace nclink::driver_detail {

/// Checks `d` (struct_size, required functions), creates the instance with
/// `config` and wraps it. `library` stays loaded while the driver lives.
Result<std::shared_ptr<Driver>> make_plugin_driver_v2(std::shared_ptr<void> library, const nclink_driver_descriptor& d,
                                                      const std::string& path, const Json& config, Logger logger);

}  // namespace nclink::driver_detail
