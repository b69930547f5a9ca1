#include "core/shared_threads_impl.hpp"

#include "core/heap_release.hpp"

#include <nclink/heap.hpp>

#include <algorithm>
#include <thread>

namespace nclink {

namespace {
std::size_t sized_to_box(std::size_t asked) {
    if (asked > 0) return asked;
    return std::max<std::size_t>(2, std::thread::hardware_concurrency());
}
}  // namespace

SharedThreads::Impl::Impl(const SharedThreadsOptions& options)
    : timers(sized_to_box(options.timer_threads), "nclink-timer"),
      work(sized_to_box(options.work_threads), "nclink-work"),
      requests(std::make_shared<core_detail::Executor>(sized_to_box(options.request_threads))),
      drivers(sized_to_box(options.driver_threads), std::chrono::milliseconds(options.driver_stuck_ms), "nclink-driver"),
      request_threads(sized_to_box(options.request_threads)),
      multiplexed_mqtt(options.shared_mqtt_io),
      mqtt_connect_max(options.mqtt_connect_max) {
    // The top of the main heap is kept as keep_freed_heap()'s default keeps it.
    heap_release = work.add([release = core_detail::PeriodicHeapRelease([] {
                                 (void)core_detail::release_freed_heap(max_heap_keep_bytes);
                             })](core_detail::PollHost::Time now) mutable { return release.poll(now); });
}

SharedThreads::SharedThreads(SharedThreadsOptions options) : impl_(std::make_unique<Impl>(options)) {}

SharedThreads::~SharedThreads() {
    impl_->timers.stop();
    impl_->work.stop();
    impl_->watchdog.stop();
    impl_->requests->stop();
    impl_->drivers.stop();
}

double SharedThreads::Impl::next_sampling_phase() {
    std::uint32_t n = phases_given.fetch_add(1, std::memory_order_relaxed) % kSamplingPhases;
    double phase = 0, bit = 0.5;
    for (; n != 0; n >>= 1, bit /= 2)
        if (n & 1u) phase += bit;
    return phase;
}

std::size_t SharedThreads::timer_threads() const { return impl_->timers.threads(); }
std::size_t SharedThreads::request_threads() const { return impl_->request_threads; }
std::size_t SharedThreads::work_threads() const { return impl_->work.threads(); }
std::size_t SharedThreads::driver_threads() const { return impl_->drivers.threads(); }

}  // namespace nclink
