#include "agent/access.hpp"

#include <fmt/format.h>

namespace nclink::agent_detail {

std::optional<AccessRight> required_right(TopicKind kind) noexcept {
    switch (kind) {
        case TopicKind::probe_query_request:
        case TopicKind::query_request:
        case TopicKind::sample_register_request:
        case TopicKind::sample_unregister_request:
        case TopicKind::event_register_request:
        case TopicKind::event_unregister_request: return access_read;
        case TopicKind::probe_set_request:
        case TopicKind::set_request: return access_set;
        case TopicKind::method_call:
        case TopicKind::method_control_request: return access_method;
        default: return std::nullopt;
    }
}

const std::vector<TopicKind>& adapter_request_kinds() {
    static const std::vector<TopicKind> kinds = {TopicKind::probe_query_request,
                                                 TopicKind::probe_set_request,
                                                 TopicKind::query_request,
                                                 TopicKind::set_request,
                                                 TopicKind::sample_register_request,
                                                 TopicKind::sample_unregister_request,
                                                 TopicKind::method_call,
                                                 TopicKind::method_control_request,
                                                 TopicKind::event_register_request,
                                                 TopicKind::event_unregister_request};
    return kinds;
}

unsigned rights_of(const AccessPolicy& policy, const std::string& ex, const std::string& dev) {
    const auto app = policy.applications.find(ex);
    if (app == policy.applications.end()) return policy.default_rights;
    if (const auto exact = app->second.find(dev); exact != app->second.end()) return exact->second;
    if (const auto any = app->second.find("*"); any != app->second.end()) return any->second;
    return access_none;
}

Result<unsigned> parse_rights(const Json& value, const std::string& where, const std::string& pointer) {
    auto fail = [&](std::string message) {
        Error e = make_error(ErrorCode::value_type, std::move(message));
        e.pointer = pointer;
        return e;
    };
    auto one = [&](const std::string& name) -> Result<unsigned> {
        if (name == "read") return static_cast<unsigned>(access_read);
        if (name == "set") return static_cast<unsigned>(access_set);
        if (name == "method") return static_cast<unsigned>(access_method);
        if (name == "watch") return static_cast<unsigned>(access_watch);
        if (name == "all") return static_cast<unsigned>(access_all);
        if (name == "none") return static_cast<unsigned>(access_none);
        return fail(fmt::format("configuration: {}: unknown right '{}' (read, set, method, watch, all, none)", where, name));
    };
    if (value.is_string()) return one(value.get<std::string>());
    if (!value.is_array()) return fail(fmt::format("configuration: {} must be a list of rights", where));
    unsigned bits = access_none;
    for (const auto& item : value) {
        if (!item.is_string()) return fail(fmt::format("configuration: {} must be a list of rights", where));
        auto bit = one(item.get<std::string>());
        if (!bit) return std::move(bit).error();
        bits |= *bit;
    }
    return bits;
}

std::vector<std::string> right_names(unsigned rights) {
    std::vector<std::string> out;
    if (rights & access_read) out.emplace_back("read");
    if (rights & access_set) out.emplace_back("set");
    if (rights & access_method) out.emplace_back("method");
    if (rights & access_watch) out.emplace_back("watch");
    return out;
}

}  // namespace nclink::agent_detail
