#include "embed/c_boundary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

namespace nclink::embed {

int report(nclink_error* out, int code, std::string_view message) noexcept {
    if (out == nullptr) return code;
    const std::uint32_t size = out->struct_size;
    if (size < offsetof(nclink_error, code) + sizeof out->code || size > NCLINK_MAX_STRUCT_SIZE) return code;
    out->code = code;
    if (size < offsetof(nclink_error, message) + 1) return code;
    // The message array as far as the caller's struct has it.
    const std::size_t room = std::min<std::size_t>(size - offsetof(nclink_error, message), sizeof out->message) - 1;
    std::size_t n = std::min(message.size(), room);
    // Never end inside a UTF-8 sequence: back up over continuation bytes.
    if (n < message.size())
        while (n > 0 && (static_cast<unsigned char>(message[n]) & 0xC0) == 0x80) --n;
    std::memcpy(out->message, message.data(), n);
    out->message[n] = '\0';
    return code;
}

int check_struct_size(nclink_error* out, const char* type, std::uint32_t size, std::size_t first_size) noexcept {
    if (size >= first_size && size <= NCLINK_MAX_STRUCT_SIZE) return 0;
    try {
        return report(out, to_int(ErrorCode::value_type),
                      fmt::format("{}.struct_size is {}: not a size any version of nclink.h gave it (at least {}, at "
                                  "most {}: set it to sizeof({}))",
                                  type, size, first_size, NCLINK_MAX_STRUCT_SIZE, type));
    } catch (...) {
        return report(out, to_int(ErrorCode::value_type), "wrong struct_size");
    }
}

}  // namespace nclink::embed

extern "C" const char* nclink_error_message(int code) {
    if (code == 0) return "OK";
    if (code < 0) return "vendor error";
    const auto known = nclink::error_code_from_int(code);
    // reason() returns static storage holding NUL-terminated literals.
    return known ? nclink::reason(*known).data() : "unknown error";
}
