// The arguments of `nclink events` that need parsing: filters given as JSON
// or in a short form, and the one-line rendering of an Event DTU.
// Header-only and pure, so tests/unit/events can test it without the program.
//
// Short forms (VALUE is JSON if it parses, else a string):
//   change[:VARIANCE]            equal:VALUE
//   range:FROM,TO[,VARIANCE]     less:VALUE[,VARIANCE]   greater:VALUE[,VARIANCE]
//   include:V1,V2,...
// or a JSON filter object, or a JSON array of them.
#pragma once

#include "commands.hpp"

#include "client_args.hpp"
#include <nclink/dtu.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace nclink::cli {

namespace event_args_detail {

inline std::vector<std::string> split_commas(std::string_view text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true) {
        const auto comma = text.find(',', start);
        out.emplace_back(text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    return out;
}

inline Json number_arg(const std::string& text, const std::string& spec) {
    const Json value = parse_value_text(text);
    if (!value.is_number()) throw UsageError{"--filter " + spec + ": \"" + text + "\" is not a number"};
    return value;
}

}  // namespace event_args_detail

/// The filter objects of one --filter argument. The adapter checks them
/// (419/421); here only the short form's shape is checked (UsageError).
inline std::vector<Json> parse_filter_arg(const std::string& spec) {
    using namespace event_args_detail;
    if (spec.empty()) throw UsageError{"--filter needs a value"};
    if (spec.front() == '{' || spec.front() == '[') {
        const Json parsed = Json::parse(spec, nullptr, false);
        if (parsed.is_object()) return {parsed};
        if (parsed.is_array()) return parsed.get<std::vector<Json>>();
        throw UsageError{"--filter " + spec + ": not a JSON object or array"};
    }
    const auto colon = spec.find(':');
    const std::string type = spec.substr(0, colon);
    const bool has_args = colon != std::string::npos;
    const std::vector<std::string> args =
        has_args ? split_commas(std::string_view(spec).substr(colon + 1)) : std::vector<std::string>{};
    Json filter{{"type", type}};
    auto need = [&](std::size_t min, std::size_t max) {
        if (args.size() < min || args.size() > max)
            throw UsageError{"--filter " + spec + ": wrong number of arguments for " + type};
    };
    if (type == "change") {
        need(0, 1);
        if (!args.empty()) filter["variance"] = number_arg(args[0], spec);
    } else if (type == "equal") {
        if (!has_args) throw UsageError{"--filter equal:VALUE needs a value"};
        filter["value"] = parse_value_text(spec.substr(colon + 1));  // the value may contain commas
    } else if (type == "range") {
        need(2, 3);
        filter["from"] = number_arg(args[0], spec);
        filter["to"] = number_arg(args[1], spec);
        if (args.size() == 3) filter["variance"] = number_arg(args[2], spec);
    } else if (type == "less" || type == "greater") {
        need(1, 2);
        filter["value"] = number_arg(args[0], spec);
        if (args.size() == 2) filter["variance"] = number_arg(args[1], spec);
    } else if (type == "include") {
        need(1, static_cast<std::size_t>(-1));
        Json values = Json::array();
        for (const auto& a : args) values.push_back(parse_value_text(a));
        filter["values"] = std::move(values);
    } else {
        throw UsageError{"--filter: unknown filter type \"" + type + "\" (change, equal, range, less, greater, include, or JSON)"};
    }
    return {filter};
}

/// "EVENT_ID ITEM[KEY] OLD -> NEW" (the time is printed by the caller).
inline std::string format_event(const EventData& dtu) {
    std::string out = dtu.id + " " + dtu.event.id;
    if (dtu.event.key) out += "[" + *dtu.event.key + "]";
    if (dtu.event.index) out += "[" + std::to_string(*dtu.event.index) + "]";
    const auto dump = [](const Json& v) { return v.dump(-1, ' ', false, Json::error_handler_t::replace); };
    out += " ";
    if (dtu.event.old_value) out += dump(*dtu.event.old_value) + " -> ";
    out += dump(dtu.event.value);
    return out;
}

}  // namespace nclink::cli
