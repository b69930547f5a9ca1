#include "transport/outbox.hpp"

#include <algorithm>

namespace nclink::transport_detail {

Outbox::Outbox(OutboxLimits limits, SendFn send, Logger logger, core_detail::PollHost* work, bool link_copies)
    : limits_(limits), send_(std::move(send)), link_copies_(link_copies), logger_(std::move(logger)), window_(limits.max_in_flight) {
    spares_.reserve(kSpares);
    sender_.start(work, "nclink-outbox", [this](core_detail::PollHost::Time) { return send_waiting(); });
}

Outbox::~Outbox() { stop(); }

void Outbox::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    drained_.notify_all();
    sender_.stop();  // returns once no turn of the sender runs or will
}

Result<void> Outbox::push(Message message) {
    const std::size_t size = cost(message);
    bool send_now = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopping_) return make_error(ErrorCode::unavailable, "transport stopped");
        if (size > limits_.max_bytes)
            return make_error(ErrorCode::memory_configured,
                              fmt::format("message of {} bytes exceeds the {}-byte buffer", size, limits_.max_bytes));
        while (bytes_ + size > limits_.max_bytes && entries_.size() > in_flight_) drop_oldest_waiting_locked();
        std::shared_ptr<Message> kept;
        if (!spares_.empty()) {
            kept = std::move(spares_.back());
            spares_.pop_back();
            *kept = std::move(message);
        } else {
            kept = std::make_shared<Message>(std::move(message));
        }
        entries_.push_back(Entry{std::move(kept), 0});
        bytes_ += size;
        send_now = can_send_locked() && entries_.size() - in_flight_ == 1;
    }
    // Fast path: link up and nothing waiting ahead of this message, so hand it
    // over on the caller's thread and save a thread wake-up per message (a
    // request/response round trip is a few hundred microseconds here; each
    // wake-up costs ~25 us). try_lock: never wait behind the sender thread,
    // which will pick the message up itself.
    if (send_now && send_mutex_.try_lock()) {
        send_first_waiting();
        send_mutex_.unlock();
    } else {
        sender_.wake();
    }
    return ok_result();
}

bool Outbox::can_send_locked() const {
    return link_up_ && !stopping_ && in_flight_ < window_ && std::chrono::steady_clock::now() >= paused_until_;
}

// Caller holds send_mutex_, which keeps hand-overs in pick (= publish) order
// whichever thread makes them.
bool Outbox::send_first_waiting() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!can_send_locked()) return false;
    auto next = std::find_if(entries_.begin(), entries_.end(), [](const Entry& e) { return e.attempt == 0; });
    if (next == entries_.end()) return false;
    const std::uint64_t attempt = next_attempt_++;
    next->attempt = attempt;
    ++in_flight_;
    std::shared_ptr<Message> message = next->message;  // the entry may be erased while we send
    lock.unlock();
    const bool accepted = send_(message, attempt);
    lock.lock();
    // Let go under the lock, so recycle_locked() sees every holder; the last
    // one when the link delivered it during the send (a QoS 0 publish).
    recycle_locked(std::move(message));
    if (!accepted) put_back_locked(attempt);
    return true;
}

void Outbox::drop_oldest_waiting_locked() {
    auto it = std::find_if(entries_.begin(), entries_.end(), [](const Entry& e) { return e.attempt == 0; });
    if (it == entries_.end()) return;
    const std::size_t size = cost(*it->message);
    bytes_ -= size;
    ++dropped_;
    dropped_bytes_ += size;
    if (drop_burst_++ == 0)
        logger_.warn("offline buffer full ({} bytes): dropping oldest messages, first on {}", limits_.max_bytes,
                     it->message->topic);
    recycle_locked(std::move(it->message));
    entries_.erase(it);
}

void Outbox::recycle_locked(std::shared_ptr<Message> message) {
    // The only other holders, an entry and a send in progress, let go
    // under mutex_, so use_count() 1 read here means this is the last one.
    if (!link_copies_ || message.use_count() != 1 || spares_.size() >= kSpares) return;
    // Its text goes now: a kept spare must not hold a DTU of megabytes.
    *message = Message{};
    spares_.push_back(std::move(message));
}

void Outbox::link_up() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        link_up_ = true;
        paused_until_ = {};
        if (drop_burst_ > 1) logger_.warn("offline buffer dropped {} messages in total so far", dropped_);
        drop_burst_ = 0;
    }
    sender_.wake();
}

void Outbox::set_window(std::size_t max_in_flight) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        window_ = std::max<std::size_t>(1, std::min(max_in_flight, limits_.max_in_flight));
    }
    sender_.wake();
}

void Outbox::link_down() {
    std::lock_guard<std::mutex> lock(mutex_);
    link_up_ = false;
    for (auto& entry : entries_) entry.attempt = 0;
    in_flight_ = 0;
}

void Outbox::delivered(std::uint64_t attempt) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = std::find_if(entries_.begin(), entries_.end(), [attempt](const Entry& e) { return e.attempt == attempt; });
        if (it == entries_.end()) return;  // a late answer for an attempt already put back
        bytes_ -= cost(*it->message);
        --in_flight_;
        ++published_;
        recycle_locked(std::move(it->message));
        entries_.erase(it);
        if (entries_.empty()) drained_.notify_all();
        // Wake the sender only when the window held something back: an
        // acknowledgement comes on the client library's receive thread, which
        // a gateway shares between all its machines (1,000 acks a second at
        // 1,000 machines), and a futile wake-up there costs a futex call and
        // a thread switch (docs/performance.md "Fleet").
        if (entries_.size() <= in_flight_) return;
    }
    sender_.wake();
}

void Outbox::failed(std::uint64_t attempt) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        put_back_locked(attempt);
    }
    sender_.wake();
}

bool Outbox::wait_drained(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return drained_.wait_for(lock, timeout, [this] { return entries_.empty() || stopping_; }) && entries_.empty();
}

core_detail::PollHost::Time Outbox::send_waiting() {
    std::unique_lock<std::mutex> lock(mutex_);
    ++sender_wakeups_;
    for (std::size_t sent = 0; !stopping_; ++sent) {
        const auto now = std::chrono::steady_clock::now();
        const bool waiting = entries_.size() > in_flight_;
        if (!waiting || !can_send_locked()) {
            if (waiting && link_up_ && now < paused_until_) return paused_until_;
            return core_detail::PollHost::Time::max();  // push(), an ack, link_up() or set_window() wakes it
        }
        // A backlog of thousands (a reconnect) is sent in turns, so the
        // other machines on the shared threads are not held up behind it.
        if (sent == kSendsPerTurn) return now;
        // Always the first waiting entry: publish order is kept even after
        // messages were put back by link_down() or failed().
        lock.unlock();
        {
            std::lock_guard<std::mutex> sending(send_mutex_);
            send_first_waiting();
        }
        lock.lock();
    }
    return core_detail::PollHost::Time::max();
}

void Outbox::put_back_locked(std::uint64_t attempt) {
    auto it = std::find_if(entries_.begin(), entries_.end(), [attempt](const Entry& e) { return e.attempt == attempt; });
    if (it == entries_.end()) return;
    it->attempt = 0;
    --in_flight_;
    // The link refused or lost it: retry shortly rather than spin on a link
    // that is going down (link_down()/link_up() will follow if it is).
    paused_until_ = std::chrono::steady_clock::now() + kRetryPause;
}

void Outbox::fill_stats(TransportStats& stats) const {
    std::lock_guard<std::mutex> lock(mutex_);
    stats.published = published_;
    stats.dropped = dropped_;
    stats.dropped_bytes = dropped_bytes_;
    stats.buffered = entries_.size() - in_flight_;
    stats.buffered_bytes = bytes_;
    stats.in_flight = in_flight_;
}

}  // namespace nclink::transport_detail
