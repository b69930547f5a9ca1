// Typed DTUs of GB/T 41970-2022 chapter 8 (table 17, 8.2.1-8.2.31, 8.3).
//
// Every struct decodes liberally (docs/wire.md "What nclink accepts": numeric "@id", omitted "guid" in
// requests, probe given as a string, empty Probe/Query payload, ...) and
// encodes strictly: spec key names, only keys that are set. The protocol
// module knows nothing of the model or of value semantics, so params, probe,
// args, return, values and filters stay Json.
//
// For each DTU type T:
//   Result<T> decode<T>(std::string_view payload) / decode<T>(const Json&)
//   Result<T> decode_<name>(...)   (named aliases of the above)
//   Json to_json(const T&)         (also nlohmann's to_json(Json&, const T&))
//   std::string encode(const T&)   (compact UTF-8 text)
// Conventions: an empty std::string means "absent" for optional string keys
// (guid of a request, guid of a response before the adapter fills it in).
// Responses built by the adapter always carry guid = dev and echo "@id"
// (see make_reply()).
#pragma once

#include <nclink/dtu_common.hpp>
#include <nclink/export.hpp>
#include <nclink/topics.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace nclink {

// ---- 8.2.1 / 8.2.2 Register ------------------------------------------------
struct NCLINK_API RegisterRequest {
    MessageId msg_id;
    std::string cli_uuid;  ///< required
    std::optional<Json> private_info;
};
struct NCLINK_API RegisterResponse {
    MessageId msg_id;
    std::string cli_uuid;  ///< required
    ResponseStatus status;
    std::optional<Json> private_info;
};

// ---- 8.2.3 / 8.2.4 Discovery -----------------------------------------------
struct NCLINK_API DiscoveryRequest {
    MessageId msg_id;
    std::string guid;  ///< ex_cid of the asking application (may be omitted: the topic carries it)
    std::optional<Json> private_info;
};
/// Table 25.
struct NCLINK_API DeviceListEntry {
    std::string guid;
    std::string status;                 ///< "online" | "offline" | "unknown"
    std::string last_alive_time_stamp;  ///< seconds, as a string
    std::optional<Json> private_info;
};
struct NCLINK_API DiscoveryResponse {
    MessageId msg_id;
    std::string guid;  ///< ex_cid
    ResponseStatus status;
    std::optional<std::vector<DeviceListEntry>> device_list;  ///< null = no accessible adapter (always sent)
    std::optional<Json> private_info;
};

// ---- 8.2.5 / 8.2.6 Probe/Version -------------------------------------------
struct NCLINK_API ProbeVersionRequest {
    MessageId msg_id;
    std::string guid;     ///< the adapter's dev
    std::string version;  ///< required
    std::optional<Json> private_info;
};
struct NCLINK_API ProbeVersionResponse {
    MessageId msg_id;
    std::string guid;
    std::optional<ResponseStatus> status;  ///< code is optional here (table 27)
    std::optional<std::string> version;
    std::optional<Json> private_info;
};

// ---- 8.2.7 - 8.2.10 Probe/Query, Probe/Set ----------------------------------
/// An empty payload and `{}` decode fine.
struct NCLINK_API ProbeQueryRequest {
    MessageId msg_id;
    std::string guid;
    std::optional<Json> private_info;
};
struct NCLINK_API ProbeQueryResponse {
    MessageId msg_id;
    std::string guid;
    ResponseStatus status;
    std::optional<Json> probe;  ///< the model, a JSON object (required when OK); decode also takes a string holding JSON
    std::optional<Json> private_info;
};
struct NCLINK_API ProbeSetRequest {
    MessageId msg_id;
    std::string guid;
    Json probe;  ///< required; a JSON object, given as an object or as a string holding JSON
    std::optional<Json> private_info;
};
struct NCLINK_API ProbeSetResponse {
    MessageId msg_id;
    std::string guid;
    ResponseStatus status;
    std::optional<Json> private_info;
};

// ---- 8.2.11 / 8.2.12 Query --------------------------------------------------
struct NCLINK_API QueryItem {
    std::string id;
    std::optional<Json> params;  ///< operation, keys, indexes, ... (values module's business)
};
struct NCLINK_API QueryRequest {
    MessageId msg_id;
    std::string guid;
    std::vector<QueryItem> ids;  ///< required; an entry may also be a bare id string (liberal)
    std::optional<Json> private_info;
};
struct NCLINK_API QueryResult {
    std::string id;
    ResponseStatus status;
    std::optional<Json> params;  ///< the request's params echoed
    std::optional<Json> values;  ///< on OK: always an array
    /// On NG from the driver: {"message": the vendor's reason} (docs/wire.md,
    /// "Vendor errors"); sent as the entry's "privateInfo".
    std::optional<Json> private_info;
};
struct NCLINK_API QueryResponse {
    MessageId msg_id;
    std::string guid;
    std::vector<QueryResult> values;  ///< one per requested item, in order
    /// Not in table 33: set only when the request as a whole is refused
    /// (undecodable), then sent as top-level code/reason/error with empty values.
    std::optional<ResponseStatus> status;
    std::optional<Json> private_info;
};

// ---- 8.2.13 / 8.2.14 Set ----------------------------------------------------
struct NCLINK_API SetItem {
    std::string id;
    std::optional<Json> params;  ///< value/values, key/keys, index/indexes, offset, length, operation
    /// Appendix A CMD_Set_Request gives offset/length beside `params` too
    /// (8.2.13 example 3 inside them): both places are read, as given.
    std::optional<Json> offset;
    std::optional<Json> length;
};
struct NCLINK_API SetRequest {
    MessageId msg_id;
    std::string guid;
    std::vector<SetItem> values;  ///< required
    std::optional<Json> private_info;
};
struct NCLINK_API SetResult {
    std::string id;
    ResponseStatus status;
    std::optional<Json> params;
    /// On NG from the driver: {"message": the vendor's reason}, as for QueryResult.
    std::optional<Json> private_info;
};
struct NCLINK_API SetResponse {
    MessageId msg_id;
    std::string guid;
    std::vector<SetResult> results;        ///< decode also takes "values" (8.2.14 example 3 says so)
    std::optional<ResponseStatus> status;  ///< whole-request refusal, as for QueryResponse
    std::optional<Json> private_info;
};

// ---- 8.2.15 / 8.2.21 Sample (model and dynamic channels) --------------------
/// The generic (DOM) form of a Sample DTU; the hot path uses SampleEncoder.
struct NCLINK_API SampleDtu {
    MessageId msg_id;
    std::string guid;
    std::string id;               ///< channel id
    std::int64_t begin_time = 0;  ///< ms since epoch; sent as a string, decode takes a string or number
    std::vector<Json> data;       ///< one array per point, values in time order
    std::optional<Json> private_info;
};

// ---- 8.2.16 Notify/State ------------------------------------------------------
struct NCLINK_API NotifyState {
    std::string tid;    ///< optional in table 37; empty = absent
    std::string state;  ///< "online" | "offline"; empty = absent
};

// ---- 8.2.17 - 8.2.20 dynamic sampling ---------------------------------------
struct NCLINK_API SampleRegisterRequest {
    MessageId msg_id;
    std::string guid;
    double sample_interval = 0;    ///< ms, required
    double upload_interval = 0;    ///< ms, required
    std::vector<std::string> ids;  ///< required; wire form [{"id": ...}]
    std::optional<Json> private_info;
};
struct NCLINK_API SampleRegisterResponse {
    MessageId msg_id;
    std::string guid;
    std::string id;  ///< channel id (empty = absent, e.g. refused)
    ResponseStatus status;
    std::optional<Json> private_info;
};
struct NCLINK_API SampleUnregisterRequest {
    MessageId msg_id;
    std::string guid;
    std::string id;  ///< channel id, required
    std::optional<Json> private_info;
};
struct NCLINK_API SampleUnregisterResponse {
    MessageId msg_id;
    std::string guid;
    ResponseStatus status;
    std::optional<Json> private_info;
};

// ---- 8.2.22 - 8.2.26 methods -------------------------------------------------
struct NCLINK_API MethodCall {
    MessageId msg_id;
    std::string guid;
    std::string id;  ///< method id, required
    std::optional<Json> args;
    std::optional<Json> private_info;
};
struct NCLINK_API MethodStatus {
    MessageId msg_id;
    std::string guid;
    std::string id;
    std::string status;              ///< waiting | executing | stopped | sleep
    std::optional<double> progress;  ///< percent; decode also takes "process" (8.2.23 example)
    std::optional<Json> private_info;
};
struct NCLINK_API MethodResult {
    MessageId msg_id;
    std::string guid;
    std::string id;
    std::string result;  ///< finished | canceled | error
    ResponseStatus status;
    std::optional<Json> return_value;  ///< "return"
    std::optional<Json> private_info;
};
struct NCLINK_API MethodControlRequest {
    MessageId msg_id;
    std::string guid;
    std::string id;
    std::string action;  ///< stop | resume | cancel (checked by the methods module: 418)
    std::optional<Json> private_info;
};
struct NCLINK_API MethodControlResponse {
    MessageId msg_id;
    std::string guid;
    std::string id;
    ResponseStatus status;
    std::optional<Json> private_info;
};

// ---- 8.2.27 - 8.2.31 events ---------------------------------------------------
struct NCLINK_API EventRegisterRequest {
    MessageId msg_id;
    std::string guid;
    std::string id;                            ///< data item id, required
    std::optional<std::string> key;            ///< dict element
    std::optional<std::int64_t> index;         ///< list element; decode takes a number or numeric string
    std::optional<std::vector<Json>> filters;  ///< each a filter object (type, from, to, value, values, variance)
    std::string trigger_type;                  ///< always | normal | once, required (checked by the events module: 420)
    std::optional<Json> private_info;
};
struct NCLINK_API EventRegisterResponse {
    MessageId msg_id;
    std::string guid;
    std::string id;  ///< event id (empty = absent, e.g. refused)
    ResponseStatus status;
    std::optional<Json> private_info;
};
struct NCLINK_API EventUnregisterRequest {
    MessageId msg_id;
    std::string guid;
    std::string id;  ///< event id, required
    std::optional<Json> private_info;
};
struct NCLINK_API EventUnregisterResponse {
    MessageId msg_id;
    std::string guid;
    ResponseStatus status;
    std::optional<Json> private_info;
};
/// Figure 17.
struct NCLINK_API EventBody {
    std::string id;  ///< data item id
    Json value;      ///< required (may be null)
    std::optional<Json> old_value;
    std::optional<std::string> key;
    std::optional<std::int64_t> index;
};
struct NCLINK_API EventData {
    MessageId msg_id;
    std::string guid;
    std::string id;         ///< event id
    std::int64_t time = 0;  ///< ms since epoch, a number
    EventBody event;
    std::optional<Json> private_info;
};

// ---- 8.3.4 / 8.3.5 (tables 53, 54) -------------------------------------------
struct NCLINK_API DevUnreachable {
    MessageId msg_id;  ///< of the application's latest request
    std::string dev_uuid;
    std::string cli_uuid;
    ResponseStatus status = ResponseStatus::failure(std::string(dev_unreachable_reason), 301);
    std::optional<Json> private_info;
};

// ---- codec declarations --------------------------------------------------------
#define NCLINK_DTU_CODEC(Type, name)                                                                                  \
    template <>                                                                                                       \
    NCLINK_API Result<Type> decode<Type>(std::string_view payload);                                                   \
    template <>                                                                                                       \
    NCLINK_API Result<Type> decode<Type>(const Json& dtu);                                                            \
    inline Result<Type> decode_##name(std::string_view payload) { return decode<Type>(payload); }                     \
    inline Result<Type> decode_##name(const Json& dtu) { return decode<Type>(dtu); }                                  \
    inline Result<Type> decode_##name(const char* payload) { return decode<Type>(std::string_view(payload)); }        \
    inline Result<Type> decode_##name(const std::string& payload) { return decode<Type>(std::string_view(payload)); } \
    NCLINK_API Json to_json(const Type& dtu);                                                                         \
    inline void to_json(Json& out, const Type& dtu) { out = to_json(dtu); }

NCLINK_DTU_CODEC(RegisterRequest, register_request)
NCLINK_DTU_CODEC(RegisterResponse, register_response)
NCLINK_DTU_CODEC(DiscoveryRequest, discovery_request)
NCLINK_DTU_CODEC(DiscoveryResponse, discovery_response)
NCLINK_DTU_CODEC(ProbeVersionRequest, probe_version_request)
NCLINK_DTU_CODEC(ProbeVersionResponse, probe_version_response)
NCLINK_DTU_CODEC(ProbeQueryRequest, probe_query_request)
NCLINK_DTU_CODEC(ProbeQueryResponse, probe_query_response)
NCLINK_DTU_CODEC(ProbeSetRequest, probe_set_request)
NCLINK_DTU_CODEC(ProbeSetResponse, probe_set_response)
NCLINK_DTU_CODEC(QueryRequest, query_request)
NCLINK_DTU_CODEC(QueryResponse, query_response)
NCLINK_DTU_CODEC(SetRequest, set_request)
NCLINK_DTU_CODEC(SetResponse, set_response)
NCLINK_DTU_CODEC(SampleDtu, sample)
NCLINK_DTU_CODEC(NotifyState, notify_state)
NCLINK_DTU_CODEC(SampleRegisterRequest, sample_register_request)
NCLINK_DTU_CODEC(SampleRegisterResponse, sample_register_response)
NCLINK_DTU_CODEC(SampleUnregisterRequest, sample_unregister_request)
NCLINK_DTU_CODEC(SampleUnregisterResponse, sample_unregister_response)
NCLINK_DTU_CODEC(MethodCall, method_call)
NCLINK_DTU_CODEC(MethodStatus, method_status)
NCLINK_DTU_CODEC(MethodResult, method_result)
NCLINK_DTU_CODEC(MethodControlRequest, method_control_request)
NCLINK_DTU_CODEC(MethodControlResponse, method_control_response)
NCLINK_DTU_CODEC(EventRegisterRequest, event_register_request)
NCLINK_DTU_CODEC(EventRegisterResponse, event_register_response)
NCLINK_DTU_CODEC(EventUnregisterRequest, event_unregister_request)
NCLINK_DTU_CODEC(EventUnregisterResponse, event_unregister_response)
NCLINK_DTU_CODEC(EventData, event_data)
NCLINK_DTU_CODEC(DevUnreachable, dev_unreachable)

#undef NCLINK_DTU_CODEC

/// Compact UTF-8 text of a DTU (invalid UTF-8 in strings is replaced, never thrown).
template <class T>
std::string encode(const T& dtu) {
    return to_json(dtu).dump(-1, ' ', false, Json::error_handler_t::replace);
}
/// The same text, written without building the Json tree (the answers on
/// the request path; a Query's is the largest).
template <>
NCLINK_API std::string encode<QueryResponse>(const QueryResponse& dtu);
template <>
NCLINK_API std::string encode<SetResponse>(const SetResponse& dtu);

/// A response to `request` with "@id" echoed and guid = dev (for the DTUs
/// whose responses carry both). Fill in the rest.
template <class Response, class Request>
Response make_reply(const Request& request, std::string dev) {
    Response response{};
    response.msg_id = request.msg_id;
    response.guid = std::move(dev);
    return response;
}

/// The answer to a request of `request_kind` that could not be decoded (or is
/// refused as a whole): the matching response DTU with "@id" (if any), guid =
/// dev and code NG / reason / error from `error`. For Method/Call it is a
/// Method/Result with result "error"; for Register/Request a Register/Response
/// (cli_uuid = dev). std::nullopt for kinds that are not answered (responses,
/// samples, events, Probe/Version, Notify/State).
NCLINK_API std::optional<Json> make_error_reply(TopicKind request_kind, const MessageId& msg_id, std::string_view dev,
                                                const Error& error);

}  // namespace nclink
