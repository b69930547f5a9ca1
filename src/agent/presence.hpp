// Who is online (3.21-3.23, 8.2.16): every terminal's state as the agent
// sees it, from Notify/State (the terminals' own retained state and last
// wills) and from the DTUs it publishes (liveness: no DTU for a configured
// time = offline). Pure bookkeeping: the caller passes the time, holds the
// lock and publishes what changed.
#pragma once

#include <nclink/clock.hpp>

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <queue>
#include <string>
#include <vector>

namespace nclink::agent_detail {

enum class Status { unknown, online, offline };
const char* to_wire(Status status) noexcept;  ///< "unknown" | "online" | "offline"

enum class Kind { unknown, adapter, application };
const char* to_string(Kind kind) noexcept;  ///< "" | "adapter" | "application"
Kind kind_from_string(const std::string& text) noexcept;

class Presence {
public:
    Presence(std::chrono::milliseconds adapter_liveness, std::chrono::milliseconds application_liveness)
        : adapter_liveness_(adapter_liveness), application_liveness_(application_liveness) {}

    /// A DTU published by `tid` (anything but Notify/State). Returns true when
    /// this brought it online from offline/unknown (the agent announces it).
    bool saw_dtu(const std::string& tid, Clock::Steady now, std::int64_t wall_s);
    /// A Notify/State for `tid`. Returns true when the status changed.
    bool set_state(const std::string& tid, Status status, Clock::Steady now, std::int64_t wall_s);
    /// Terminals whose liveness ran out at `now`; they are offline from now
    /// on. An adapter asked by questions() goes only once its answer window
    /// passed without a DTU from it. The housekeeping tick calls questions()
    /// and then expire() with the same `now`: each returns its share of the
    /// terminals that fell due.
    std::vector<std::string> expire(Clock::Steady now);
    /// Adapters whose liveness ran out at `now`, asked for the first time:
    /// the caller sends each a request; any DTU from it within
    /// `answer_window` keeps it online (its last will may have died with its
    /// broker node, or its link hangs, while it is there). Empty while
    /// questions are off (an answer window of 0, the default).
    std::vector<std::string> questions(Clock::Steady now);
    void set_answer_window(std::chrono::milliseconds window) {
        answer_window_ = window;
        reschedule_all();
    }

    /// New liveness times (a configuration reload); they count from each
    /// terminal's last DTU as before.
    void set_liveness(std::chrono::milliseconds adapter, std::chrono::milliseconds application) {
        adapter_liveness_ = adapter;
        application_liveness_ = application;
        reschedule_all();
    }

    /// Adapter/application, once the traffic (or the allowlist) said so. An
    /// adapter stays an adapter.
    void set_kind(const std::string& tid, Kind kind);
    /// Known from the persisted state (status unknown until something arrives).
    void remember(const std::string& tid, Kind kind, std::int64_t last_alive_s);

    Status status(const std::string& tid) const;
    Kind kind(const std::string& tid) const;
    /// How many times `tid` came online: a registration belongs to one such
    /// period (a new connection starts a new one).
    std::uint64_t online_periods(const std::string& tid) const;
    std::int64_t last_alive_s(const std::string& tid) const;
    std::vector<std::string> known() const;
    /// Checks waiting in the tick's queue (tests: at most one per terminal).
    std::size_t queued() const { return due_.size(); }

private:
    struct Entry {
        Kind kind = Kind::unknown;
        Status status = Status::unknown;
        std::optional<Clock::Steady> last_dtu;  ///< liveness runs from here
        std::optional<Clock::Steady> asked;     ///< questions(): when its liveness ran out
        std::int64_t last_alive_s = 0;
        std::uint64_t online_periods = 0;
        std::optional<Clock::Steady> due;  ///< when its item in due_ falls due (none: not queued)
    };
    // A terminal's next check, in a queue ordered by time: the tick looks at
    // the terminals that fell due, not at every terminal (at 10,000 machines
    // and a 20 ms tick, scanning them all took a quarter of the agent's CPU
    // and held its lock against the DTUs waiting to be handled).
    struct Due {
        Clock::Steady at;
        std::string tid;
        bool operator>(const Due& other) const { return at > other.at; }
    };
    std::chrono::milliseconds liveness_of(const Entry& e) const;
    bool asks(const Entry& e) const;  ///< an adapter, questions on
    /// Online with a liveness time that has passed since its last DTU.
    bool ran_out(const Entry& e, Clock::Steady now) const;
    /// Queues `e` for the end of its liveness, when it can run out.
    void schedule(const std::string& tid, Entry& e);
    /// Queues `e` at `at` unless it is queued for that time or earlier (a
    /// DTU only moves the end of liveness later: no queue work per DTU).
    void queue(const std::string& tid, Entry& e, Clock::Steady at);
    /// The liveness times or the answer window changed: every terminal anew.
    void reschedule_all();
    /// Takes the terminals due at `now` into asking_ and gone_.
    void advance(Clock::Steady now);

    std::chrono::milliseconds adapter_liveness_;
    std::chrono::milliseconds application_liveness_;
    std::chrono::milliseconds answer_window_{0};
    std::map<std::string, Entry> entries_;
    std::priority_queue<Due, std::vector<Due>, std::greater<Due>> due_;
    std::vector<std::string> asking_, gone_;  // fell due, not yet taken by questions()/expire()
};

}  // namespace nclink::agent_detail
