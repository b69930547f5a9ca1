// RFC 6901 pointer building for problem locations.
#include "model/problems.hpp"

namespace nclink::model_detail {

std::string pointer_append(std::string_view base, std::string_view token) {
    std::string out(base);
    out.reserve(out.size() + token.size() + 1);
    out += '/';
    for (char c : token) {
        if (c == '~') out += "~0";
        else if (c == '/') out += "~1";
        else out += c;
    }
    return out;
}

std::string pointer_append(std::string_view base, std::size_t index) {
    std::string out(base);
    out += '/';
    out += std::to_string(index);
    return out;
}

}  // namespace nclink::model_detail
