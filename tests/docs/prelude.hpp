// Declares what the guides' C++ examples call but a vendor supplies: the
// controller API (hal_*) and the firmware's logger (fw_*). Included before
// every C++ block of the docs by check_doc_blocks.sh.
#pragma once
#include <cstddef>
#include <cstdint>
bool hal_connect(const char* port);
void hal_disconnect();
double hal_spindle_rpm();
bool hal_running();
bool hal_read_registers(const std::uint16_t* registers, std::int32_t* values, std::size_t count);
std::int32_t hal_read_register(std::uint16_t reg);
bool hal_set_feed_override(int percent);
void hal_warm_up_step(int step);
double hal_axis_position(int axis);
int hal_feed_override();
enum { FW_DEBUG, FW_INFO, FW_WARNING, FW_ERROR };
void fw_log(int level, const char* format, ...);
