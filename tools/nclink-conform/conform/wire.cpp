#include "conform/wire.hpp"

#include <fmt/format.h>

namespace nclink::conform {
namespace {
// Samples of fast channels pile up; a run keeps this many messages at most
// (the oldest go first; checks look at recent windows).
constexpr std::size_t max_log = 200000;

std::int64_t wall_now_ms() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}
}  // namespace

Wire::Wire(Transport& transport, std::string ex_cid) : transport_(transport), ex_(std::move(ex_cid)) {
    // Thread: the transport's callback thread (never blocks: append and notify).
    transport_.set_message_handler([this](const Message& m) { on_message(m); });
    transport_.set_state_handler([this](LinkState state, std::string_view) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            link_ = state;
        }
        arrived_.notify_all();
    });
}

Wire::~Wire() { close(); }

void Wire::close() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (closed_) return;
        closed_ = true;
    }
    transport_.stop(std::chrono::milliseconds(500));
}

void Wire::on_message(const Message& message) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        log_.push_back(Captured{next_seq_++, message, wall_now_ms(), std::chrono::steady_clock::now()});
        if (log_.size() > max_log) {
            log_.pop_front();
            ++dropped_;
        }
    }
    arrived_.notify_all();
}

Result<void> Wire::connect(const std::vector<std::string>& filters, std::chrono::milliseconds timeout) {
    const std::string sync_topic = fmt::format("nclink-conform/{}/sync", ex_);
    std::vector<std::string> all = filters;
    all.push_back(sync_topic);
    if (auto s = transport_.subscribe(all, 1); !s) return s;
    if (auto s = transport_.start(); !s) return s;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    {
        std::unique_lock<std::mutex> lock(mutex_);
        if (!arrived_.wait_until(lock, deadline, [&] { return link_ == LinkState::connected; }))
            return make_error(ErrorCode::timeout, "no connection to the broker");
    }
    // A message of our own through the broker: the subscriptions made before
    // it are in force once it comes back.
    const auto from = mark();
    const std::string token = next_msg_id();
    if (auto p = publish(sync_topic, Json{{"sync", token}}); !p) return p;
    auto echoed = wait_for(
        from,
        [&](const Captured& c) { return c.message.topic == sync_topic && c.message.payload.find(token) != std::string::npos; },
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()));
    if (!echoed) return make_error(ErrorCode::timeout, "the broker did not deliver the tester's own message");
    return ok_result();
}

Result<void> Wire::publish(const std::string& topic, const Json& payload, int qos) {
    return transport_.publish(Message{topic, payload.dump(-1, ' ', false, Json::error_handler_t::replace), qos, false});
}

std::uint64_t Wire::mark() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return next_seq_;
}

std::optional<Captured> Wire::wait_for(std::uint64_t from, const MessagePredicate& pred, std::chrono::milliseconds timeout) {
    auto found = wait_count(from, pred, 1, timeout);
    if (found.empty()) return std::nullopt;
    return std::move(found.front());
}

std::vector<Captured> Wire::wait_count(std::uint64_t from, const MessagePredicate& pred, std::size_t count,
                                       std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::vector<Captured> found;
    std::uint64_t scanned = from;  // next seq to look at
    std::unique_lock<std::mutex> lock(mutex_);
    while (true) {
        const std::uint64_t first = log_.empty() ? next_seq_ : log_.front().seq;
        for (std::uint64_t s = std::max(scanned, first); s < next_seq_; ++s) {
            const Captured& c = log_[static_cast<std::size_t>(s - first)];
            if (pred(c)) found.push_back(c);
            if (found.size() >= count) return found;
        }
        scanned = next_seq_;
        if (arrived_.wait_until(lock, deadline) == std::cv_status::timeout && next_seq_ == scanned) return found;
    }
}

std::vector<Captured> Wire::collect(std::uint64_t from, const MessagePredicate& pred) const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Captured> out;
    for (const auto& c : log_)
        if (c.seq >= from && pred(c)) out.push_back(c);
    return out;
}

std::string Wire::next_msg_id() {
    std::lock_guard<std::mutex> lock(mutex_);
    return fmt::format("{}-{}", ex_, ++ids_);
}

bool Wire::connected() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return link_ == LinkState::connected;
}

}  // namespace nclink::conform
