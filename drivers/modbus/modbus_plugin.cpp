// nclink-modbus.so: the Modbus driver (TCP, or RTU on a serial line) as a
// driver plugin, so any adapter host (nclink-sim --config, a gateway) runs it
// from configuration alone:
//   "driver": {"plugin": "nclink-modbus.so", "config": {"host": ..., "points": {...}}}
// The map is read in open() (docs/drivers/modbus.md).
#include <nclink/driver_plugin_export.hpp>
#include "modbus/modbus_bus.hpp"
#include "modbus/modbus_driver.hpp"

namespace {

/// The serial lines of every driver this plugin makes. A gateway loads the
/// plugin once per machine, and dlopen() hands each the same loaded library,
/// so machines whose maps name one device find one Bus here and take turns
/// on it: one device cannot be opened twice with each reading the other's
/// answers. The only state the plugin's drivers share; it lives as long as
/// the library stays loaded.
std::shared_ptr<nclink::modbus::BusRegistry> plugin_buses() {
    static const auto buses = std::make_shared<nclink::modbus::BusRegistry>();
    return buses;
}

class PluginModbusDriver final : public nclink::modbus::ModbusDriver {
public:
    PluginModbusDriver() : ModbusDriver(std::nullopt, {}, plugin_buses()) {}
};

}  // namespace

NCLINK_EXPORT_DRIVER(PluginModbusDriver)
