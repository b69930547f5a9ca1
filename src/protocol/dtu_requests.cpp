// Request DTUs (what applications and agents send to an adapter, and the
// adapter's own Register/Request and Probe/Version): liberal decode, strict encode.
#include "protocol/dtu_codec.hpp"
#include "protocol/query_request_fast.hpp"
#include "protocol/set_request_fast.hpp"

#include <fmt/format.h>

namespace nclink {
namespace protocol_detail {

namespace {

/// "guid" may be omitted in requests: the topic carries the device.
std::string request_guid(const Reader& r) { return r.string_or_empty("guid"); }

void put_header(Json& out, const MessageId& msg_id, const std::string& guid) {
    put_msg_id(out, msg_id);
    put_if(out, "guid", guid);
}

/// The "id" of an ids/values entry: an object with "id" (or a bare id string for Query).
const Json& entry_object(const Json& entry, std::string_view what) { return expect_object(entry, ErrorCode::value_type, what); }

}  // namespace

RegisterRequest read(const Json& dtu, Tag<RegisterRequest>) {
    Reader r(dtu, {"@id", "cli_uuid", "privateInfo"}, "Register request");
    RegisterRequest out;
    out.msg_id = r.message_id();
    out.cli_uuid = r.require_string("cli_uuid");
    out.private_info = r.private_info();
    return out;
}

DiscoveryRequest read(const Json& dtu, Tag<DiscoveryRequest>) {
    Reader r(dtu, {"@id", "guid", "privateInfo"}, "Discovery request");
    DiscoveryRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.private_info = r.private_info();
    return out;
}

ProbeVersionRequest read(const Json& dtu, Tag<ProbeVersionRequest>) {
    Reader r(dtu, {"@id", "guid", "version", "privateInfo"}, "Probe/Version request");
    ProbeVersionRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.version = r.require_string("version");
    out.private_info = r.private_info();
    return out;
}

ProbeQueryRequest read(const Json& dtu, Tag<ProbeQueryRequest>) {
    Reader r(dtu, {"@id", "guid", "privateInfo"}, "Probe/Query request");
    ProbeQueryRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.private_info = r.private_info();
    return out;
}

ProbeSetRequest read(const Json& dtu, Tag<ProbeSetRequest>) {
    Reader r(dtu, {"@id", "guid", "probe", "privateInfo"}, "Probe/Set request");
    ProbeSetRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.probe = probe_value(r.require("probe"), r.what());
    out.private_info = r.private_info();
    return out;
}

QueryRequest read(const Json& dtu, Tag<QueryRequest>) {
    Reader r(dtu, {"@id", "guid", "ids", "privateInfo"}, "Query request");
    QueryRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    for (const Json& entry : r.require_array("ids")) {
        QueryItem item;
        if (entry.is_string()) {  // liberal: ["010203"] for [{"id":"010203"}]
            item.id = entry.get<std::string>();
        } else {
            Reader e(entry_object(entry, "ids entry"), {"id", "params"}, "ids entry");
            item.id = e.require_string("id");
            item.params = e.optional_any("params");
        }
        out.ids.push_back(std::move(item));
    }
    out.private_info = r.private_info();
    return out;
}

SetRequest read(const Json& dtu, Tag<SetRequest>) {
    Reader r(dtu, {"@id", "guid", "values", "privateInfo"}, "Set request");
    SetRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    for (const Json& entry : r.require_array("values")) {
        Reader e(entry_object(entry, "values entry"), {"id", "params", "offset", "length"}, "values entry");
        SetItem item;
        item.id = e.require_string("id");
        // A missing params is answered per item (102) by the values module.
        item.params = e.optional_any("params");
        item.offset = e.optional_any("offset");
        item.length = e.optional_any("length");
        out.values.push_back(std::move(item));
    }
    out.private_info = r.private_info();
    return out;
}

SampleRegisterRequest read(const Json& dtu, Tag<SampleRegisterRequest>) {
    Reader r(dtu, {"@id", "guid", "sampleInterval", "uploadInterval", "ids", "privateInfo"}, "Register/Sample request");
    SampleRegisterRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.sample_interval = r.require_number("sampleInterval");
    out.upload_interval = r.require_number("uploadInterval");
    for (const Json& entry : r.require_array("ids")) {
        if (entry.is_string()) {
            out.ids.push_back(entry.get<std::string>());
            continue;
        }
        Reader e(entry_object(entry, "ids entry"), {"id"}, "ids entry");
        out.ids.push_back(e.require_string("id"));
    }
    out.private_info = r.private_info();
    return out;
}

SampleUnregisterRequest read(const Json& dtu, Tag<SampleUnregisterRequest>) {
    Reader r(dtu, {"@id", "guid", "id", "privateInfo"}, "Unregister/Sample request");
    SampleUnregisterRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.id = r.require_string("id");
    out.private_info = r.private_info();
    return out;
}

MethodCall read(const Json& dtu, Tag<MethodCall>) {
    Reader r(dtu, {"@id", "guid", "id", "args", "privateInfo"}, "Method/Call");
    MethodCall out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.id = r.require_string("id");
    out.args = r.optional_any("args");
    out.private_info = r.private_info();
    return out;
}

MethodControlRequest read(const Json& dtu, Tag<MethodControlRequest>) {
    Reader r(dtu, {"@id", "guid", "id", "action", "privateInfo"}, "Method/Control request");
    MethodControlRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.id = r.require_string("id");
    out.action = r.require_string("action");
    out.private_info = r.private_info();
    return out;
}

EventRegisterRequest read(const Json& dtu, Tag<EventRegisterRequest>) {
    Reader r(dtu, {"@id", "guid", "id", "key", "index", "filters", "triggerType", "privateInfo"}, "Register/Event request");
    EventRegisterRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.id = r.require_string("id");
    out.key = r.optional_string("key");
    out.index = r.optional_integer("index");
    if (r.has("filters")) {
        const Json& filters = r.require_array("filters");
        out.filters.emplace();
        for (const Json& filter : filters) out.filters->push_back(expect_object(filter, ErrorCode::value_type, "filters entry"));
    }
    out.trigger_type = r.require_string("triggerType");
    out.private_info = r.private_info();
    return out;
}

EventUnregisterRequest read(const Json& dtu, Tag<EventUnregisterRequest>) {
    Reader r(dtu, {"@id", "guid", "id", "privateInfo"}, "Unregister/Event request");
    EventUnregisterRequest out;
    out.msg_id = r.message_id();
    out.guid = request_guid(r);
    out.id = r.require_string("id");
    out.private_info = r.private_info();
    return out;
}

}  // namespace protocol_detail

using namespace protocol_detail;

NCLINK_DEFINE_DECODE(RegisterRequest, false)
NCLINK_DEFINE_DECODE(DiscoveryRequest, false)
NCLINK_DEFINE_DECODE(ProbeVersionRequest, false)
NCLINK_DEFINE_DECODE(ProbeQueryRequest, true)  // an empty payload is a valid Probe/Query
NCLINK_DEFINE_DECODE(ProbeSetRequest, false)
// A Query decodes by streaming when it can (query_request_fast.hpp).
NCLINK_DEFINE_DECODE_FAST(QueryRequest, protocol_detail::fast_decode_query_request)
// A Set in its plain form is scanned (set_request_fast.hpp).
NCLINK_DEFINE_DECODE_FAST(SetRequest, protocol_detail::plain_decode_set_request)
NCLINK_DEFINE_DECODE(SampleRegisterRequest, false)
NCLINK_DEFINE_DECODE(SampleUnregisterRequest, false)
NCLINK_DEFINE_DECODE(MethodCall, false)
NCLINK_DEFINE_DECODE(MethodControlRequest, false)
NCLINK_DEFINE_DECODE(EventRegisterRequest, false)
NCLINK_DEFINE_DECODE(EventUnregisterRequest, false)

Json to_json(const RegisterRequest& dtu) {
    Json out = Json::object();
    put_msg_id(out, dtu.msg_id);
    out["cli_uuid"] = dtu.cli_uuid;
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const DiscoveryRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const ProbeVersionRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["version"] = dtu.version;
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const ProbeQueryRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const ProbeSetRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["probe"] = dtu.probe;
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const QueryRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    Json ids = Json::array();
    for (const auto& item : dtu.ids) {
        Json entry = {{"id", item.id}};
        put_if(entry, "params", item.params);
        ids.push_back(std::move(entry));
    }
    out["ids"] = std::move(ids);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const SetRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    Json values = Json::array();
    for (const auto& item : dtu.values) {
        Json entry = {{"id", item.id}};
        put_if(entry, "params", item.params);
        put_if(entry, "offset", item.offset);
        put_if(entry, "length", item.length);
        values.push_back(std::move(entry));
    }
    out["values"] = std::move(values);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const SampleRegisterRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["sampleInterval"] = number_json(dtu.sample_interval);
    out["uploadInterval"] = number_json(dtu.upload_interval);
    Json ids = Json::array();
    for (const auto& id : dtu.ids) ids.push_back({{"id", id}});
    out["ids"] = std::move(ids);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const SampleUnregisterRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["id"] = dtu.id;
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const MethodCall& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["id"] = dtu.id;
    put_if(out, "args", dtu.args);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const MethodControlRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["id"] = dtu.id;
    out["action"] = dtu.action;
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const EventRegisterRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["id"] = dtu.id;
    put_if(out, "key", dtu.key);
    if (dtu.index) out["index"] = *dtu.index;
    if (dtu.filters) out["filters"] = *dtu.filters;
    out["triggerType"] = dtu.trigger_type;
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const EventUnregisterRequest& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["id"] = dtu.id;
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

}  // namespace nclink
