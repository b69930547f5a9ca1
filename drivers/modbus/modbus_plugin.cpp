// nclink-modbus.so: the Modbus TCP driver as a driver plugin, so any adapter
// host (nclink-sim --config, a gateway) runs it from configuration alone:
//   "driver": {"plugin": "nclink-modbus.so", "config": {"host": ..., "points": {...}}}
// The map is read in open() (docs/drivers/modbus.md).
#include <nclink/driver_plugin_export.hpp>
#include "modbus/modbus_driver.hpp"

NCLINK_EXPORT_DRIVER(nclink::modbus::ModbusDriver)
