// NC-Link topics (GB/T 41970-2022 table 17, shapes in docs/wire.md):
// builders for every topic, the subscription filters of an adapter and an
// agent, a parser, and the mirror rule that turns a request topic into the
// response topic(s) to publish to.
//
// Terms: dev = the adapter's terminal id (its model GUID); ex = the
// application's terminal id (ex_cid); channel = sample channel id.
// Topics are case-sensitive. Register/Unregister may arrive spelled as the
// standard misprints them ("Reigster", "Unreigster"); the parser accepts both
// spellings wherever Register/Unregister can appear and says which it saw.
#pragma once

#include <nclink/export.hpp>
#include <nclink/topic_filter.hpp>  // topic_matches()

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

enum class TopicKind {
    register_request,            ///< Register/Request
    register_response,           ///< Register/Response/{cli}            (dev = cli_uuid)
    discovery_request,           ///< Discovery/Request/{ex}             (dev empty)
    discovery_response,          ///< Discovery/Response/{ex}            (dev empty)
    probe_version,               ///< Probe/Version/{dev}
    probe_version_response,      ///< Probe/Version/Response/{dev}[/{ex}]
    probe_query_request,         ///< Probe/Query/Request/{dev}[/{ex}]
    probe_query_response,        ///< Probe/Query/Response/{dev}[/{ex}]
    probe_set_request,           ///< Probe/Set/Request/{dev}[/{ex}]
    probe_set_response,          ///< Probe/Set/Response/{dev}[/{ex}]
    query_request,               ///< Query/Request/{dev}[/{ex}]
    query_response,              ///< Query/Response/{dev}[/{ex}]
    set_request,                 ///< Set/Request/{dev}[/{ex}]
    set_response,                ///< Set/Response/{dev}[/{ex}]
    sample,                      ///< Sample/{dev}/{channel}
    dynamic_sample,              ///< Sample/{dev}/{ex}/{channel}
    notify_state,                ///< Notify/State/{tid}                 (dev = tid)
    sample_register_request,     ///< Register/Sample/Request/{dev}[/{ex}]
    sample_register_response,    ///< Register/Sample/Response/{dev}[/{ex}]
    sample_unregister_request,   ///< Unregister/Sample/Request/{dev}[/{ex}]
    sample_unregister_response,  ///< Unregister/Sample/Response/{dev}[/{ex}]
    method_call,                 ///< Method/Call/{dev}[/{ex}]
    method_status,               ///< Method/Status/{dev}[/{ex}]
    method_result,               ///< Method/Result/{dev}[/{ex}]
    method_control_request,      ///< Method/Control/Request/{dev}[/{ex}]
    method_control_response,     ///< Method/Control/Response/{dev}[/{ex}]
    event_register_request,      ///< Register/Event/Request/{dev}[/{ex}]
    event_register_response,     ///< Register/Event/Response/{dev}[/{ex}]
    event_unregister_request,    ///< Unregister/Event/Request/{dev}[/{ex}]
    event_unregister_response,   ///< Unregister/Event/Response/{dev}[/{ex}]
    event,                       ///< Event/{dev}[/{ex}]
};

/// "query_request", ... (for logs).
NCLINK_API std::string_view to_string(TopicKind kind) noexcept;

/// How Register/Unregister is spelled in a topic.
enum class Spelling {
    standard,  ///< Register / Unregister
    typo,      ///< Reigster / Unreigster, as table 17 and 8.2.18/8.2.20/8.2.28 print them
};

struct NCLINK_API ParsedTopic {
    TopicKind kind = TopicKind::register_request;
    std::string dev;  ///< dev_uuid; cli_uuid for Register/Response; tid for Notify/State; empty for Register/Request and Discovery
    std::optional<std::string> ex;           ///< ex_cid when the topic carries one
    std::optional<std::string> channel;      ///< sample channel id (Sample topics)
    Spelling spelling = Spelling::standard;  ///< which spelling of Register/Unregister was seen

    friend bool operator==(const ParsedTopic& a, const ParsedTopic& b) {
        return a.kind == b.kind && a.dev == b.dev && a.ex == b.ex && a.channel == b.channel && a.spelling == b.spelling;
    }
    friend bool operator!=(const ParsedTopic& a, const ParsedTopic& b) { return !(a == b); }
};

/// Parses a concrete topic (no wildcards). std::nullopt for anything that is
/// not exactly one of the shapes above: unknown command, empty segment
/// (leading/trailing/double '/'), a wildcard or NUL character, too few or too
/// many segments. Longer command prefixes win, so "Probe/Version/Response/x"
/// is a version-check response; the 3-segment "Probe/Version/Response" is a
/// version check from a device named "Response".
NCLINK_API std::optional<ParsedTopic> parse_topic(std::string_view topic);
/// parse_topic(topic)->kind, without copying the topic's parts: no heap
/// allocation (a transport classifies every DTU it sends and receives).
NCLINK_API std::optional<TopicKind> topic_kind(std::string_view topic) noexcept;

/// Builds the topic described by `parsed` (inverse of parse_topic). Parts a
/// kind does not use are ignored; a kind that needs ex/channel and lacks them
/// gets an empty segment, so callers pass what the kind needs.
NCLINK_API std::string build_topic(const ParsedTopic& parsed);

/// True for kinds that can be spelled "Reigster"/"Unreigster".
NCLINK_API bool has_typo_spelling(TopicKind kind) noexcept;

/// The response kind that answers a request kind (Probe/Version -> its
/// response, Method/Call -> Method/Result, Discovery/Request -> Discovery/Response,
/// Register/Request -> Register/Response); std::nullopt for kinds that are
/// not requests.
NCLINK_API std::optional<TopicKind> response_kind(TopicKind request) noexcept;

/// The mirror rule (docs/wire.md): `X/Request/{dev}/{ex}` -> `X/Response/{dev}/{ex}`,
/// `X/Request/{dev}` -> `X/Response/{dev}`, always in the standard spelling.
/// std::nullopt when `request` is not a request topic, and for Register/Request
/// (its response topic names the registering client, which only the payload carries:
/// use topics::register_response(cli_uuid)).
NCLINK_API std::optional<std::string> response_topic(std::string_view request_topic);
NCLINK_API std::optional<std::string> response_topic(const ParsedTopic& request);

/// Every topic a response to `request` is published to: the mirrored topic in
/// the standard spelling and, for Register/Sample, Unregister/Sample,
/// Register/Event and Unregister/Event responses when `standard_typo_topics`
/// is on (the adapter option, default on), also the literal spelling of the
/// standard ("Reigster/...", "Unreigster/..."). Empty when there is no response topic.
NCLINK_API std::vector<std::string> response_topics(std::string_view request_topic, bool standard_typo_topics = true);
NCLINK_API std::vector<std::string> response_topics(const ParsedTopic& request, bool standard_typo_topics = true);

namespace topics {

using OptEx = std::optional<std::string_view>;

NCLINK_API std::string register_request();
NCLINK_API std::string register_response(std::string_view cli_uuid);
NCLINK_API std::string discovery_request(std::string_view ex);
NCLINK_API std::string discovery_response(std::string_view ex);
NCLINK_API std::string probe_version(std::string_view dev);
NCLINK_API std::string probe_version_response(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string probe_query_request(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string probe_query_response(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string probe_set_request(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string probe_set_response(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string query_request(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string query_response(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string set_request(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string set_response(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string sample(std::string_view dev, std::string_view channel);
NCLINK_API std::string dynamic_sample(std::string_view dev, std::string_view ex, std::string_view channel);
NCLINK_API std::string notify_state(std::string_view tid);
NCLINK_API std::string sample_register_request(std::string_view dev, OptEx ex = std::nullopt, Spelling s = Spelling::standard);
NCLINK_API std::string sample_register_response(std::string_view dev, OptEx ex = std::nullopt, Spelling s = Spelling::standard);
NCLINK_API std::string sample_unregister_request(std::string_view dev, OptEx ex = std::nullopt, Spelling s = Spelling::standard);
NCLINK_API std::string sample_unregister_response(std::string_view dev, OptEx ex = std::nullopt, Spelling s = Spelling::standard);
NCLINK_API std::string method_call(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string method_status(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string method_result(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string method_control_request(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string method_control_response(std::string_view dev, OptEx ex = std::nullopt);
NCLINK_API std::string event_register_request(std::string_view dev, OptEx ex = std::nullopt, Spelling s = Spelling::standard);
NCLINK_API std::string event_register_response(std::string_view dev, OptEx ex = std::nullopt, Spelling s = Spelling::standard);
NCLINK_API std::string event_unregister_request(std::string_view dev, OptEx ex = std::nullopt, Spelling s = Spelling::standard);
NCLINK_API std::string event_unregister_response(std::string_view dev, OptEx ex = std::nullopt, Spelling s = Spelling::standard);
NCLINK_API std::string event(std::string_view dev, OptEx ex = std::nullopt);

/// Every filter an adapter for `dev` subscribes to: Register/Response/{dev},
/// Probe/Version/Response/{dev}[/+], and each request topic it serves as
/// `X/Request/{dev}` and `X/Request/{dev}/+` (Register/Unregister requests in
/// both spellings). Each filter once, in a fixed order.
NCLINK_API std::vector<std::string> adapter_subscriptions(std::string_view dev);

}  // namespace topics
}  // namespace nclink
