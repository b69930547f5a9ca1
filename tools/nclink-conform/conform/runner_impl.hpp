// Internals of run_conformance(): the state shared by the item functions
// (runner.cpp: connection, state, model, query; runner_features.cpp:
// sampling, dynamic sampling, set, model set, methods; runner_events.cpp: events).
#pragma once

#include "conform/checks.hpp"
#include "conform/runner.hpp"

#include <nclink/model.hpp>
#include <nclink/topics.hpp>

#include <map>
#include <set>
#include <memory>

namespace nclink::conform::detail {

/// One request and what came back.
struct Exchange {
    std::string topic;  ///< where the request went
    Json request;
    Json sent_id;                   ///< the request's "@id"
    std::optional<Captured> reply;  ///< the answer with our "@id"
    std::optional<Json> dtu;        ///< reply parsed as a JSON object
    std::string unparsable;         ///< why the reply is not a JSON object
    bool mirrored = true;           ///< the reply came on the mirrored topic (docs/wire.md)
    std::vector<Captured> strays;   ///< other messages on the response topics (wrong "@id")
};

class Runner {
public:
    Runner(Wire& wire, const RunOptions& options);
    TestRecord run();

    // ---- plumbing ----
    /// Publishes `payload` (with a fresh "@id" added) to `topic` and waits for
    /// the answer with that "@id" on one of `reply_topics`; answers on
    /// `unmirrored_topics` are taken too but flagged.
    Exchange request(const std::string& topic, Json payload, const std::vector<std::string>& reply_topics,
                     const std::vector<std::string>& unmirrored_topics = {});
    /// Standard request on `X/Request/{dev}/{ex}` answered on `X/Response/{dev}/{ex}`.
    Exchange request_kind(TopicKind kind, Json payload);
    /// For an exchange without a usable answer: records fail or not-supported
    /// (silence on an optional feature, or an NG 202/"not supported") in
    /// `item` and returns true. Also returns true (and fails the item) for
    /// answers that are not JSON objects or come on the wrong topic.
    bool settle_unusable(ItemResult& item, const Exchange& ex, bool optional_feature);
    void fail_with(ItemResult& item, const std::string& note, const Exchange& ex);
    void fail_with(ItemResult& item, const std::string& note, const Captured& c);
    ItemResult& item(std::string_view key);
    std::chrono::milliseconds ms_since(std::chrono::steady_clock::time_point t) const;

    // ---- items (in run order) ----
    void connection();
    void state_notification();
    void probe();
    void model_file();
    void query();
    void sampling();
    void events();
    void dynamic_sampling();
    void set();
    void model_set();
    void methods();

    // ---- helpers for features ----
    /// An item seen changing (sample columns, or two queries apart), else a fallback.
    std::string changing_item(bool* seen_changing);
    /// Whether item `id` was seen changing in what arrived since `mark` (its
    /// Sample rows stamped from `since_wall_ms` on), or between `before` (its
    /// value then) and a Query now.
    bool moved_since(const std::string& id, std::uint64_t mark, const std::optional<Json>& before, std::int64_t since_wall_ms);
    std::vector<ChannelSpec> channel_specs() const;
    /// Chapter 7 on the values answered, and the appendix A Query forms (runner_fidelity.cpp).
    void query_fidelity(ItemResult& q);
    /// A model that cannot be valid is refused with a table-19 reason (8.2.10, table 20).
    void refused_model_set(ItemResult& m);
    /// Whole-item Query of one id: its value, or why not.
    std::optional<Json> query_value(const std::string& id, const Json& params, std::string* why);

    Wire& wire;
    const RunOptions& opts;
    const std::string dev;
    const std::string ex;
    TestRecord record;
    bool connection_failed = false;
    Json raw_model;                      ///< the probe as received
    std::shared_ptr<const Model> model;  ///< parsed (null when unusable)
    const Device* device = nullptr;
    std::map<std::string, Json> whole_values;  ///< whole values answered by the Query item
    std::string whole_values_topic;            ///< the topic they came on (evidence)
    std::uint64_t start_mark = 0;              ///< first message of the run
    std::set<std::string> sent_ids;            ///< "@id"s of our requests (late answers are not strays)
};

/// Problems joined with "; ".
std::string join(const Problems& problems);
/// Why an item that changes the machine was skipped.
inline constexpr const char* needs_write = "skipped: needs --allow-write (this item changes the machine, then restores it)";
/// True when the captured message's topic is of `kind`.
bool is_topic(const Captured& c, TopicKind kind);
/// A captured Sample DTU of a model channel of `dev`: its channel id.
std::optional<std::string> model_channel_of(const Captured& c, const std::string& dev);

/// "<topic>" + payload of a captured message, for evidence.
Evidence evidence_of(const Captured& c, std::string note);

}  // namespace nclink::conform::detail
