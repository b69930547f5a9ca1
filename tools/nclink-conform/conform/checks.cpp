#include "conform/checks.hpp"
#include "conform/check_text.hpp"
#include "conform/checks_fidelity.hpp"

#include "model/vocabulary.hpp"  // chapter-7 vocabularies (src/, linked from libnclink)

#include <nclink/dtu.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

namespace nclink::conform {
namespace check_text {
std::string show(const Json& value, std::size_t max) {
    return clip(value.dump(-1, ' ', false, Json::error_handler_t::replace), max);
}

std::string lower(std::string_view text) {
    std::string out(text);
    for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// A string member, or std::nullopt when absent or not a string.
std::optional<std::string> str(const Json& dtu, const char* key) {
    auto it = dtu.find(key);
    if (it == dtu.end() || !it->is_string()) return std::nullopt;
    return it->get<std::string>();
}

void add_all(Problems& to, Problems from, std::string_view prefix) {
    for (auto& p : from) to.push_back(prefix.empty() ? std::move(p) : fmt::format("{}{}", prefix, p));
}

// A required string key equal to `expected`.
void expect_string(Problems& out, const Json& dtu, const char* key, std::string_view expected, std::string_view table) {
    auto it = dtu.find(key);
    if (it == dtu.end()) {
        out.push_back(fmt::format("\"{}\" is missing ({} requires it)", key, table));
    } else if (!it->is_string()) {
        out.push_back(fmt::format("\"{}\" is {}, not a string", key, show(*it)));
    } else if (it->get<std::string>() != expected) {
        out.push_back(fmt::format("\"{}\" is \"{}\", expected \"{}\"", key, it->get<std::string>(), expected));
    }
}

// Envelope + status of a response.
Problems response_basics(const Json& dtu, const Json& sent_id, std::string_view dev, bool guid_required) {
    Problems out = check_envelope(dtu, sent_id, dev, guid_required);
    add_all(out, check_status_keys(dtu));
    return out;
}
}  // namespace check_text

using namespace check_text;

std::optional<Json> parse_object(std::string_view payload, std::string* why) {
    Json parsed = Json::parse(payload.begin(), payload.end(), nullptr, false);
    if (parsed.is_discarded()) {
        if (why) *why = "not JSON";
        return std::nullopt;
    }
    if (!parsed.is_object()) {
        if (why) *why = fmt::format("not a JSON object but {}", parsed.type_name());
        return std::nullopt;
    }
    return parsed;
}

bool is_ok(const Json& dtu) {
    auto code = str(dtu, "code");
    return code && *code == "OK";
}

bool says_not_supported(const Json& dtu) {
    if (is_ok(dtu)) return false;
    if (auto it = dtu.find("error"); it != dtu.end() && it->is_number() && it->get<double>() == 202) return true;
    if (auto reason = str(dtu, "reason")) {
        const std::string r = lower(*reason);
        if (r == "unavailable" || r.find("not supported") != std::string::npos || r.find("unsupported") != std::string::npos)
            // "unsupported operation get_length" (406-408) is about one operation, not the feature.
            return r.rfind("unsupported operation", 0) != 0;
    }
    return false;
}

Problems check_status_keys(const Json& dtu) {
    Problems out;
    auto code = dtu.find("code");
    if (code == dtu.end()) {
        out.push_back("\"code\" is missing (table 20: it shall be present)");
    } else if (!code->is_string() || (*code != "OK" && *code != "NG")) {
        out.push_back(fmt::format("\"code\" is {}, expected \"OK\" or \"NG\" (table 18)", show(*code)));
    }
    if (auto reason = dtu.find("reason"); reason != dtu.end() && !reason->is_string() && !reason->is_null())
        out.push_back(fmt::format("\"reason\" is {}, not a string (table 20)", show(*reason)));
    if (auto error = dtu.find("error"); error != dtu.end() && !error->is_number() && !error->is_null())
        out.push_back(fmt::format("\"error\" is {}, not a number (table 20)", show(*error)));
    if (code != dtu.end() && *code == "NG" && dtu.find("reason") == dtu.end() && dtu.find("error") == dtu.end())
        out.push_back("NG without \"reason\" or \"error\": the application cannot tell why");
    for (auto& p : check_table19_reason(dtu)) out.push_back(std::move(p));
    return out;
}

Problems check_envelope(const Json& dtu, const Json& sent_id, std::string_view dev, bool guid_required) {
    Problems out;
    if (!sent_id.is_null()) {
        auto id = dtu.find("@id");
        if (id == dtu.end())
            out.push_back(fmt::format("\"@id\" is missing; the request's {} must be echoed (8.1.3)", show(sent_id)));
        else if (*id != sent_id)
            out.push_back(fmt::format("\"@id\" is {}, the request's was {} (8.1.3: echo it verbatim)", show(*id), show(sent_id)));
    }
    auto guid = dtu.find("guid");
    if (guid == dtu.end()) {
        if (guid_required) out.push_back(fmt::format("\"guid\" is missing (expected \"{}\")", dev));
    } else if (!guid->is_string() || guid->get<std::string>() != dev) {
        out.push_back(fmt::format("\"guid\" is {}, expected \"{}\"", show(*guid), dev));
    }
    return out;
}

Problems check_register_response(const Json& dtu, const Json& sent_id, std::string_view cli_uuid) {
    Problems out = check_envelope(dtu, sent_id, cli_uuid, false);
    add_all(out, check_status_keys(dtu));
    expect_string(out, dtu, "cli_uuid", cli_uuid, "table 22");
    if (dtu.contains("code") && !is_ok(dtu))
        out.push_back(fmt::format("registration refused: {}", show(dtu.value("reason", Json("(no reason)")))));
    return out;
}

Problems check_discovery_response(const Json& dtu, const Json& sent_id, std::string_view ex, std::string_view dev) {
    Problems out = check_envelope(dtu, sent_id, ex, true);
    add_all(out, check_status_keys(dtu));
    if (dtu.contains("code") && !is_ok(dtu)) {
        out.push_back(fmt::format("discovery refused: {}", show(dtu.value("reason", Json("(no reason)")))));
        return out;
    }
    auto list = dtu.find("deviceList");
    if (list == dtu.end()) {
        out.push_back("\"deviceList\" is missing (table 24: present, null when no adapter is accessible)");
        return out;
    }
    if (list->is_null()) {
        out.push_back(fmt::format("\"deviceList\" is null: the adapter \"{}\" is not discovered", dev));
        return out;
    }
    if (!list->is_array()) {
        out.push_back(fmt::format("\"deviceList\" is {}, not an array", show(*list)));
        return out;
    }
    bool found = false;
    for (std::size_t i = 0; i < list->size(); ++i) {
        const Json& e = (*list)[i];
        const std::string where = fmt::format("deviceList[{}]: ", i);
        if (!e.is_object()) {
            out.push_back(where + "not an object");
            continue;
        }
        auto guid = str(e, "guid");
        if (!guid) out.push_back(where + "\"guid\" missing or not a string (table 25)");
        auto status = str(e, "status");
        if (!status || (*status != "online" && *status != "offline" && *status != "unknown"))
            out.push_back(where + fmt::format("\"status\" is {}, expected online/offline/unknown (table 25)",
                                              show(e.value("status", Json()))));
        auto stamp = str(e, "lastAliveTimeStamp");
        if (!stamp || stamp->empty() || !std::all_of(stamp->begin(), stamp->end(), [](char c) { return c >= '0' && c <= '9'; }))
            out.push_back(where + fmt::format("\"lastAliveTimeStamp\" is {}, expected seconds as a string (table 25)",
                                              show(e.value("lastAliveTimeStamp", Json()))));
        if (guid && *guid == dev) found = true;
    }
    if (!found) out.push_back(fmt::format("the adapter \"{}\" is not in deviceList", dev));
    return out;
}

ProbeCheck check_probe_response(const Json& dtu, const Json& sent_id, std::string_view dev) {
    ProbeCheck out;
    out.problems = response_basics(dtu, sent_id, dev, false);  // table 29 has no guid
    if (!is_ok(dtu)) {
        out.problems.push_back(fmt::format("Probe/Query answered {}: {}", show(dtu.value("code", Json())),
                                           show(dtu.value("reason", Json("(no reason)")))));
        return out;
    }
    auto probe = dtu.find("probe");
    if (probe == dtu.end()) {
        out.problems.push_back("\"probe\" is missing (table 29: required when code is OK)");
    } else if (probe->is_object()) {
        out.model = *probe;
    } else if (probe->is_string()) {
        // The standard's example sends the text; docs/wire.md: we send an object and accept both.
        std::string why;
        auto parsed = parse_object(probe->get_ref<const std::string&>(), &why);
        if (parsed) out.model = std::move(*parsed);
        else out.problems.push_back("\"probe\" is a string that is " + why);
    } else {
        out.problems.push_back(fmt::format("\"probe\" is {}, not an object", probe->type_name()));
    }
    return out;
}

const Device* device_for(const Model& model, std::string_view dev) {
    for (const auto& d : model.devices())
        if (resolve_dev_uuid(d) == dev || d.id == dev) return &d;
    return model.devices().size() == 1 ? &model.devices().front() : nullptr;
}

std::vector<const DataObject*> served_items(const Model& model, const Device& device) {
    std::vector<const DataObject*> out;
    for (const auto& item : model.data_objects())
        if (item.device_id == device.id || item.device_id.empty()) out.push_back(&item);
    return out;
}

ObjectCounts count_objects(const Model& model) {
    ObjectCounts c;
    for (const auto& comp : model.components()) {
        if (model_detail::is_component_type(comp.type)) ++c.components_standard;
        else ++c.components_custom;
    }
    for (const auto& item : model.data_objects()) {
        if (model_detail::is_data_type(item.type)) ++c.data_standard;
        else ++c.data_custom;
    }
    c.channels = model.channels().size();
    c.methods = model.methods().size();
    return c;
}

std::string bump_version(std::string_view version) {
    if (version.empty()) return "1.0.1";
    std::string prefix;
    std::string_view rest = version;
    if (rest.front() == 'v' || rest.front() == 'V') {
        prefix = std::string(1, rest.front());
        rest.remove_prefix(1);
    }
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const auto dot = rest.find('.', start);
        parts.emplace_back(rest.substr(start, dot == std::string_view::npos ? std::string_view::npos : dot - start));
        if (dot == std::string_view::npos) break;
        start = dot + 1;
    }
    const bool numeric = std::all_of(parts.begin(), parts.end(), [](const std::string& p) {
        return !p.empty() && p.size() < 9 && std::all_of(p.begin(), p.end(), [](char c) { return c >= '0' && c <= '9'; });
    });
    if (!numeric) return std::string(version) + ".1";
    while (parts.size() < 3) parts.emplace_back("0");
    parts.back() = std::to_string(std::stol(parts.back()) + 1);
    std::string out = prefix;
    for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? "." : "") + parts[i];
    return out;
}

// ---- Query / Set ------------------------------------------------------------------

namespace {

Problems check_result_list(const Json& dtu, const char* key, const std::vector<std::string>& ids, bool query) {
    Problems out;
    auto list = dtu.find(key);
    if (list == dtu.end() && !query) list = dtu.find("values");  // 8.2.14 example 3 says "values"
    if (list == dtu.end()) {
        out.push_back(fmt::format("\"{}\" is missing", key));
        return out;
    }
    if (!list->is_array()) {
        out.push_back(fmt::format("\"{}\" is {}, not an array", key, list->type_name()));
        return out;
    }
    if (list->size() != ids.size())
        out.push_back(
            fmt::format("\"{}\" has {} entries for {} requested items (8.2.12, docs/wire.md: exactly one per item, in order)",
                        key, list->size(), ids.size()));
    const std::size_t n = std::min(list->size(), ids.size());
    for (std::size_t i = 0; i < n; ++i) {
        const Json& e = (*list)[i];
        const std::string where = fmt::format("{}[{}] ({}): ", key, i, ids[i]);
        if (!e.is_object()) {
            out.push_back(where + "not an object");
            continue;
        }
        auto id = str(e, "id");
        if (!id) out.push_back(where + "\"id\" missing or not a string");
        else if (*id != ids[i]) out.push_back(where + fmt::format("\"id\" is \"{}\" (answers must come in request order)", *id));
        add_all(out, check_status_keys(e), where);
        if (query && is_ok(e)) {
            auto values = e.find("values");
            if (values == e.end()) out.push_back(where + "code OK without \"values\"");
            else if (!values->is_array())
                out.push_back(where + fmt::format("\"values\" is {}, not an array (docs/wire.md: always an array)", show(*values)));
        }
    }
    return out;
}

}  // namespace

Problems check_query_response(const Json& dtu, const Json& sent_id, std::string_view dev, const std::vector<std::string>& ids) {
    Problems out = check_envelope(dtu, sent_id, dev, true);
    if (dtu.contains("code") && !is_ok(dtu) && !dtu.contains("values")) {
        out.push_back(fmt::format("the whole Query was refused: {}", show(dtu)));
        return out;
    }
    add_all(out, check_result_list(dtu, "values", ids, true));
    return out;
}

Problems check_set_response(const Json& dtu, const Json& sent_id, std::string_view dev, const std::vector<std::string>& ids) {
    Problems out = check_envelope(dtu, sent_id, dev, true);
    if (dtu.contains("code") && !is_ok(dtu) && !dtu.contains("results") && !dtu.contains("values")) {
        out.push_back(fmt::format("the whole Set was refused: {}", show(dtu)));
        return out;
    }
    add_all(out, check_result_list(dtu, "results", ids, false));
    return out;
}

const Json* result_entry(const Json& dtu, std::size_t index) {
    for (const char* key : {"values", "results"}) {
        auto list = dtu.find(key);
        if (list != dtu.end() && list->is_array() && index < list->size() && (*list)[index].is_object()) return &(*list)[index];
    }
    return nullptr;
}

Problems check_whole_value(const DataObject& item, const Json& values) {
    Problems out;
    if (!values.is_array()) {
        out.push_back(fmt::format("\"values\" is {}, not an array", show(values)));
        return out;
    }
    if (values.size() != 1) {
        out.push_back(fmt::format("a whole-item query answered {} values; expected [value] (docs/values.md): {}", values.size(),
                                  show(values)));
        return out;
    }
    const Json& v = values[0];
    if (item.kind == DataKind::list && !v.is_array() && !v.is_null())
        out.push_back(fmt::format("list item answered {} ({}), not an array", show(v), v.type_name()));
    if (item.kind == DataKind::dict && !v.is_object() && !v.is_null())
        out.push_back(fmt::format("dict item answered {} ({}), not an object", show(v), v.type_name()));
    if (item.value && v != *item.value)
        out.push_back(fmt::format("the model fixes the value {}, the adapter answered {}", show(*item.value), show(v)));
    return out;
}

Problems check_list_length(const Json& values, const Json& whole) {
    Problems out;
    if (!values.is_array() || values.size() != 1 || !values[0].is_number_integer() || values[0].get<std::int64_t>() < 0) {
        out.push_back(fmt::format("get_length answered {}, expected [n] with n a non-negative integer", show(values)));
        return out;
    }
    if (whole.is_array() && values[0].get<std::size_t>() != whole.size())
        out.push_back(fmt::format("get_length answered {} but the whole list has {} elements", values[0].get<std::int64_t>(),
                                  whole.size()));
    return out;
}

Problems check_dict_keys(const Json& values, const Json& whole) {
    Problems out;
    if (!values.is_array() || !std::all_of(values.begin(), values.end(), [](const Json& k) { return k.is_string(); })) {
        out.push_back(fmt::format("get_keys answered {}, expected an array of strings", show(values)));
        return out;
    }
    if (whole.is_object()) {
        std::set<std::string> answered, expected;
        for (const auto& k : values) answered.insert(k.get<std::string>());
        for (auto it = whole.begin(); it != whole.end(); ++it) expected.insert(it.key());
        if (answered != expected)
            out.push_back(fmt::format("get_keys answered {} keys, the whole dict has {} keys{}", answered.size(), expected.size(),
                                      answered.size() == expected.size() ? " (different ones)" : ""));
    }
    return out;
}

// ---- sampling ------------------------------------------------------------------------

Problems check_sample_register_response(const Json& dtu, const Json& sent_id, std::string_view dev) {
    Problems out = response_basics(dtu, sent_id, dev, true);
    if (is_ok(dtu)) {
        auto id = str(dtu, "id");
        if (!id || id->empty()) out.push_back("code OK without a channel \"id\" (table 39)");
    } else {
        for (auto& p : check_id_in_refusal(dtu, "table 39")) out.push_back(std::move(p));
    }
    return out;
}

Problems check_unregister_response(const Json& dtu, const Json& sent_id, std::string_view dev) {
    return response_basics(dtu, sent_id, dev, true);
}

Problems check_event_register_response(const Json& dtu, const Json& sent_id, std::string_view dev) {
    Problems out = response_basics(dtu, sent_id, dev, true);
    if (is_ok(dtu)) {
        auto id = str(dtu, "id");
        if (!id || id->empty()) out.push_back("code OK without an event \"id\" (table 49)");
    } else {
        for (auto& p : check_id_in_refusal(dtu, "table 49")) out.push_back(std::move(p));
    }
    return out;
}

Problems check_event_data(const Json& dtu, std::string_view dev, std::string_view event_id, std::string_view item_id) {
    Problems out = check_envelope(dtu, Json(), dev, true);
    if (!dtu.contains("@id")) out.push_back("\"@id\" is missing (table 52: it shall be present)");
    expect_string(out, dtu, "id", event_id, "table 52");
    auto time = dtu.find("time");
    if (time == dtu.end()) out.push_back("\"time\" is missing (table 52)");
    else if (!time->is_number_integer())
        out.push_back(fmt::format("\"time\" is {}, expected a number of milliseconds (table 52)", show(*time)));
    else if (!plausible_epoch_ms(time->get<std::int64_t>()))
        out.push_back(fmt::format("\"time\" {} is not milliseconds since the epoch", time->get<std::int64_t>()));
    auto body = dtu.find("event");
    if (body == dtu.end() || !body->is_object()) {
        out.push_back("\"event\" is missing or not an object (table 52, figure 17)");
        return out;
    }
    expect_string(out, *body, "id", item_id, "figure 17");
    if (!body->contains("value")) out.push_back("\"event\" has no \"value\" (figure 17)");
    return out;
}

Problems check_method_status(const Json& dtu, std::string_view dev, std::string_view method_id) {
    Problems out = check_envelope(dtu, Json(), dev, true);
    expect_string(out, dtu, "id", method_id, "table 44");
    auto status = str(dtu, "status");
    if (!status || (*status != "waiting" && *status != "executing" && *status != "stopped" && *status != "sleep"))
        out.push_back(fmt::format("\"status\" is {}, expected waiting/executing/stopped/sleep (table 44)",
                                  show(dtu.value("status", Json()))));
    for (const char* key : {"progress", "process"})
        if (auto it = dtu.find(key); it != dtu.end() && !it->is_number())
            out.push_back(fmt::format("\"{}\" is {}, not a number (table 44)", key, show(*it)));
    return out;
}

Problems check_method_result(const Json& dtu, const Json& sent_id, std::string_view dev, std::string_view method_id) {
    Problems out = response_basics(dtu, sent_id, dev, true);
    expect_string(out, dtu, "id", method_id, "table 45");
    auto result = str(dtu, "result");
    if (!result || (*result != "finished" && *result != "canceled" && *result != "error"))
        out.push_back(
            fmt::format("\"result\" is {}, expected finished/canceled/error (table 45)", show(dtu.value("result", Json()))));
    if (result && *result == "finished" && dtu.contains("code") && !is_ok(dtu)) out.push_back("result \"finished\" with code NG");
    return out;
}

Problems check_method_control_response(const Json& dtu, const Json& sent_id, std::string_view dev, std::string_view method_id) {
    Problems out = response_basics(dtu, sent_id, dev, true);
    expect_string(out, dtu, "id", method_id, "table 47");
    return out;
}

Problems check_notify_state(const Message& message, std::string_view dev) {
    Problems out;
    std::string why;
    auto dtu = parse_object(message.payload, &why);
    if (!dtu) {
        out.push_back("Notify/State payload is " + why);
        return out;
    }
    if (auto tid = dtu->find("tid"); tid != dtu->end() && (!tid->is_string() || tid->get<std::string>() != dev))
        out.push_back(fmt::format("\"tid\" is {}, expected \"{}\" (table 37)", show(*tid), dev));
    auto state = str(*dtu, "state");
    if (!state) out.push_back("\"state\" is missing or not a string (table 37)");
    else if (*state != "online")
        out.push_back(fmt::format("\"state\" is \"{}\" while the adapter is serving; expected \"online\"", *state));
    if (!message.retained)
        out.push_back("Notify/State is not retained (docs/wire.md: retained, so late subscribers see the current state)");
    return out;
}

}  // namespace nclink::conform
