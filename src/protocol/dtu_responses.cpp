// Response DTUs (the adapter's answers, and the agent's Register/Discovery/
// Probe-Version answers and DEV_UNREACHABLE): liberal decode, strict encode,
// and the error answer for requests that cannot be decoded.
#include "protocol/dtu_codec.hpp"

namespace nclink {
namespace protocol_detail {

namespace {

void put_header(Json& out, const MessageId& msg_id, const std::string& guid) {
    put_msg_id(out, msg_id);
    put_if(out, "guid", guid);
}

/// "id" is required on success (even if empty); a refusal may have none.
// Tables 39, 47 and 49: `id` is present in every answer, also a refusal
// (then "" when nothing was allocated: docs/wire.md).
void put_id(Json& out, const std::string& id, const ResponseStatus& /*status*/) { out["id"] = id; }

}  // namespace

RegisterResponse read(const Json& dtu, Tag<RegisterResponse>) {
    Reader r(dtu, {"@id", "cli_uuid", "code", "reason", "error", "privateInfo"}, "Register response");
    RegisterResponse out;
    out.msg_id = r.message_id();
    out.cli_uuid = r.require_string("cli_uuid");
    out.status = r.status();
    out.private_info = r.private_info();
    return out;
}

DiscoveryResponse read(const Json& dtu, Tag<DiscoveryResponse>) {
    Reader r(dtu, {"@id", "guid", "code", "reason", "error", "deviceList", "privateInfo"}, "Discovery response");
    DiscoveryResponse out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    out.status = r.status();
    // Liberal: a missing deviceList reads like null (no accessible adapter).
    const Json* list = r.find("deviceList");
    if (list && !list->is_null()) {
        if (!list->is_array()) r.wrong_type("deviceList", "an array or null");
        out.device_list.emplace();
        for (const Json& entry : *list) {
            Reader e(expect_object(entry, ErrorCode::value_type, "deviceList entry"),
                     {"guid", "status", "lastAliveTimeStamp", "privateInfo"}, "deviceList entry");
            DeviceListEntry device;
            device.guid = e.require_string("guid");
            device.status = e.require_string("status");
            // Seconds as a string per table 25; a number is taken too.
            const Json& stamp = e.require("lastAliveTimeStamp");
            if (stamp.is_string()) device.last_alive_time_stamp = stamp.get<std::string>();
            else if (stamp.is_number_integer()) device.last_alive_time_stamp = stamp.dump();
            else e.wrong_type("lastAliveTimeStamp", "a string");
            device.private_info = e.private_info();
            out.device_list->push_back(std::move(device));
        }
    }
    out.private_info = r.private_info();
    return out;
}

ProbeVersionResponse read(const Json& dtu, Tag<ProbeVersionResponse>) {
    Reader r(dtu, {"@id", "guid", "code", "reason", "error", "version", "privateInfo"}, "Probe/Version response");
    ProbeVersionResponse out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    out.status = r.optional_status();
    out.version = r.optional_string("version");
    out.private_info = r.private_info();
    return out;
}

ProbeQueryResponse read(const Json& dtu, Tag<ProbeQueryResponse>) {
    Reader r(dtu, {"@id", "guid", "code", "reason", "error", "probe", "privateInfo"}, "Probe/Query response");
    ProbeQueryResponse out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    out.status = r.status();
    if (const Json* probe = r.find("probe"); probe && !probe->is_null()) out.probe = probe_value(*probe, r.what());
    out.private_info = r.private_info();
    return out;
}

ProbeSetResponse read(const Json& dtu, Tag<ProbeSetResponse>) {
    Reader r(dtu, {"@id", "guid", "code", "reason", "error", "privateInfo"}, "Probe/Set response");
    ProbeSetResponse out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    out.status = r.status();
    out.private_info = r.private_info();
    return out;
}

QueryResponse read(const Json& dtu, Tag<QueryResponse>) {
    Reader r(dtu, {"@id", "guid", "values", "code", "reason", "error", "privateInfo"}, "Query response");
    QueryResponse out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    out.status = r.optional_status();
    // A whole-request refusal may come without values.
    if (!out.status || r.has("values")) {
        for (const Json& entry : r.require_array("values")) {
            Reader e(expect_object(entry, ErrorCode::value_type, "values entry"),
                     {"id", "code", "reason", "error", "params", "values", "privateInfo"}, "values entry");
            QueryResult result;
            result.id = e.require_string("id");
            result.status = e.status();
            result.params = e.optional_any("params");
            result.values = e.optional_any("values");
            result.private_info = e.private_info();
            out.values.push_back(std::move(result));
        }
    }
    out.private_info = r.private_info();
    return out;
}

SetResponse read(const Json& dtu, Tag<SetResponse>) {
    Reader r(dtu, {"@id", "guid", "results", "values", "code", "reason", "error", "privateInfo"}, "Set response");
    SetResponse out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    out.status = r.optional_status();
    // 8.2.14 example 3 names the list "values": take it when "results" is absent.
    const char* key = !r.has("results") && r.has("values") ? "values" : "results";
    if (!out.status || r.has(key)) {
        for (const Json& entry : r.require_array(key)) {
            Reader e(expect_object(entry, ErrorCode::value_type, "results entry"),
                     {"id", "code", "reason", "error", "params", "privateInfo"}, "results entry");
            SetResult result;
            result.id = e.require_string("id");
            result.status = e.status();
            result.params = e.optional_any("params");
            result.private_info = e.private_info();
            out.results.push_back(std::move(result));
        }
    }
    out.private_info = r.private_info();
    return out;
}

namespace {

template <class T>
T read_id_status(const Json& dtu, std::string_view what, bool with_id) {
    Reader r(dtu, {"@id", "guid", "id", "code", "reason", "error", "privateInfo"}, what);
    T out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    if constexpr (std::is_same_v<T, SampleRegisterResponse> || std::is_same_v<T, EventRegisterResponse> ||
                  std::is_same_v<T, MethodControlResponse>) {
        // The id is required on success; a refusal may have no id to give.
        out.status = r.status();
        if (with_id && out.status.ok) out.id = r.require_string("id");
        else out.id = r.string_or_empty("id");
    } else {
        out.status = r.status();
    }
    out.private_info = r.private_info();
    return out;
}

}  // namespace

SampleRegisterResponse read(const Json& dtu, Tag<SampleRegisterResponse>) {
    return read_id_status<SampleRegisterResponse>(dtu, "Register/Sample response", true);
}
SampleUnregisterResponse read(const Json& dtu, Tag<SampleUnregisterResponse>) {
    return read_id_status<SampleUnregisterResponse>(dtu, "Unregister/Sample response", false);
}
MethodControlResponse read(const Json& dtu, Tag<MethodControlResponse>) {
    return read_id_status<MethodControlResponse>(dtu, "Method/Control response", true);
}
EventRegisterResponse read(const Json& dtu, Tag<EventRegisterResponse>) {
    return read_id_status<EventRegisterResponse>(dtu, "Register/Event response", true);
}
EventUnregisterResponse read(const Json& dtu, Tag<EventUnregisterResponse>) {
    return read_id_status<EventUnregisterResponse>(dtu, "Unregister/Event response", false);
}

DevUnreachable read(const Json& dtu, Tag<DevUnreachable>) {
    Reader r(dtu, {"@id", "dev_uuid", "cli_uuid", "code", "reason", "error", "privateInfo"}, "DEV_UNREACHABLE");
    DevUnreachable out;
    out.msg_id = r.message_id();
    out.dev_uuid = r.require_string("dev_uuid");
    out.cli_uuid = r.require_string("cli_uuid");
    out.status = r.status();
    out.private_info = r.private_info();
    return out;
}

}  // namespace protocol_detail

using namespace protocol_detail;

NCLINK_DEFINE_DECODE(RegisterResponse, false)
NCLINK_DEFINE_DECODE(DiscoveryResponse, false)
NCLINK_DEFINE_DECODE(ProbeVersionResponse, false)
NCLINK_DEFINE_DECODE(ProbeQueryResponse, false)
NCLINK_DEFINE_DECODE(ProbeSetResponse, false)
NCLINK_DEFINE_DECODE(QueryResponse, false)
NCLINK_DEFINE_DECODE(SetResponse, false)
NCLINK_DEFINE_DECODE(SampleRegisterResponse, false)
NCLINK_DEFINE_DECODE(SampleUnregisterResponse, false)
NCLINK_DEFINE_DECODE(MethodControlResponse, false)
NCLINK_DEFINE_DECODE(EventRegisterResponse, false)
NCLINK_DEFINE_DECODE(EventUnregisterResponse, false)
NCLINK_DEFINE_DECODE(DevUnreachable, false)

Json to_json(const RegisterResponse& dtu) {
    Json out = Json::object();
    put_msg_id(out, dtu.msg_id);
    out["cli_uuid"] = dtu.cli_uuid;
    put_status(out, dtu.status);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const DiscoveryResponse& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    put_status(out, dtu.status);
    if (dtu.device_list) {
        Json list = Json::array();
        for (const auto& device : *dtu.device_list) {
            Json entry = {{"guid", device.guid}, {"status", device.status}, {"lastAliveTimeStamp", device.last_alive_time_stamp}};
            put_if(entry, "privateInfo", device.private_info);
            list.push_back(std::move(entry));
        }
        out["deviceList"] = std::move(list);
    } else {
        out["deviceList"] = nullptr;  // required key; null = no accessible adapter
    }
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const ProbeVersionResponse& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    if (dtu.status) put_status(out, *dtu.status);
    put_if(out, "version", dtu.version);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const ProbeQueryResponse& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    put_status(out, dtu.status);
    put_if(out, "probe", dtu.probe);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const ProbeSetResponse& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    put_status(out, dtu.status);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const QueryResponse& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    if (dtu.status) put_status(out, *dtu.status);
    Json values = Json::array();
    for (const auto& result : dtu.values) {
        Json entry = {{"id", result.id}};
        put_status(entry, result.status);
        put_if(entry, "params", result.params);
        put_if(entry, "values", result.values);
        put_if(entry, "privateInfo", result.private_info);
        values.push_back(std::move(entry));
    }
    out["values"] = std::move(values);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const SetResponse& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    if (dtu.status) put_status(out, *dtu.status);
    Json results = Json::array();
    for (const auto& result : dtu.results) {
        Json entry = {{"id", result.id}};
        put_status(entry, result.status);
        put_if(entry, "params", result.params);
        put_if(entry, "privateInfo", result.private_info);
        results.push_back(std::move(entry));
    }
    out["results"] = std::move(results);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

namespace {

// The answers of dynamic sampling, events and method control share one shape:
// header (@id, guid), the channel/event/method id when the DTU has one, status.
template <class Dtu>
Json header_id_status_json(const Dtu& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    put_id(out, dtu.id, dtu.status);
    put_status(out, dtu.status);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

template <class Dtu>
Json header_status_json(const Dtu& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    put_status(out, dtu.status);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

}  // namespace

Json to_json(const SampleRegisterResponse& dtu) { return header_id_status_json(dtu); }

Json to_json(const SampleUnregisterResponse& dtu) { return header_status_json(dtu); }

Json to_json(const MethodControlResponse& dtu) { return header_id_status_json(dtu); }

Json to_json(const EventRegisterResponse& dtu) { return header_id_status_json(dtu); }

Json to_json(const EventUnregisterResponse& dtu) { return header_status_json(dtu); }

Json to_json(const DevUnreachable& dtu) {
    Json out = Json::object();
    put_msg_id(out, dtu.msg_id);
    out["dev_uuid"] = dtu.dev_uuid;
    out["cli_uuid"] = dtu.cli_uuid;
    put_status(out, dtu.status);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

std::optional<Json> make_error_reply(TopicKind request_kind, const MessageId& msg_id, std::string_view dev, const Error& error) {
    const ResponseStatus status(error);
    const std::string guid(dev);
    auto reply = [&](auto response) -> Json {
        response.msg_id = msg_id;
        response.guid = guid;
        response.status = status;
        return to_json(response);
    };
    switch (request_kind) {
        case TopicKind::register_request: {
            RegisterResponse response;
            response.msg_id = msg_id;
            response.cli_uuid = guid;
            response.status = status;
            return to_json(response);
        }
        case TopicKind::discovery_request: {
            DiscoveryResponse response;  // deviceList null: nothing accessible
            return reply(response);
        }
        case TopicKind::probe_query_request: return reply(ProbeQueryResponse{});
        case TopicKind::probe_set_request: return reply(ProbeSetResponse{});
        case TopicKind::query_request: return reply(QueryResponse{});
        case TopicKind::set_request: return reply(SetResponse{});
        case TopicKind::sample_register_request: return reply(SampleRegisterResponse{});
        case TopicKind::sample_unregister_request: return reply(SampleUnregisterResponse{});
        case TopicKind::method_call: {
            MethodResult result;
            result.result = "error";
            return reply(result);
        }
        case TopicKind::method_control_request: return reply(MethodControlResponse{});
        case TopicKind::event_register_request: return reply(EventRegisterResponse{});
        case TopicKind::event_unregister_request: return reply(EventUnregisterResponse{});
        default: return std::nullopt;
    }
}

}  // namespace nclink
