// Fuzz target for the protocol module: every DTU decoder, re-encoding of
// whatever decodes, the topic parser and mirror rule on the bytes as a topic,
// and the sample encoder's string escaper (its output must always be JSON).
#include <nclink/dtu.hpp>
#include <nclink/sample_encoder.hpp>
#include <nclink/topics.hpp>

#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <type_traits>

namespace {

template <class T>
void exercise(std::string_view payload) {
    auto decoded = nclink::decode<T>(payload);
    if (!decoded) return;
    // What decodes must re-encode, and our own encoding must decode again.
    const std::string text = nclink::encode(*decoded);
    if (!nclink::decode<T>(text).ok()) std::abort();
    // The answers written as text, not dumped from the tree, must read as
    // the dumped tree reads (their doubles may have other digits, never
    // another value).
    if constexpr (std::is_same_v<T, nclink::QueryResponse> || std::is_same_v<T, nclink::SetResponse>) {
        const auto dumped = to_json(*decoded).dump(-1, ' ', false, nclink::Json::error_handler_t::replace);
        if (nclink::Json::parse(text, nullptr, false) != nclink::Json::parse(dumped, nullptr, false)) std::abort();
    }
}

template <class... T>
void exercise_all(std::string_view payload) {
    (exercise<T>(payload), ...);
}

// A Query or Set request decodes by a scan or a stream when it can (the
// adapter's hot path), else by the tree: from text it must always read as
// the tree reads the same JSON, accepted or refused alike.
template <class T>
void request_as_tree(std::string_view payload) {
    std::size_t opened = 0;
    for (const char c : payload) opened += c == '[' || c == '{';
    if (opened > static_cast<std::size_t>(nclink::max_payload_depth))
        return;  // the text path refuses deep nesting (412), the tree has no such limit
    const nclink::Json tree = nclink::Json::parse(payload.begin(), payload.end(), nullptr, false);
    if (tree.is_discarded() || !tree.is_object()) return;
    const auto from_text = nclink::decode<T>(payload);
    const auto from_tree = nclink::decode<T>(tree);
    if (from_text.ok() != from_tree.ok()) std::abort();
    if (from_text.ok() && nclink::encode(*from_text) != nclink::encode(*from_tree)) std::abort();
    if (!from_text.ok() && from_text.error().code != from_tree.error().code) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace nclink;
    const std::string_view input(reinterpret_cast<const char*>(data), size);

    exercise_all<RegisterRequest, RegisterResponse, DiscoveryRequest, DiscoveryResponse, ProbeVersionRequest,
                 ProbeVersionResponse, ProbeQueryRequest, ProbeQueryResponse, ProbeSetRequest, ProbeSetResponse, QueryRequest,
                 QueryResponse, SetRequest, SetResponse, SampleDtu, NotifyState, SampleRegisterRequest, SampleRegisterResponse,
                 SampleUnregisterRequest, SampleUnregisterResponse, MethodCall, MethodStatus, MethodResult, MethodControlRequest,
                 MethodControlResponse, EventRegisterRequest, EventRegisterResponse, EventUnregisterRequest,
                 EventUnregisterResponse, EventData, DevUnreachable>(input);
    (void)peek_message_id(input);
    request_as_tree<QueryRequest>(input);
    request_as_tree<SetRequest>(input);

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
