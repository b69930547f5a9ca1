// The agent's insides, shared by the files that implement it, one
// responsibility each:
//   agent.cpp              the public facade and the lifecycle
//   agent_messages.cpp     every DTU in: routing, replies, presence notes
//   agent_terminals.cpp    registration (8.2.1/8.2.2), discovery (8.2.3/8.2.4),
//                          Probe/Version and the model fetch (8.2.5-8.2.7),
//                          Notify/State (8.2.16)
//   agent_forwarding.cpp   requests to adapters: 301, DEV_UNREACHABLE (8.3.4),
//                          the cached probe, 203 for a silent adapter
//   agent_housekeeping.cpp timeouts, liveness and the state files
//   agent_split.cpp        requests of another instance's share (instances
//                          without $share; the rule is instance_split.hpp)
//   agent_metrics.cpp      DTUs by kind and the Prometheus text of the stats
//
// and the objects it composes: Picture (agent_picture.hpp: what the agent
// knows of every terminal, behind its one lock), StateStore (the state
// files), the transport (the broker link) and the housekeeping thread.
//
// Every DTU is handled on the transport's callback thread inside
// Picture::with() (bookkeeping only, no I/O): each handler gets the picture
// as `State& p`, so none can reach it unlocked. What a handler decides to
// publish is collected and published after the lock is released. The
// housekeeping thread runs the timeouts and liveness on the injected clock
// and writes the state files.
// Nothing outside src/agent/ includes this.
#pragma once

#include "agent/access.hpp"
#include "agent/agent_picture.hpp"
#include "agent/instance_split.hpp"
#include "agent/state_store.hpp"
#include "agent/terminal_id.hpp"
#include "core/periodic_thread.hpp"
#include "transport/dtu_counting_transport.hpp"

#include <nclink/agent.hpp>
#include <nclink/agent_state.hpp>
#include <nclink/dtu.hpp>
#include <nclink/topics.hpp>

#include <fmt/format.h>

#include <atomic>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace nclink {

namespace agent_detail {

/// A terminal id usable as one topic level (no wildcards).
bool publishable_level(std::string_view level);
/// True for the response DTUs the agent watches to see adapters answer.
bool is_response(TopicKind kind);

}  // namespace agent_detail

struct NCLINK_LOCAL Agent::Impl {
    using Kind = agent_detail::Kind;
    using Picture = agent_detail::Picture;
    using State = agent_detail::Picture::State;
    using StateStore = agent_detail::StateStore;
    using Status = agent_detail::Status;
    struct Counters {
        std::atomic<std::uint64_t> registrations{0}, refused{0}, repeated{0}, discoveries{0}, versions{0}, fetched{0}, cached{0},
            unreachable{0}, timeouts{0}, denied{0}, notifications{0}, malformed{0}, retained{0}, held{0};
    };
    using Out = std::vector<Message>;

    AgentConfig config;
    Logger log;
    std::shared_ptr<const Clock> clock = std::make_shared<SystemClock>();
    std::unique_ptr<Transport> transport;
    // Discovery's own link (config.discovery_link), or null: Discovery then
    // comes and goes on `transport`. Set before start(), read-only after.
    std::unique_ptr<Transport> discovery_transport;
    // The $share group of answer_filters(): config.share_group, or "" after
    // start() found the broker without shared subscriptions. Written before
    // the transport starts, read-only after.
    std::string share_group;
    StateStore store;
    Counters counters;
    std::shared_ptr<transport_detail::DtuCounter> dtus = std::make_shared<transport_detail::DtuCounter>();  // docs/metrics.md

    Picture picture;  // the terminals, behind the one lock every DTU handler takes

    std::mutex lifecycle;
    bool started = false;
    bool stopped = false;
    core_detail::PeriodicThread housekeeping;  // housekeep() every config.tick

    Impl(AgentConfig c, Logger l)
        : config(std::move(c)),
          log(std::move(l)),
          store(config.state_dir),
          picture(config.adapter_liveness, config.application_liveness) {}

    std::int64_t wall_s() const { return clock->wall_ms() / 1000; }

    // ------------------------------------------------------------ lifecycle

    Result<void> start();

    void stop(std::chrono::milliseconds flush_timeout);

    // Thread: the owner's (nclink-agent: its signal loop). Applies under the
    // lock every DTU handler takes, so a DTU sees the old or the new rules.
    Result<ConfigReload> reload(const AgentConfig& next);

    MqttOptions mqtt_options() const;

    // The share group to answer through (start(), before the transport).
    std::string usable_share_group();

    // Requests the agent answers: with several agents, exactly one of them
    // gets each (MQTT shared subscription), or all get each and one answers
    // (instances, without $share).
    std::vector<std::string> answer_filters() const;
    // `filter` through share_group, when there is one.
    std::string shared(const std::string& filter) const;
    // Connects the Discovery link (start(), after the main one).
    Result<void> start_discovery_link();
    // Counts a link's DTUs and hands its messages and states to the agent.
    void attach(std::unique_ptr<Transport>& link, const char* name);

    // What every agent instance must see to keep its own picture complete.
    std::vector<std::string> observe_filters() const;

    // ------------------------------------------------------------ messages

    // Thread: transport callback. Takes the picture's lock for dispatch().
    void on_message(const Message& m);

    void publish(Out& out);

    void dispatch(State& p, const ParsedTopic& topic, const Message& m, Out& out);

    // ---- instances without $share (agent_split.cpp) ----
    // False for a request in another instance's share.
    bool answers_here(const ParsedTopic& topic, const Message& m) const;
    // Such a request: only the sign of life of its sender, as its owner takes it.
    void watch_request(State& p, const ParsedTopic& topic, const Message& m, Out& out);

    void reply(Out& out, std::string topic, const Json& payload);

    // Answers the agent gives in an adapter's place carry privateInfo.agent,
    // so every agent instance can tell them from the adapter's own.
    Json marked(Json answer) const;

    void reply_all(Out& out, const ParsedTopic& request, const Json& payload);

    void announce_state(State& p, const std::string& tid, Status status, Out& out);

    // A DTU from `tid`: a sign of life (3.22/3.23). `may_overtake`: it came
    // at QoS 0 (Sample DTUs), ahead of the terminal's QoS 1 Notify/State
    // perhaps, so its announcement is held back (pending_announcements.hpp).
    enum class Arrival { in_order, may_overtake };
    void alive(State& p, const std::string& tid, Kind kind, Out& out, Arrival arrival = Arrival::in_order);

    // ---- 8.2.1 / 8.2.2 ----
    void on_register(State& p, const Message& m, Out& out);

    void on_register_response(State& p, const ParsedTopic& topic, const Message& m);

    // ---- 8.2.3 / 8.2.4 ----
    void on_discovery(State& p, const ParsedTopic& topic, const Message& m, Out& out);

    // ---- 8.2.5 / 8.2.6 and the model fetch of 8.2.7 ----
    void on_version(State& p, const ParsedTopic& topic, const Message& m, Out& out);

    void fetch_model(State& p, const std::string& dev, Out& out);
    void learn_kind(State& p, const std::string& tid, Out& out);
    // An adapter silent for its liveness time: asked before it is offline.
    void ask_alive(State& p, const std::string& tid, Out& out);
    void ask_model(State& p, const std::string& dev, std::string_view what, Out& out);
    bool asks(const std::string& tid) const;
    bool model_fetch_waits(const State& p, const std::string& tid) const;

    void on_version_response(State& p, const ParsedTopic& topic, const Message& m, Out&);

    // ---- 8.2.16 ----
    void on_notify(State& p, const ParsedTopic& topic, const Message& m, Out& out);

    // 8.3.5: the adapter went away while requests to it were waiting.
    void unreachable_for(State& p, const std::string& dev, Out& out);

    void answer_unreachable(TopicKind kind, const std::string& request_topic, const std::string& dev,
                            const std::optional<std::string>& ex, const MessageId& msg_id, Out& out) {
        DevUnreachable dtu;
        dtu.msg_id = msg_id;
        dtu.dev_uuid = dev;
        dtu.cli_uuid = ex.value_or("");
        ++counters.unreachable;
        log.debug("agent: {} to {} answered DEV_UNREACHABLE", to_string(kind), dev);
        const Json answer = marked(to_json(dtu));
        for (auto& t : response_topics(request_topic, true)) reply(out, std::move(t), answer);
    }

    // ---- requests to adapters: 301, DEV_UNREACHABLE, cached probe, 203 ----
    void on_request(State& p, const ParsedTopic& topic, const Message& m, Out& out);

    void on_response(State& p, const ParsedTopic& topic, const Message& m, Out& out);

    static bool from_agent(const std::string& payload);

    // ------------------------------------------------------------ housekeeping

    // Thread: housekeeping, every tick: timeouts and liveness on the
    // injected clock, the state files once a second.
    void housekeep();
    Clock::Steady last_save{};  // housekeeping thread only

    void tick(State& p, Out& out);

    // Writes what changed; the text is built under the lock, written outside it.
    void persist(bool all);
};

}  // namespace nclink
