// The Driver adapters over a loaded plugin, one per ABI version the host
// speaks (driver_plugin.h for 2, driver_plugin_v1.h for 1). The loader
// (plugin_loader.cpp) opens the library and picks one by abi_version.
#pragma once

#include <nclink/driver.hpp>
#include <nclink/driver_plugin.h>
#include <nclink/driver_plugin_v1.h>

#include <memory>
#include <string>

namespace nclink::detail {

/// Checks `d` (struct_size, required functions), creates the instance with
/// `config` and wraps it. `library` stays loaded while the driver lives.
Result<std::shared_ptr<Driver>> make_plugin_driver_v2(std::shared_ptr<void> library, const nclink_driver_descriptor& d,
                                                      const std::string& path, const Json& config, Logger logger);
/// The same for a version-1 plugin: reads and writes by id, values as JSON
/// text, no bind, no typed read, no link.
Result<std::shared_ptr<Driver>> make_plugin_driver_v1(std::shared_ptr<void> library, const nclink_driver_descriptor_v1& d,
                                                      const std::string& path, const Json& config, Logger logger);

}  // namespace nclink::detail
