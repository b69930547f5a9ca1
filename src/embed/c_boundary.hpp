// What every function of the C embedding API (include/nclink/nclink.h) does
// at the boundary: check a struct's struct_size, fill an nclink_error, and
// turn any C++ exception into a code (none may cross into C).
#pragma once

#include <nclink/error.hpp>
#include <nclink/nclink.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>

namespace nclink::embed {

/// Writes `code` and `message` into `out` as far as its struct_size covers
/// (nclink.h, "Growth"); NULL or a struct_size too small for the code is
/// ignored. The message is cut at a character boundary. Returns `code`.
int report(nclink_error* out, int code, std::string_view message) noexcept;
inline int report(nclink_error* out, const Error& error) noexcept { return report(out, to_int(error.code), error.message); }
inline int report_ok(nclink_error* out) noexcept { return report(out, 0, {}); }

/// 0 when a struct of `first_size` bytes at version 1 may have `size` (at
/// least the first version, at most NCLINK_MAX_STRUCT_SIZE), else 405 with a
/// message naming the struct.
int check_struct_size(nclink_error* out, const char* type, std::uint32_t size, std::size_t first_size) noexcept;

/// Runs `body` (returning an int code), mapping any exception to 202 with
/// its text. The last line of every C entry point.
template <class Body>
int guarded(nclink_error* out, Body&& body) noexcept {
    try {
        return body();
    } catch (const std::exception& e) {
        return report(out, to_int(ErrorCode::unavailable), std::string("internal error: ") + e.what());
    } catch (...) {
        return report(out, to_int(ErrorCode::unavailable), "internal error: unknown exception");
    }
}

}  // namespace nclink::embed
