// Threads that several adapters in one process share (gateway mode,
// docs/gateway.md "Threads"). Without it every adapter starts its own
// sampling scheduler, uploader, housekeeping, request workers, driver worker
// and deadline watchdog; with it they take that work from a fixed set of threads sized to
// the box, so a process serving 1,000 machines does not run thousands of
// mostly idle threads that each wake up on their own.
//
//   auto threads = std::make_shared<nclink::SharedThreads>();
//   nclink::Adapter a(config_a, driver_a, logger, threads);
//   nclink::Adapter b(config_b, driver_b, logger, threads);
//
// Each adapter's serial background work (its MQTT outbox's sender, events
// engine, method status ticker and sample spool) runs on the shared work
// threads too, each still in order per adapter. What stays per adapter: its
// MQTT connection (the terminal's own last will) and a thread per method run
// under way. A single adapter is better off without SharedThreads: its sampling
// thread then sleeps in clock_nanosleep on absolute deadlines and may run at
// real-time priority (docs/sampling.md); shared timer threads wait on a
// condition variable, which is precise to tens of microseconds, enough for
// the 10 ms .. 1 s channels of a gateway.
//
// Threading: thread-safe; must outlive every adapter using it.
#pragma once

#include <nclink/export.hpp>

#include <cstddef>
#include <memory>

namespace nclink {

struct NCLINK_API SharedThreadsOptions {
    /// Threads running every adapter's sampling scheduler, uploader and
    /// housekeeping at their deadlines. 0 = the box's cores (at least 2).
    std::size_t timer_threads = 0;
    /// Threads handling requests (Query, Set, Probe, ...) of every adapter.
    /// 0 = the box's cores (at least 2).
    std::size_t request_threads = 0;
    /// Threads calling every adapter's driver (Query reads, Set writes,
    /// bind): calls into one driver stay serialized unless the driver is
    /// concurrent. 0 = the box's cores (at least 2). A call still inside
    /// its driver after `driver_stuck_ms` no longer counts: the pool starts
    /// another thread, so one stuck driver never holds up the others.
    std::size_t driver_threads = 0;
    std::size_t driver_stuck_ms = 1000;
    /// Threads running every adapter's serial background work: its MQTT
    /// publishing (outbox), events engine, method status ticker and sample
    /// spool, each still one at a time and in order per adapter. 0 = the
    /// box's cores (at least 2).
    std::size_t work_threads = 0;
    /// The adapters' broker connections (each still its own, with its own
    /// last will) served by one I/O thread over libmosquitto and epoll
    /// instead of one I/O thread per connection (a single adapter's
    /// transport). A gateway turns it on ("mqtt_client", docs/gateway.md).
    bool shared_mqtt_io = false;
    /// With shared_mqtt_io: connections that may wait for the broker's
    /// CONNACK at once; the others wait their turn, in order, without their
    /// connect timeout running. Thousands of CONNECTs at once were answered
    /// after the timeout and sent again (docs/gateway.md). 0 = no limit.
    std::size_t mqtt_connect_max = 64;
};

class NCLINK_API SharedThreads {
public:
    explicit SharedThreads(SharedThreadsOptions options = {});
    ~SharedThreads();
    SharedThreads(const SharedThreads&) = delete;
    SharedThreads& operator=(const SharedThreads&) = delete;

    std::size_t timer_threads() const;
    std::size_t request_threads() const;
    std::size_t work_threads() const;
    /// Driver threads now: driver_threads plus replacements of stuck ones.
    std::size_t driver_threads() const;

    struct Impl;
    /// The SDK's own access (not part of the API).
    Impl& impl() const { return *impl_; }

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace nclink
