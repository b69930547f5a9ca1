// What an MQTT transport counts and remembers about its link (the
// TransportStats besides the outbox's) and how it announces a state change:
// one piece for the paho and the libmosquitto transports, so both report
// and log a link the same way (docs/security.md: programs exit on `refused`).
#pragma once

#include <nclink/log.hpp>
#include <nclink/transport.hpp>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>

namespace nclink::transport_detail {

class LinkRecord {
public:
    LinkRecord(Logger logger, std::string broker_url, std::string client_id)
        : logger_(std::move(logger)), broker_url_(std::move(broker_url)), client_id_(std::move(client_id)) {}

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

    /// A connection attempt failed: logged before it is published, so a
    /// program that exits on a refusal prints its own line last.
    void attempt_failed(const std::string& why, bool refused, std::chrono::milliseconds retry) {
        logger_.warn("mqtt: connect to {} failed: {} (retry in {} ms)", broker_url_, why, retry.count());
        ++connect_failures_;
        std::lock_guard<std::mutex> lock(failure_mutex_);
        last_error_ = why;
        refused_ = refused;
    }
    /// A later finding about the last attempt (a TLS handshake of our own).
    void attempt_named(const std::string& why, bool refused) {
        logger_.warn("mqtt: connect to {} failed: {}", broker_url_, why);
        std::lock_guard<std::mutex> lock(failure_mutex_);
        last_error_ = why;
        refused_ = refused;
    }
    void connected() {
        ++connects_;
        std::lock_guard<std::mutex> lock(failure_mutex_);
        last_error_.clear();
        refused_ = false;
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
            in_flight, broker_url_, waited.count());
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
        std::lock_guard<std::mutex> lock(failure_mutex_);
        s.last_error = last_error_;
        s.refused = refused_;
    }

private:
    const Logger logger_;
    const std::string broker_url_;
    const std::string client_id_;
    std::mutex state_mutex_;  // serializes state transitions and the state handler
    std::atomic<LinkState> state_{LinkState::disconnected};
    std::atomic<std::uint64_t> received_{0};
    std::atomic<std::uint64_t> connects_{0};
    std::atomic<int> nodelay_sockets_{0};
    std::atomic<std::uint64_t> connect_failures_{0};
    std::atomic<std::uint64_t> sessions_lost_{0};
    std::atomic<std::uint64_t> stalled_links_{0};
    mutable std::mutex failure_mutex_;  // last_error_, refused_
    std::string last_error_;
    bool refused_ = false;
};

}  // namespace nclink::transport_detail
