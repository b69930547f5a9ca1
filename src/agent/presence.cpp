#include "agent/presence.hpp"

#include <utility>

namespace nclink::agent_detail {

const char* to_wire(Status status) noexcept {
    switch (status) {
        case Status::online: return "online";
        case Status::offline: return "offline";
        case Status::unknown: break;
    }
    return "unknown";
}

const char* to_string(Kind kind) noexcept {
    switch (kind) {
        case Kind::adapter: return "adapter";
        case Kind::application: return "application";
        case Kind::unknown: break;
    }
    return "";
}

Kind kind_from_string(const std::string& text) noexcept {
    if (text == "adapter") return Kind::adapter;
    if (text == "application") return Kind::application;
    return Kind::unknown;
}

bool Presence::saw_dtu(const std::string& tid, Clock::Steady now, std::int64_t wall_s) {
    Entry& e = entries_[tid];
    e.last_dtu = now;
    e.last_alive_s = wall_s;
    e.asked.reset();
    const bool came = e.status != Status::online;
    if (came) {
        e.status = Status::online;
        ++e.online_periods;
    }
    schedule(tid, e);
    return came;
}

bool Presence::set_state(const std::string& tid, Status status, Clock::Steady now, std::int64_t wall_s) {
    Entry& e = entries_[tid];
    e.asked.reset();
    if (status == Status::online) {
        // Coming online is a sign of life; the liveness clock starts here.
        e.last_dtu = now;
        e.last_alive_s = wall_s;
    }
    if (e.status == status) return false;
    e.status = status;
    if (status == Status::online) {
        ++e.online_periods;
        schedule(tid, e);
    }
    return true;
}

std::chrono::milliseconds Presence::liveness_of(const Entry& e) const {
    // A terminal of unknown kind is treated as an application: only adapters
    // have a last will, so only for them may liveness be switched off.
    return e.kind == Kind::adapter ? adapter_liveness_ : application_liveness_;
}

bool Presence::ran_out(const Entry& e, Clock::Steady now) const {
    const auto limit = liveness_of(e);
    return e.status == Status::online && limit.count() > 0 && e.last_dtu && now - *e.last_dtu >= limit;
}

void Presence::schedule(const std::string& tid, Entry& e) {
    const auto limit = liveness_of(e);
    if (e.status != Status::online || limit.count() <= 0 || !e.last_dtu) return;
    queue(tid, e, *e.last_dtu + limit);
}

void Presence::queue(const std::string& tid, Entry& e, Clock::Steady at) {
    if (e.due && *e.due <= at) return;  // checked then; a later end of liveness is seen there
    e.due = at;
    due_.push(Due{at, tid});
}

void Presence::reschedule_all() {
    due_ = {};
    for (auto& [tid, e] : entries_) {
        e.due.reset();
        if (e.asked && asks(e)) queue(tid, e, *e.asked + answer_window_);
        else schedule(tid, e);
    }
}

void Presence::advance(Clock::Steady now) {
    while (!due_.empty() && due_.top().at <= now) {
        const Due next = due_.top();
        due_.pop();
        const auto it = entries_.find(next.tid);
        if (it == entries_.end()) continue;
        Entry& e = it->second;
        if (!e.due || *e.due != next.at) continue;  // queued again for an earlier time since
        e.due.reset();
        if (!ran_out(e, now)) {
            schedule(next.tid, e);  // a DTU came in time: its new end of liveness
            continue;
        }
        if (asks(e)) {
            if (!e.asked) {
                e.asked = now;
                asking_.push_back(next.tid);
                queue(next.tid, e, now + answer_window_);
                continue;
            }
            if (now - *e.asked < answer_window_) {
                queue(next.tid, e, *e.asked + answer_window_);
                continue;
            }
        }
        e.status = Status::offline;
        e.asked.reset();
        gone_.push_back(next.tid);
    }
}

std::vector<std::string> Presence::expire(Clock::Steady now) {
    advance(now);
    return std::exchange(gone_, {});
}

bool Presence::asks(const Entry& e) const { return answer_window_.count() > 0 && e.kind == Kind::adapter; }

std::vector<std::string> Presence::questions(Clock::Steady now) {
    advance(now);
    return std::exchange(asking_, {});
}

void Presence::set_kind(const std::string& tid, Kind kind) {
    if (kind == Kind::unknown) return;
    Entry& e = entries_[tid];
    if (e.kind == Kind::adapter) return;  // a terminal that answered requests is an adapter, whatever else it does
    e.kind = kind;
    schedule(tid, e);  // its liveness time may be shorter now
}

void Presence::remember(const std::string& tid, Kind kind, std::int64_t last_alive_s) {
    Entry& e = entries_[tid];
    if (e.kind == Kind::unknown) e.kind = kind;
    if (e.last_alive_s == 0) e.last_alive_s = last_alive_s;
}

Status Presence::status(const std::string& tid) const {
    const auto it = entries_.find(tid);
    return it == entries_.end() ? Status::unknown : it->second.status;
}

Kind Presence::kind(const std::string& tid) const {
    const auto it = entries_.find(tid);
    return it == entries_.end() ? Kind::unknown : it->second.kind;
}

std::uint64_t Presence::online_periods(const std::string& tid) const {
    const auto it = entries_.find(tid);
    return it == entries_.end() ? 0 : it->second.online_periods;
}

std::int64_t Presence::last_alive_s(const std::string& tid) const {
    const auto it = entries_.find(tid);
    return it == entries_.end() ? 0 : it->second.last_alive_s;
}

std::vector<std::string> Presence::known() const {
    std::vector<std::string> out;
    for (const auto& [tid, e] : entries_) out.push_back(tid);
    return out;
}

}  // namespace nclink::agent_detail
