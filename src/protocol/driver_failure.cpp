#include "protocol/driver_failure.hpp"

#include <fmt/format.h>

namespace nclink::protocol_detail {

WireFailure driver_failure(const Error& error) {
    WireFailure out;
    const int number = to_int(error.code);
    // A failure must never read OK: "success" as an error is an unknown code.
    const bool known = number != 0 && error_code_from_int(number).has_value();
    out.status = number == 0 ? ResponseStatus(make_error(ErrorCode::unavailable)) : ResponseStatus(error);
    std::string text = error.message;
    if (!known && number >= 0)
        text = error.message.empty() ? fmt::format("vendor error {}", number)
                                     : fmt::format("vendor error {}: {}", number, error.message);
    if (!text.empty()) out.private_info = Json{{"message", std::move(text)}};
    return out;
}

}  // namespace nclink::protocol_detail
