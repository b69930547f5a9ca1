// The insides of nclink::SharedThreads, for the modules that take their
// threads from it (adapter, sampling). Nothing public includes this.
#pragma once

#include "core/deadline_watchdog.hpp"
#include "core/executor.hpp"
#include "core/poll_host.hpp"
#include "core/worker_pool.hpp"

#include <nclink/shared_threads.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>

namespace nclink::transport_detail {
class MqttLoop;  // transport module: made there, only held here
}

namespace nclink {

struct NCLINK_LOCAL SharedThreads::Impl {
    explicit Impl(const SharedThreadsOptions& options);
    core_detail::PollHost timers;
    /// Every adapter's serial background work (core/serial_work.hpp): not
    /// on `timers`, so a burst of publishing or a spool's disk write never
    /// holds up a sampling deadline.
    core_detail::PollHost work;
    std::shared_ptr<core_detail::Executor> requests;
    core_detail::DeadlineWatchdog watchdog;
    core_detail::WorkerPool drivers;
    std::size_t request_threads = 0;
    /// SharedThreadsOptions::shared_mqtt_io. The first adapter that connects
    /// makes the loop (transport/mqtt_loop.hpp).
    bool multiplexed_mqtt = false;
    std::size_t mqtt_connect_max = 0;  ///< SharedThreadsOptions::mqtt_connect_max
    std::mutex mqtt_loop_mutex;
    std::shared_ptr<transport_detail::MqttLoop> mqtt_loop;

    /// Where in its channels' interval grid the next adapter samples, a
    /// fraction in [0, 1): 0, 1/2, 1/4, 3/4, 1/8, ... (the base-2 van der
    /// Corput sequence), so any number of adapters started one after another
    /// spread evenly over the period. On one grid, every machine's 100 ms
    /// channel came due at the same instant and a gateway of 1,000 machines
    /// did all its sampling in one burst per tick, which every Query
    /// arriving then waited behind.
    /// Only kSamplingPhases places (a power of two): adapters in one place
    /// still share a wake-up, where a place each cost a wake-up per machine
    /// per tick (bench_fleet, 1,000 machines: 41-43 % CPU against 28-30 %).
    double next_sampling_phase();
    static constexpr std::uint32_t kSamplingPhases = 64;
    std::atomic<std::uint32_t> phases_given{0};

    /// The gateway's freed memory, handed back every
    /// PeriodicHeapRelease::kEvery on a work thread (core/heap_release.hpp).
    core_detail::PollHost::Handle heap_release;
};

}  // namespace nclink
