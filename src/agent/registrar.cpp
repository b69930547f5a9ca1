#include "agent/registrar.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace nclink::agent_detail {

std::string id_text(const MessageId& id) {
    if (!id) return {};
    return id->is_string() ? id->get<std::string>() : id->dump();
}

Kind Registrar::listed_kind(const std::string& tid) const {
    const auto it = policy_.terminals.find(tid);
    return it == policy_.terminals.end() ? Kind::unknown : kind_from_string(it->second.kind);
}

Registrar::Decision Registrar::decide(const RegisterRequest& request, const Presence& presence, std::int64_t wall_s) {
    const std::string& tid = request.cli_uuid;
    if (auto valid = rule_.check(tid); !valid) return {ResponseStatus(valid.error()), valid.error().message};

    const auto listed = policy_.terminals.find(tid);
    if (listed == policy_.terminals.end()) {
        if (!policy_.open) return {ResponseStatus::failure(ErrorCode::permission_denied), "not on the registration allowlist"};
    } else if (!listed->second.password.empty()) {
        const Json* given = nullptr;
        if (request.private_info && request.private_info->is_object()) {
            const auto it = request.private_info->find("password");
            if (it != request.private_info->end()) given = &*it;
        }
        if (!given || !given->is_string() || given->get<std::string>() != listed->second.password)
            return {ResponseStatus::failure(ErrorCode::permission_denied), "wrong or missing credentials"};
    }

    Kind kind = presence.kind(tid);
    if (kind == Kind::unknown) kind = listed_kind(tid);
    const std::string msg_id = id_text(request.msg_id);
    const std::uint64_t period = presence.online_periods(tid);
    if (const auto current = registrations_.find(tid); current != registrations_.end()) {
        const Registration& r = current->second;
        const bool resend = !msg_id.empty() && msg_id == r.msg_id;
        const bool live = kind == Kind::adapter && presence.status(tid) == Status::online && r.period != 0 && r.period == period;
        if (live && !resend)
            return {ResponseStatus::failure(ErrorCode::permission_denied),
                    "already registered by a terminal that is online (one live registration per id)"};
    }
    Registration& r = registrations_[tid];
    r.kind = kind;
    r.registered_at_s = wall_s;
    r.msg_id = msg_id;
    r.period = period;
    return {ResponseStatus::success(), {}};
}

void Registrar::answered(const std::string& tid, Clock::Steady now) {
    if (const auto it = registrations_.find(tid); it != registrations_.end()) it->second.answered_at = now;
}

bool Registrar::resent_while_answered(const std::string& tid, const std::string& msg_id, std::uint64_t period, Clock::Steady now,
                                      std::chrono::milliseconds quiet) const {
    const auto it = registrations_.find(tid);
    if (it == registrations_.end() || msg_id.empty()) return false;
    const Registration& r = it->second;
    return r.msg_id == msg_id && r.period != 0 && r.period == period && r.answered_at && now - *r.answered_at < quiet;
}

void Registrar::record(const std::string& tid, Kind kind, std::int64_t wall_s, std::uint64_t period) {
    Registration& r = registrations_[tid];
    if (r.kind == Kind::unknown) r.kind = kind;
    if (r.registered_at_s == 0) r.registered_at_s = wall_s;
    r.period = std::max(r.period, period);
}

}  // namespace nclink::agent_detail
