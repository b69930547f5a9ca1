// DTUs an adapter publishes on its own (subscribe/publish mode): Sample (DOM
// form), Notify/State, Method/Status, Method/Result and Event data.
#include "protocol/dtu_codec.hpp"

#include <charconv>

namespace nclink {
namespace protocol_detail {

namespace {

void put_header(Json& out, const MessageId& msg_id, const std::string& guid) {
    put_msg_id(out, msg_id);
    put_if(out, "guid", guid);
}

}  // namespace

SampleDtu read(const Json& dtu, Tag<SampleDtu>) {
    Reader r(dtu, {"@id", "guid", "id", "beginTime", "data", "privateInfo"}, "Sample");
    SampleDtu out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");  // 8.2.21's example omits it
    out.id = r.require_string("id");
    out.begin_time = r.require_integer("beginTime");  // string per table 36; a number is taken too
    for (const Json& point : r.require_array("data")) {
        if (point.is_array()) {  // liberal: a bare column
            out.data.push_back(point);
            continue;
        }
        Reader p(expect_object(point, ErrorCode::value_type, "data entry"), {"data"}, "data entry");
        out.data.push_back(p.require_array("data"));
    }
    out.private_info = r.private_info();
    return out;
}

NotifyState read(const Json& dtu, Tag<NotifyState>) {
    Reader r(dtu, {"tid", "state"}, "Notify/State");
    NotifyState out;
    out.tid = r.string_or_empty("tid");
    out.state = r.string_or_empty("state");
    return out;
}

MethodStatus read(const Json& dtu, Tag<MethodStatus>) {
    Reader r(dtu, {"@id", "guid", "id", "status", "progress", "process", "privateInfo"}, "Method/Status");
    MethodStatus out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    out.id = r.require_string("id");
    out.status = r.require_string("status");
    // 8.2.23's example spells the key "process".
    out.progress = r.has("progress") ? r.optional_number("progress") : r.optional_number("process");
    out.private_info = r.private_info();
    return out;
}

MethodResult read(const Json& dtu, Tag<MethodResult>) {
    Reader r(dtu, {"@id", "guid", "id", "result", "code", "reason", "error", "return", "privateInfo"}, "Method/Result");
    MethodResult out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    out.id = r.string_or_empty("id");  // a refusal of an undecodable call has no id
    out.result = r.require_string("result");
    out.status = r.status();
    out.return_value = r.optional_any("return");
    out.private_info = r.private_info();
    return out;
}

EventData read(const Json& dtu, Tag<EventData>) {
    Reader r(dtu, {"@id", "guid", "id", "time", "event", "privateInfo"}, "Event");
    EventData out;
    out.msg_id = r.message_id();
    out.guid = r.string_or_empty("guid");
    out.id = r.require_string("id");
    out.time = r.require_integer("time");
    const Json& body = r.require("event");
    if (!body.is_object()) r.wrong_type("event", "an object");
    Reader e(body, {"id", "value", "oldValue", "key", "index"}, "event body");
    out.event.id = e.require_string("id");
    out.event.value = e.require("value");
    out.event.old_value = e.optional_any("oldValue");
    out.event.key = e.optional_string("key");
    out.event.index = e.optional_integer("index");
    out.private_info = r.private_info();
    return out;
}

}  // namespace protocol_detail

using namespace protocol_detail;

NCLINK_DEFINE_DECODE(SampleDtu, false)
NCLINK_DEFINE_DECODE(NotifyState, false)
NCLINK_DEFINE_DECODE(MethodStatus, false)
NCLINK_DEFINE_DECODE(MethodResult, false)
NCLINK_DEFINE_DECODE(EventData, false)

Json to_json(const SampleDtu& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["id"] = dtu.id;
    char text[24];
    const auto end = std::to_chars(text, text + sizeof text, dtu.begin_time).ptr;
    out["beginTime"] = std::string(text, end);
    Json data = Json::array();
    for (const auto& column : dtu.data) data.push_back({{"data", column}});
    out["data"] = std::move(data);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const NotifyState& dtu) {
    Json out = Json::object();
    put_if(out, "tid", dtu.tid);
    put_if(out, "state", dtu.state);
    return out;
}

Json to_json(const MethodStatus& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["id"] = dtu.id;
    out["status"] = dtu.status;
    if (dtu.progress) out["progress"] = number_json(*dtu.progress);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const MethodResult& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    put_if(out, "id", dtu.id);
    out["result"] = dtu.result;
    put_status(out, dtu.status);
    put_if(out, "return", dtu.return_value);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

Json to_json(const EventData& dtu) {
    Json out = Json::object();
    put_header(out, dtu.msg_id, dtu.guid);
    out["id"] = dtu.id;
    out["time"] = dtu.time;
    Json body = {{"id", dtu.event.id}, {"value", dtu.event.value}};
    put_if(body, "oldValue", dtu.event.old_value);
    put_if(body, "key", dtu.event.key);
    if (dtu.event.index) body["index"] = *dtu.event.index;
    out["event"] = std::move(body);
    put_if(out, "privateInfo", dtu.private_info);
    return out;
}

}  // namespace nclink
