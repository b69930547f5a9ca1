#include "conform/checks_fidelity.hpp"

#include <nclink/error.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace nclink::conform {
namespace {

std::string folded(std::string_view text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

std::string shown(const Json& value) {
    std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
    if (text.size() > 160) text = text.substr(0, 157) + "...";
    return text;
}

}  // namespace

Problems check_table19_reason(const Json& status) {
    Problems out;
    if (!status.is_object() || status.value("code", Json()) != Json("NG")) return out;
    const auto reason_it = status.find("reason");
    if (reason_it == status.end() || !reason_it->is_string()) return out;
    const std::string given = reason_it->get<std::string>();
    if (given == dev_unreachable_reason) return out;
    const auto error_it = status.find("error");
    if (error_it != status.end() && error_it->is_number_integer()) {
        const int number = error_it->get<int>();
        if (number < 0) return out;  // user-defined (table 19, last row)
        const auto code = error_code_from_int(number);
        if (!code) {
            out.push_back(fmt::format("\"error\" {} is not a code of table 19", number));
            return out;
        }
        if (folded(given) != folded(reason(*code)))
            out.push_back(fmt::format("\"reason\" is \"{}\", but error {} is \"{}\" (table 20: reason and error from table 19)",
                                      given, number, reason(*code)));
        return out;
    }
    if (!error_code_from_reason(folded(given)) && !error_code_from_reason(given))
        out.push_back(fmt::format("\"reason\" \"{}\" is not a reason of table 19 (table 20)", given));
    return out;
}

Problems check_id_in_refusal(const Json& dtu, std::string_view table) {
    Problems out;
    const auto id = dtu.find("id");
    if (id == dtu.end()) out.push_back(fmt::format("\"id\" is missing ({}: it shall be present, also in a refusal)", table));
    else if (!id->is_string()) out.push_back(fmt::format("\"id\" is {}, not a string ({})", shown(*id), table));
    return out;
}

Problems check_value_rule(const ValueRules& rules, const std::string& id, const Json& value) {
    Problems out;
    if (auto verdict = rules.verify(id, value); !verdict)
        out.push_back(fmt::format("the value breaks chapter 7: {}", verdict.error().message));
    return out;
}

Problems check_form_understood(const Json& entry, std::string_view form) {
    Problems out;
    if (!entry.is_object() || entry.value("code", Json()) != Json("NG")) return out;
    const Json error = entry.value("error", Json());
    const std::string why = folded(entry.value("reason", std::string()));
    const bool unknown_form = error == Json(412) || error == Json(413) || why == folded(reason(ErrorCode::syntax_error)) ||
                              why == folded(reason(ErrorCode::keys_of_arguments));
    if (unknown_form)
        out.push_back(fmt::format("{} is refused as malformed ({}), but the standard defines it", form, shown(entry)));
    return out;
}

Problems check_version_round_trip(std::string_view announced, std::string_view probed, std::string_view expected) {
    Problems out;
    if (!expected.empty() && probed != expected)
        out.push_back(
            fmt::format("Probe/Query returns version \"{}\" after Probe/Set set \"{}\": the model comes back changed "
                        "(8.2.8: the model file as provided)",
                        probed, expected));
    if (!announced.empty() && announced != probed)
        out.push_back(fmt::format("Probe/Version announces \"{}\", the model Probe/Query returns has version \"{}\" (8.2.5)",
                                  announced, probed));
    return out;
}

Problems check_set_echo(const Json& result, const Json& request_params) {
    Problems out;
    const auto echoed = result.find("params");
    if (echoed != result.end() && echoed->is_object()) {
        for (const char* key : {"value", "values"})
            if (echoed->contains(key))
                out.push_back(
                    fmt::format("the result echoes \"{}\": 8.2.14's examples echo what was done, not the value written", key));
    }
    if (!request_params.is_object()) return out;
    for (const char* key : {"operation", "key", "keys", "index", "indexes", "offset", "length"}) {
        if (!request_params.contains(key) || key == std::string_view("operation")) continue;
        if (echoed == result.end() || !echoed->is_object() || !echoed->contains(key))
            out.push_back(
                fmt::format("the result does not echo \"{}\" of the request (8.2.14 examples 2 and 3: params echoed)", key));
    }
    return out;
}

}  // namespace nclink::conform
