// Registration (8.2.1/8.2.2): which terminals are registered, and the answer
// to a Register/Request. Pure bookkeeping under the agent's lock.
#pragma once

#include "agent/presence.hpp"
#include "agent/terminal_id.hpp"

#include <nclink/dtu.hpp>

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace nclink::agent_detail {

struct Registration {
    Kind kind = Kind::unknown;
    std::int64_t registered_at_s = 0;
    std::string msg_id;                        ///< "@id" of the accepted request (a resend with it is answered OK again)
    std::uint64_t period = 0;                  ///< Presence::online_periods() when accepted (0 = from the state file)
    std::optional<Clock::Steady> answered_at;  ///< when this agent last answered it OK (not persisted)
};

class Registrar {
public:
    Registrar(TerminalIdRule rule, RegistrationPolicy policy) : rule_(std::move(rule)), policy_(std::move(policy)) {}

    struct Decision {
        ResponseStatus status;
        std::string why;  ///< for the log when refused
    };

    /// Answers a Register/Request and records the registration when accepted:
    ///  414 for an id the rule refuses; 301 for an id not on a closed
    ///  allowlist, a wrong or missing password (privateInfo.password), or an
    ///  adapter id whose registration is live -- accepted in the current
    ///  online period of a terminal that is online now (8.2.2.3: one valid
    ///  connection per id). Applications have no last will, so the agent
    ///  cannot tell a restart from a second instance: their new
    ///  registration replaces the old one.
    Decision decide(const RegisterRequest& request, const Presence& presence, std::int64_t wall_s);

    /// This agent answered `tid`'s accepted registration at `now`.
    void answered(const std::string& tid, Clock::Steady now);
    /// A resend of a request this agent answered OK less than `quiet` ago:
    /// the same "@id" in the same online period. The answer is still on its
    /// way (QoS 1, to the connection that asked), only queued behind others
    /// while the agent is busy; answering each resend again only lengthened
    /// that queue (docs/agent.md).
    bool resent_while_answered(const std::string& tid, const std::string& msg_id, std::uint64_t period, Clock::Steady now,
                               std::chrono::milliseconds quiet) const;
    /// A registration another agent accepted (seen as Register/Response OK).
    void record(const std::string& tid, Kind kind, std::int64_t wall_s, std::uint64_t period);
    void restore(const std::string& tid, Registration registration) { registrations_[tid] = std::move(registration); }

    /// A new rule and policy (a configuration reload); the registrations stay.
    void set_policy(TerminalIdRule rule, RegistrationPolicy policy) {
        rule_ = std::move(rule);
        policy_ = std::move(policy);
    }

    bool valid_id(const std::string& tid) const { return rule_.check(tid).ok(); }
    bool registered(const std::string& tid) const { return registrations_.count(tid) != 0; }
    const std::map<std::string, Registration>& all() const { return registrations_; }
    /// The allowlist's kind for a terminal, if it names one.
    Kind listed_kind(const std::string& tid) const;

private:
    TerminalIdRule rule_;
    RegistrationPolicy policy_;
    std::map<std::string, Registration> registrations_;
};

/// The "@id" as text (strings verbatim, other scalars dumped); "" when absent.
std::string id_text(const MessageId& id);

}  // namespace nclink::agent_detail
