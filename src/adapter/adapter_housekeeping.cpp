// The adapter's housekeeping (adapter_housekeeping.hpp).
#include "adapter/adapter_housekeeping.hpp"

#include "core/thread_name.hpp"

namespace nclink::adapter_detail {

Housekeeping::Housekeeping(AdapterLink& link, ApplicationWatch& applications, DropsNow drops, std::shared_ptr<const Clock> clock,
                           const Logger& logger, core_detail::PollHost* timers, std::chrono::milliseconds period)
    : link_(link),
      applications_(applications),
      drops_(std::move(drops)),
      clock_(std::move(clock)),
      timers_(timers),
      period_(period),
      drop_reporter_(logger) {}

void Housekeeping::start() {
    if (timers_) {
        entry_ = timers_->add([this](core_detail::PollHost::Time now) {
            pass();
            return now + period_;
        });
        return;
    }
    thread_ = std::thread([this] {
        core_detail::name_this_thread("nclink-house");
        run();
    });
}

void Housekeeping::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    if (timers_) timers_->remove(entry_);
}

void Housekeeping::wake() {
    if (timers_) {
        timers_->wake(entry_);
        return;
    }
    wake_.notify_all();
}

void Housekeeping::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        lock.unlock();
        pass();
        lock.lock();
        if (stopping_) break;
        wake_.wait_for(lock, kHousekeepingPeriod);
    }
}

// Registers again when no agent answered in time, releases what silent
// applications registered, and tries kept responses again.
void Housekeeping::pass() {
    const auto now = clock_->now();
    link_.tick_registration(now);
    applications_.expire(now);
    link_.retry_kept();
    // Once a second (real time: the statistics are not cheap): every
    // loss logged once per burst (drop_reporter.hpp).
    if (const auto real = std::chrono::steady_clock::now(); real - last_drop_check_ >= std::chrono::seconds(1)) {
        last_drop_check_ = real;
        drop_counts_.zero();
        if (drops_(drop_counts_)) drop_reporter_.observe(drop_counts_);
    }
}

}  // namespace nclink::adapter_detail
