// What an MQTT transport counts and remembers about its link (the
// TransportStats besides the outbox's) and how it announces a state change:
// one piece for the paho and the libmosquitto transports, so both report
// and log a link the same way (docs/security.md: programs exit on `refused`),
// and which broker of the failover list (broker_list.hpp) the link is on.
#pragma once

#include <nclink/log.hpp>
#include <nclink/transport.hpp>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <set>
#include <string>
#include <string_view>

namespace nclink::transport_detail {

class LinkRecord {
public:
    LinkRecord(Logger logger, std::string broker_url, std::string client_id)
        : logger_(std::move(logger)), client_id_(std::move(client_id)), broker_(broker_url), last_connected_(broker_url) {}

    /// Thread-safe; never concurrently with itself: a transition is logged
    /// and handed to the handler, a repeat of the current state is not.
    void set_state(LinkState next, std::string_view detail, const LinkStateHandler& handler) {
        std::lock_guard<std::mutex> lock(state_mutex_);
        if (state_ == next) return;
        state_ = next;
        logger_.info("mqtt: {} ({})", to_string(next), detail);
        if (handler) handler(next, detail);
    }
    LinkState state() const { return state_; }

    /// A connection attempt to broker() failed: logged before it is
    /// published, so a program that exits on a refusal prints its own line
    /// last. `next`: the broker of the failover list tried next, when the
    /// transport moves on to another one (its URL), else "".
    void attempt_failed(const std::string& why, bool refused, std::chrono::milliseconds retry, const std::string& next = {}) {
        std::lock_guard<std::mutex> lock(failure_mutex_);
        if (next.empty()) logger_.warn("mqtt: connect to {} failed: {} (retry in {} ms)", broker_, why, retry.count());
        else logger_.warn("mqtt: connect to {} failed: {} (failing over: {} in {} ms)", broker_, why, next, retry.count());
        ++connect_failures_;
        last_error_ = why;
        judge(refused);
        if (!next.empty()) broker_ = next;
    }
    /// The connection to broker() was lost after `lasted`, before it was
    /// stable (`stable_after`, backoff.hpp): a failed attempt
    /// (connection_lost.hpp). `next`: the broker of the failover list tried
    /// next when the transport moves on (its URL; the move is logged as a
    /// failed attempt's is, and counted as a failover once connected there),
    /// else "".
    void lost_early(std::chrono::milliseconds lasted, std::chrono::milliseconds stable_after, std::chrono::milliseconds retry,
                    const std::string& next = {}) {
        std::lock_guard<std::mutex> lock(failure_mutex_);
        if (next.empty())
            logger_.info("mqtt: the connection to {} lasted {} ms (stable after {} ms): next attempt in {} ms", broker_,
                         lasted.count(), stable_after.count(), retry.count());
        else {
            logger_.warn("mqtt: the connection to {} lasted {} ms (stable after {} ms): failing over: {} in {} ms", broker_,
                         lasted.count(), stable_after.count(), next, retry.count());
            broker_ = next;
        }
    }
    /// A later finding about the last attempt (a TLS handshake of our own).
    void attempt_named(const std::string& why, bool refused) {
        std::lock_guard<std::mutex> lock(failure_mutex_);
        logger_.warn("mqtt: connect to {} failed: {}", broker_, why);
        last_error_ = why;
        judge(refused);
    }
    /// How many brokers the failover list has (broker_list.hpp): a refusal
    /// stands (TransportStats::refused) once each of them refused.
    void brokers(std::size_t count) {
        std::lock_guard<std::mutex> lock(failure_mutex_);
        broker_count_ = std::max<std::size_t>(count, 1);
    }
    /// The broker the next attempt goes to (a failover without a failed
    /// attempt of its own: none yet; set by attempt_failed() otherwise).
    void trying(const std::string& url) {
        std::lock_guard<std::mutex> lock(failure_mutex_);
        broker_ = url;
    }
    /// The URL of the broker connected to or tried next.
    std::string broker() const {
        std::lock_guard<std::mutex> lock(failure_mutex_);
        return broker_;
    }
    /// Connected to broker(). A connection to another broker than the last
    /// one (the first: than broker_url) is a failover: counted and logged.
    void connected() {
        ++connects_;
        std::lock_guard<std::mutex> lock(failure_mutex_);
        last_error_.clear();
        refused_ = false;
        refused_by_.clear();
        if (broker_ != last_connected_) {
            ++failovers_;
            logger_.warn("mqtt: failed over from {} to {} (failover {})", last_connected_, broker_, failovers_.load());
            last_connected_ = broker_;
        }
    }
    /// A persistent session the broker no longer had after a reconnection:
    /// what it queued for us while we were away is gone, the one outage
    /// docs/delivery.md cannot cover, so it is never silent.
    void session_lost() {
        ++sessions_lost_;
        logger_.warn(
            "mqtt: the broker kept no session for client id '{}': what it held for us while we were away is "
            "lost (broker restarted without working persistence, or the session expired)",
            client_id_);
    }
    void received() { ++received_; }
    /// The link was dropped as dead: nothing in flight acknowledged for `waited`.
    void stalled(std::chrono::milliseconds waited, std::size_t in_flight) {
        ++stalled_links_;
        logger_.warn(
            "mqtt: {} message(s) in flight to {} and none acknowledged for {} ms although the link is up: "
            "taking it for dead, reconnecting and sending them again",
            in_flight, broker(), waited.count());
    }
    void nodelay_sockets(int n) { nodelay_sockets_ = n; }

    /// Everything but the outbox's part.
    void fill(TransportStats& s) const {
        s.received = received_;
        s.connects = connects_;
        s.tcp_nodelay_sockets = nodelay_sockets_;
        s.sessions_lost = sessions_lost_;
        s.stalled_links = stalled_links_;
        s.connect_failures = connect_failures_;
        s.failovers = failovers_;
        std::lock_guard<std::mutex> lock(failure_mutex_);
        s.last_error = last_error_;
        s.refused = refused_;
        s.broker = broker_;
    }

private:
    // Under failure_mutex_: the last attempt to broker_ was refused (or not).
    void judge(bool refused) {
        if (refused) refused_by_.insert(broker_);
        else refused_by_.erase(broker_);
        refused_ = refused && refused_by_.size() >= broker_count_;
    }

    const Logger logger_;
    const std::string client_id_;
    std::mutex state_mutex_;  // serializes state transitions and the state handler
    std::atomic<LinkState> state_{LinkState::disconnected};
    std::atomic<std::uint64_t> received_{0};
    std::atomic<std::uint64_t> connects_{0};
    std::atomic<int> nodelay_sockets_{0};
    std::atomic<std::uint64_t> connect_failures_{0};
    std::atomic<std::uint64_t> sessions_lost_{0};
    std::atomic<std::uint64_t> stalled_links_{0};
    std::atomic<std::uint64_t> failovers_{0};
    mutable std::mutex failure_mutex_;  // last_error_, refused_, broker_, last_connected_
    std::string last_error_;
    bool refused_ = false;
    std::string broker_;          ///< connected to, or tried next
    std::string last_connected_;  ///< of the last connection (before the first: broker_url)
    std::size_t broker_count_ = 1;
    std::set<std::string> refused_by_;  ///< brokers whose last attempt was refused, since the last connection
};

}  // namespace nclink::transport_detail
