// One thread serving the broker sockets of many MQTT connections (the
// machines of a gateway) through epoll, so the cost of a packet does not grow
// with the number of connections. paho C runs every connection of a process
// on one receive thread that polls all of their sockets on each cycle: at
// 1,000 connections that thread was 45 % of a core and the Query p99 40-60 ms
// (docs/scaling.md). The loop knows nothing of MQTT: its members do the
// protocol (mosquitto_transport.cpp) and tell it which socket to watch.
#pragma once

#include "transport/connect_turns.hpp"

#include <nclink/log.hpp>
#include <nclink/shared_threads.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <vector>

namespace nclink::transport_detail {

/// A connection served by an MqttLoop. Every call is on the loop's thread,
/// never concurrently with another call to the same or any other member.
class LoopMember {
public:
    virtual ~LoopMember() = default;
    /// Its socket is readable / writable (an error or hang-up reports both).
    virtual void on_io(bool readable, bool writable) = 0;
    /// After wake(this) from any thread; several wakes may fold into one call.
    virtual void on_wake() = 0;
    /// About every `tick` of the loop: deadlines (keep-alive, retries).
    virtual void on_tick(std::chrono::steady_clock::time_point now) = 0;
};

class MqttLoop {
public:
    /// `connect_max`: members that may wait for their CONNACK at once (0 = no
    /// limit; connect_turns.hpp).
    explicit MqttLoop(Logger logger, std::chrono::milliseconds tick = std::chrono::milliseconds(100), std::size_t connect_max = 0);
    ~MqttLoop();
    MqttLoop(const MqttLoop&) = delete;
    MqttLoop& operator=(const MqttLoop&) = delete;

    /// Thread-safe. The member is served from the next loop iteration on.
    void add(LoopMember* member);
    /// Thread-safe, never from the loop thread: returns once the loop has
    /// dropped the member and will not call it again.
    void remove(LoopMember* member);
    /// Thread-safe: on_wake() soon, on the loop thread; nothing for a member
    /// that has been removed (the pointer is not touched).
    void wake(LoopMember* member);

    /// Loop thread only: the socket to watch for `member` (-1: none) and
    /// whether to report it writable. Cheap when nothing changed. Call it
    /// with -1 BEFORE closing the socket: a socket a child process
    /// inherited stays open after the close, and the kernel keeps its
    /// registration (epoll(7)); the loop then ignores it (see run()).
    void watch(LoopMember* member, int fd, bool want_write);

    /// Loop thread only: true when `member` may send its CONNECT now. False:
    /// it waits its turn and gets on_wake() when the turn comes.
    bool connect_turn(LoopMember* member) { return turns_.take(member); }
    /// Loop thread only: `member`'s attempt ended (CONNACK, failure, closed).
    void connect_done(LoopMember* member);
    /// Members waiting for their turn to connect (tests: read it when no
    /// member is left, after the last remove()).
    std::size_t connect_waiting() const { return turns_.waiting(); }

    bool in_loop_thread() const { return std::this_thread::get_id() == thread_id_.load(); }
    /// Loop iterations so far (tests: the loop sleeps when idle).
    std::uint64_t iterations() const { return iterations_.load(); }

private:
    struct Watch {
        std::uint64_t token = 0;  ///< what its epoll registration carries (never 0: the wake-up descriptor)
        int fd = -1;
        bool want_write = false;
        bool armed = false;  ///< registered and not yet reported (one-shot)
    };
    /// (Re)registers `w` for its fd, one-shot.
    void arm(Watch& w);
    void run();
    void take_requests();
    void signal();

    const Logger logger_;
    const std::chrono::milliseconds tick_;
    int epoll_fd_ = -1;
    int event_fd_ = -1;

    std::mutex mutex_;  // the request lists below
    std::condition_variable removed_;
    std::vector<LoopMember*> adds_;
    std::vector<LoopMember*> removes_;
    std::vector<LoopMember*> wakes_;  // in the order woken, repeats included
    std::uint64_t removals_done_ = 0;
    std::uint64_t removals_asked_ = 0;
    bool stopping_ = false;

    // loop thread only
    std::vector<LoopMember*> members_;
    std::unordered_map<LoopMember*, Watch> watches_;
    // The members by their watch's token: an epoll event names a token, not
    // a pointer, so a registration that outlived its member (a socket kept
    // open by a child process after the member closed it) reaches nobody.
    std::unordered_map<std::uint64_t, LoopMember*> by_token_;
    std::uint64_t next_token_ = 1;
    std::vector<LoopMember*> woken_;
    ConnectTurns turns_;

    std::atomic<std::thread::id> thread_id_{};
    std::atomic<std::uint64_t> iterations_{0};
    std::thread thread_;
};

/// The loop of a gateway's shared threads, made on first use (thread-safe).
std::shared_ptr<MqttLoop> shared_mqtt_loop(SharedThreads::Impl& threads, const Logger& logger);

}  // namespace nclink::transport_detail
