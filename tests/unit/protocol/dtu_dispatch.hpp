// Test helper: run an example through the decoder its Dtu tag names.
#pragma once

#include "chapter8_examples.hpp"

#include <nclink/dtu.hpp>

namespace chapter8 {

/// decode -> to_json, or the decode error (Input: text or Json).
template <class T, class Input>
nclink::Result<nclink::Json> reencode_as(const Input& input) {
    auto decoded = nclink::decode<T>(input);
    if (!decoded) return decoded.error();
    return nclink::to_json(*decoded);
}

template <class Input>
nclink::Result<nclink::Json> reencode(Dtu dtu, const Input& input) {
    using namespace nclink;
    switch (dtu) {
        case Dtu::register_request: return reencode_as<RegisterRequest>(input);
        case Dtu::register_response: return reencode_as<RegisterResponse>(input);
        case Dtu::discovery_request: return reencode_as<DiscoveryRequest>(input);
        case Dtu::discovery_response: return reencode_as<DiscoveryResponse>(input);
        case Dtu::probe_version_request: return reencode_as<ProbeVersionRequest>(input);
        case Dtu::probe_version_response: return reencode_as<ProbeVersionResponse>(input);
        case Dtu::probe_query_request: return reencode_as<ProbeQueryRequest>(input);
        case Dtu::probe_query_response: return reencode_as<ProbeQueryResponse>(input);
        case Dtu::probe_set_request: return reencode_as<ProbeSetRequest>(input);
        case Dtu::probe_set_response: return reencode_as<ProbeSetResponse>(input);
        case Dtu::query_request: return reencode_as<QueryRequest>(input);
        case Dtu::query_response: return reencode_as<QueryResponse>(input);
        case Dtu::set_request: return reencode_as<SetRequest>(input);
        case Dtu::set_response: return reencode_as<SetResponse>(input);
        case Dtu::sample: return reencode_as<SampleDtu>(input);
        case Dtu::notify_state: return reencode_as<NotifyState>(input);
        case Dtu::sample_register_request: return reencode_as<SampleRegisterRequest>(input);
        case Dtu::sample_register_response: return reencode_as<SampleRegisterResponse>(input);
        case Dtu::sample_unregister_request: return reencode_as<SampleUnregisterRequest>(input);
        case Dtu::sample_unregister_response: return reencode_as<SampleUnregisterResponse>(input);
        case Dtu::method_call: return reencode_as<MethodCall>(input);
        case Dtu::method_status: return reencode_as<MethodStatus>(input);
        case Dtu::method_result: return reencode_as<MethodResult>(input);
        case Dtu::method_control_request: return reencode_as<MethodControlRequest>(input);
        case Dtu::method_control_response: return reencode_as<MethodControlResponse>(input);
        case Dtu::event_register_request: return reencode_as<EventRegisterRequest>(input);
        case Dtu::event_register_response: return reencode_as<EventRegisterResponse>(input);
        case Dtu::event_unregister_request: return reencode_as<EventUnregisterRequest>(input);
        case Dtu::event_unregister_response: return reencode_as<EventUnregisterResponse>(input);
        case Dtu::event_data: return reencode_as<EventData>(input);
        case Dtu::dev_unreachable: return reencode_as<DevUnreachable>(input);
    }
    return nclink::make_error(nclink::ErrorCode::syntax_error, "unknown Dtu");
}

}  // namespace chapter8
