// The adapter's link to the broker and the agent, one object with one lock:
// the adapter state machine (the state-machine text items 64-82, as data in
// adapter_state.cpp) with the responses it keeps while the link will not
// take them, the retained online state (8.2.16), registration with an agent
// (8.2.1/8.2.2) and Probe/Version (8.2.5). Every answer the adapter sends
// goes out through respond() here, so the table's row decides whether it is
// sent now or kept.
//
// Threads: on_link() and on_register_response() on the transport's callback
// thread (never block there); fire()/respond() on any thread (request
// workers, the driver's worker, features, model changes); tick_registration()
// and retry_kept() on the housekeeping thread. The lock is never held while
// publishing.
#pragma once

#include "adapter/registration.hpp"
#include "adapter/response_cache.hpp"

#include <nclink/adapter_config.hpp>
#include <nclink/adapter_state.hpp>
#include <nclink/clock.hpp>
#include <nclink/dtu.hpp>
#include <nclink/log.hpp>
#include <nclink/topics.hpp>
#include <nclink/transport.hpp>

#include "feature/model_state.hpp"

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace nclink::adapter_detail {

/// The retained Notify/State of terminal `dev` (8.2.16): "online", or
/// "offline" (also the last will, before any link exists).
Message state_message(const std::string& dev, const char* state_text);

class AdapterLink {
public:
    /// `config`, `transport`, `model` and `logger` outlive the link.
    /// `instance` names this run of the adapter (docs/wire.md);
    /// `wake_housekeeping` is called when a registration went out or was
    /// answered, so its retry clock is looked at at once.
    AdapterLink(const AdapterConfig& config, Transport& transport, const feature_detail::ModelSource& model,
                std::shared_ptr<const Clock> clock, const Logger& logger, std::string dev, std::string instance,
                std::function<void()> wake_housekeeping);

    AdapterState state() const;
    bool registered() const { return registration_.registered(); }

    /// The transport's link changed (transport callback thread; never blocks).
    void on_link(LinkState link);
    /// Runs the state-machine table: takes the row of (state, event), moves to
    /// its next state and performs its actions. `response` is the response
    /// at hand for request_handled/response_failed. Any thread.
    void fire(AdapterEvent event, std::vector<Message> response = {});
    /// Publishes a reply on the response topic(s) mirroring `request_topic`
    /// (both spellings where docs/wire.md says so), or keeps it (the row decides).
    void respond(const ParsedTopic& request_topic, const Json& reply);
    /// respond() with the payload already serialized (Probe/Query's verbatim
    /// model). Taken by value: the last topic's message takes it over (a
    /// Query answer can be megabytes).
    void respond_text(const ParsedTopic& request_topic, std::string payload);
    /// A fresh @id for DTUs the adapter originates.
    std::string next_msg_id();

    void on_register_response(const std::string& payload);
    /// Housekeeping: registers again when no agent answered in time.
    void tick_registration(Clock::Steady now);
    /// Housekeeping: while connected, kept responses are tried again (retry_due).
    void retry_kept();
    /// stop() closes the link itself from now on: not a lost link worth a line.
    void stopping();

private:
    void flush_responses();
    void send_registration();
    void publish_version();

    const AdapterConfig& config_;
    Transport& transport_;
    const feature_detail::ModelSource& model_;
    const std::shared_ptr<const Clock> clock_;
    const Logger& logger_;
    const std::string dev_;
    const std::string instance_;  ///< this run, in Probe/Version's and registrations' privateInfo
    const std::string msg_id_prefix_;
    const std::function<void()> wake_housekeeping_;
    std::atomic<std::uint64_t> msg_counter_{0};
    Registration registration_;  // its own lock (registration.hpp)

    mutable std::mutex mutex_;  // the state and the kept responses, in one order
    AdapterState state_ = AdapterState::initial;
    bool connected_once_ = false;  // a link_lost before it is the transport's start, not a loss
    bool stopping_ = false;
    ResponseCache responses_;  // state-machine text items 75, 79: kept while the link will not take them
};

}  // namespace nclink::adapter_detail
