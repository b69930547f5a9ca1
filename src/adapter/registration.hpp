// The adapter's side of Register/Request (8.2.1, 8.2.2) as a policy with no
// threads of its own: which answer belongs to the request out, whether the
// adapter counts as registered, and when to ask again. An agent is optional
// (docs/wire.md: an adapter serves whether or not one answers), so an
// unanswered request is retried with a growing interval, for ever. Each wait
// is drawn within a quarter of that interval either side: the machines of a plant
// that start (or reconnect after a broker restart) together time out
// together, and without the spread their retries would reach the agent's
// one connection together too, one wave per doubling.
// Thread-safe: the link thread sends, the transport thread answers, the
// housekeeping thread ticks.
#pragma once

#include <nclink/clock.hpp>
#include <nclink/dtu.hpp>

#include <chrono>
#include <cstdint>
#include <mutex>
#include <random>
#include <string>

namespace nclink::adapter_detail {

class Registration {
public:
    /// `seed`: this run's own (the terminal's id and run, hashed), so two
    /// machines draw different waits.
    Registration(std::chrono::milliseconds timeout, std::chrono::milliseconds retry_max, std::uint64_t seed)
        : timeout_(timeout), retry_max_(retry_max), random_(static_cast<std::uint_fast32_t>(seed ^ (seed >> 32))) {}

    /// A Register/Request with @id `msg_id` went out at `now`.
    void sent(std::string msg_id, Clock::Steady now);

    enum class Answer { ignored, accepted, refused };
    /// A Register/Response for this terminal. Answers to an older request
    /// (another @id) are ignored; one without @id is taken as ours.
    Answer answered(const RegisterResponse& response);

    struct Tick {
        bool resend = false;                   ///< send Register/Request again now
        std::chrono::milliseconds gave_up{0};  ///< >0: the request just timed out; next try after this (jittered)
        bool first_give_up = false;            ///< the first time out since the last answer (log it louder)
    };
    /// Called by the housekeeping loop. `connected`: a resend can go out now.
    Tick tick(Clock::Steady now, bool connected);

    bool registered() const;

private:
    const std::chrono::milliseconds timeout_;
    const std::chrono::milliseconds retry_max_;
    mutable std::mutex mutex_;
    bool pending_ = false;  // a request is out, unanswered
    std::string msg_id_;
    Clock::Steady deadline_{};
    std::chrono::milliseconds backoff_{0};  // the interval before its spread
    std::minstd_rand random_;
    bool retry_armed_ = false;
    Clock::Steady retry_at_{};
    bool registered_ = false;
};

}  // namespace nclink::adapter_detail
