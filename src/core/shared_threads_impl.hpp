// The insides of nclink::SharedThreads, for the modules that take their
// threads from it (adapter, sampling). Nothing public includes this.
#pragma once

#include "core/deadline_watchdog.hpp"
#include "core/executor.hpp"
#include "core/poll_host.hpp"
#include "core/worker_pool.hpp"

#include <nclink/shared_threads.hpp>

#include <memory>
#include <mutex>

namespace nclink::detail {
class MqttLoop;  // transport module: made there, only held here
}

namespace nclink {

struct NCLINK_LOCAL SharedThreads::Impl {
    explicit Impl(const SharedThreadsOptions& options);
    detail::PollHost timers;
    std::shared_ptr<detail::Executor> requests;
    detail::DeadlineWatchdog watchdog;
    detail::WorkerPool drivers;
    std::size_t request_threads = 0;
    /// SharedThreadsOptions::shared_mqtt_io. The first adapter that connects
    /// makes the loop (transport/mqtt_loop.hpp).
    bool multiplexed_mqtt = false;
    std::mutex mqtt_loop_mutex;
    std::shared_ptr<detail::MqttLoop> mqtt_loop;
};

}  // namespace nclink
