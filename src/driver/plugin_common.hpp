// What the two plugin adapters (ABI versions 1 and 2, driver_plugin.h) share:
// how a plugin's error code and reason become an Error, and the text sink
// the host hands out for reasons and return values.
#pragma once

#include <nclink/data_kind.hpp>
#include <nclink/driver.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

namespace nclink::driver_detail {

/// A plugin's failure: its code as is (table 19, or the vendor's own below
/// 0; docs/wire.md, "Vendor errors", decides how it goes on the wire) with
/// its reason. Code 0 is not a failure, so a plugin that reports one anyway
/// gets 202.
inline Error plugin_error(int code, std::string reason) {
    if (code == 0) return make_error(ErrorCode::unavailable, reason.empty() ? "plugin failed with code 0" : std::move(reason));
    return vendor_error(code, std::move(reason));
}

/// nclink_text_output::put for a std::string context: appends.
inline void append_text(void* context, const char* text, std::size_t length) {
    if (text != nullptr) static_cast<std::string*>(context)->append(text, length);
}

/// The DriverInfo of a plugin's descriptor (both ABI versions name it alike).
inline DriverInfo plugin_info(const char* name, const char* version, std::uint32_t flags, std::uint32_t concurrent_flag) {
    DriverInfo info;
    info.name = name ? name : "plugin";
    info.version = version ? version : "0";
    info.concurrent = (flags & concurrent_flag) != 0;
    return info;
}

inline int kind_to_c(DataKind kind) {
    return kind == DataKind::list ? 1 : kind == DataKind::dict ? 2 : 0;  // NCLINK_KIND_*
}

}  // namespace nclink::driver_detail
