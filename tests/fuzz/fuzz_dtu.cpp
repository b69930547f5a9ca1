// Fuzz target for the protocol module: every DTU decoder, re-encoding of
// whatever decodes, the topic parser and mirror rule on the bytes as a topic,
// and the sample encoder's string escaper (its output must always be JSON).
#include <nclink/dtu.hpp>
#include <nclink/sample_encoder.hpp>
#include <nclink/topics.hpp>

#include <cstdint>
#include <cstdlib>
#include <string_view>

namespace {

template <class T>
void exercise(std::string_view payload) {
    auto decoded = nclink::decode<T>(payload);
    if (!decoded) return;
    // What decodes must re-encode, and our own encoding must decode again.
    const std::string text = nclink::encode(*decoded);
    if (!nclink::decode<T>(text).ok()) std::abort();
}

template <class... T>
void exercise_all(std::string_view payload) {
    (exercise<T>(payload), ...);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace nclink;
    const std::string_view input(reinterpret_cast<const char*>(data), size);

    exercise_all<RegisterRequest, RegisterResponse, DiscoveryRequest, DiscoveryResponse, ProbeVersionRequest,
                 ProbeVersionResponse, ProbeQueryRequest, ProbeQueryResponse, ProbeSetRequest, ProbeSetResponse,
                 QueryRequest, QueryResponse, SetRequest, SetResponse, SampleDtu, NotifyState, SampleRegisterRequest,
                 SampleRegisterResponse, SampleUnregisterRequest, SampleUnregisterResponse, MethodCall, MethodStatus,
                 MethodResult, MethodControlRequest, MethodControlResponse, EventRegisterRequest,
                 EventRegisterResponse, EventUnregisterRequest, EventUnregisterResponse, EventData, DevUnreachable>(
        input);
    (void)peek_message_id(input);

    if (const auto topic = parse_topic(input)) {
        if (build_topic(*topic) != input) std::abort();  // parse and build are inverses
        (void)response_topics(*topic, true);
    }

    // The escaper must turn any bytes into one valid JSON string.
    std::string out;
    append_json_string(out, input);
    if (Json::parse(out, nullptr, false).is_discarded()) std::abort();
    return 0;
}
