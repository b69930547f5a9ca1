// What the agent knows of every terminal (presence, registrations, cached
// models, requests waiting for an adapter, what the state files still need,
// its own Notify/State announcements still to come back) and the one lock
// that guards it. One lock for all of it because each decision reads several
// parts at once: a request's answer depends on the ACL, the registration,
// both terminals' presence and the cached model (docs/state-machines.md).
//
// The picture is reachable only through with(), which holds the lock while
// its function runs: no code path can read or change it unlocked. Nothing
// inside with() does I/O: handlers collect what to publish and publish it
// after with() returns (agent_impl.hpp).
// Thread-safe: with() from any thread (transport callback, housekeeping,
// the facade's readers, reload on the owner's thread).
#pragma once

#include "agent/model_cache.hpp"
#include "agent/pending_announcements.hpp"
#include "agent/pending_forwards.hpp"
#include "agent/pending_saves.hpp"
#include "agent/presence.hpp"
#include "agent/registrar.hpp"

#include <nclink/agent.hpp>
#include <nclink/agent_state.hpp>
#include <nclink/clock.hpp>
#include <nclink/transport.hpp>

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::agent_detail {

class Picture {
public:
    struct State {
        Presence presence;
        std::unique_ptr<Registrar> registrar;  // set by Agent::start (the id rule is checked there)
        ModelCache models;
        PendingForwards pending;
        PendingAnnouncements announcements;  // online by a Sample DTU, announced later
        PendingSaves saves;                  // what the housekeeping thread writes next
        std::set<std::string> kind_probes;   // online terminals of unknown kind asked with a Probe/Query
        bool started_serving = false;        // the `initialized` row was taken (docs/state-machines.md)

        explicit State(Presence p) : presence(std::move(p)) {}

        /// A DTU from `tid` of `kind`: a sign of life (3.22/3.23). True when
        /// it makes the terminal online (the caller announces it).
        bool saw(const std::string& tid, Kind kind, Clock::Steady now, std::int64_t wall_s);
        /// The retained Notify/State the agent publishes for `tid`; its echo
        /// is expected back and then ignored (own_echo()).
        Message announce(const std::string& tid, Status status);
        /// True (and forgotten) when a Notify/State is the agent's own coming back.
        bool own_echo(const std::string& tid, const std::string& state);
        /// The state-machine state of the pair (application `ex`, adapter
        /// `dev`) from who is online now; "unknown" counts as online.
        AgentState pair_state(const std::optional<std::string>& ex, const std::string& dev) const;
        /// A fresh @id for a request of the agent's own ("<agent>-<what>-<n>").
        std::string next_id(const std::string& agent_id, std::string_view what);
        /// Every terminal known from presence or registration.
        std::vector<TerminalInfo> terminals() const;

    private:
        std::map<std::string, int> expected_echo_;  // "tid\nstate" -> own Notify/State still to come back
        std::uint64_t msg_counter_ = 0;
    };

    Picture(std::chrono::milliseconds adapter_liveness, std::chrono::milliseconds application_liveness)
        : state_(Presence(adapter_liveness, application_liveness)) {}

    template <class F>
    decltype(auto) with(F&& f) {
        std::lock_guard<std::mutex> lock(mutex_);
        return f(state_);
    }
    template <class F>
    decltype(auto) with(F&& f) const {
        std::lock_guard<std::mutex> lock(mutex_);
        return f(static_cast<const State&>(state_));
    }

private:
    mutable std::mutex mutex_;
    State state_;
};

}  // namespace nclink::agent_detail
