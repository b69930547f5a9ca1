#include "sampling/sampling_engine.hpp"
#include "core/thread_name.hpp"

#include "sampling/channel_core.hpp"
#include "sampling/engine_shared.hpp"
#include "sampling/read_serving.hpp"
#include "sampling/realtime.hpp"
#include "sampling/scheduler.hpp"
#include "sampling/uploader.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <ctime>
#include <thread>

#include <unistd.h>

namespace nclink {

// ---- PushChannel (public, include/nclink/sampling.hpp)

namespace {
std::int64_t wall_now_ns() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_REALTIME, &ts);  // vDSO: no system call
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
const std::string kNoId;
}  // namespace

bool PushChannel::push(const SampleValue* values, std::size_t count) noexcept {
    return core_ && core_->push(values, count, wall_now_ns());
}
bool PushChannel::push(const SampleValue* values, std::size_t count, std::int64_t time_ns) noexcept {
    return core_ && core_->push(values, count, time_ns);
}
std::size_t PushChannel::points() const noexcept { return core_ ? core_->ring().width() : 0; }
const std::string& PushChannel::id() const noexcept { return core_ ? core_->spec().id : kNoId; }

}  // namespace nclink

namespace nclink::sampling_detail {

namespace {

// The fewest rows a ring has: one being written, one being read and room for
// a late upload period.
constexpr double kMinRingRows = 4;

// On shared timer threads the engine's wake-ups (a channel added or removed,
// a removed channel's last rows sampled) make its two pollables due now.
class HostWaker final : public Sleeper {
public:
    explicit HostWaker(core_detail::PollHost& host) : host_(host) {}
    void sleep_until(Clock::Steady, std::uint64_t) override {}  // the host waits, never the engine
    void wake() override {
        std::lock_guard<std::mutex> lock(mutex_);
        host_.wake(sampler_);
        host_.wake(uploader_);
    }
    void set(core_detail::PollHost::Handle sampler, core_detail::PollHost::Handle uploader) {
        std::lock_guard<std::mutex> lock(mutex_);
        sampler_ = std::move(sampler);
        uploader_ = std::move(uploader);
    }

private:
    core_detail::PollHost& host_;
    std::mutex mutex_;
    core_detail::PollHost::Handle sampler_, uploader_;
};

}  // namespace

struct SamplingEngine::State {
    explicit State(EngineDeps deps) : shared(std::move(deps)), scheduler(shared), uploader(shared) {
        if (shared.deps.timers) {
            waker = std::make_shared<HostWaker>(*shared.deps.timers);
            shared.deps.sleeper = waker;
        }
    }

    EngineShared shared;
    Scheduler scheduler;
    Uploader uploader;

    std::mutex lifecycle;  // start/stop
    bool running = false;
    std::atomic<bool> stop_sampler{false};
    std::atomic<bool> stop_uploader{false};
    std::thread sampler_thread;
    std::thread uploader_thread;
    // gateway mode: the pollables on the shared timer threads instead
    std::shared_ptr<HostWaker> waker;
    core_detail::PollHost::Handle sampler_entry, uploader_entry;

    // Safety net of the shared mode: a pollable is looked at at least once
    // a second even if a wake-up were missed (the own threads wait at most
    // Sleeper::max_wait(), 20 ms, because clock_nanosleep cannot be woken).
    static Clock::Steady capped(Clock::Steady next) {
        return std::min(next, std::chrono::steady_clock::now() + std::chrono::seconds(1));
    }

    void start_on_host() {
        const auto& config = shared.deps.config;
        RealtimeStatus rt;
        rt.fifo_priority = config.rt_priority;
        rt.timer_slack_ns = config.timer_slack_ns;
        rt.cpu = config.cpu;
        if (config.rt_priority > 0 || config.timer_slack_ns > 0 || config.cpu >= 0)
            shared.deps.logger.warn("sampling: the real-time options are not applied on shared timer threads (gateway mode)");
        {
            std::lock_guard<std::mutex> lock(shared.mutex);
            shared.realtime = rt;
        }
        core_detail::PollHost& host = *shared.deps.timers;
        sampler_entry = host.add([this](core_detail::PollHost::Time) {
            if (stop_sampler.load(std::memory_order_acquire)) return core_detail::PollHost::Time::max();
            return capped(scheduler.poll());
        });
        uploader_entry = host.add([this](core_detail::PollHost::Time) {
            if (stop_uploader.load(std::memory_order_acquire)) return core_detail::PollHost::Time::max();
            return capped(uploader.poll(false));
        });
        waker->set(sampler_entry, uploader_entry);
    }

    void sample_loop() {
        RealtimeStatus rt = apply_realtime(shared.deps.config, shared.deps.logger);
        {
            std::lock_guard<std::mutex> lock(shared.mutex);
            shared.realtime = rt;
        }
        Sleeper& sleeper = *shared.deps.sleeper;
        const Clock& clock = *shared.deps.clock;
        ReadServing serving{shared.deps.driver};
        while (!stop_sampler.load(std::memory_order_acquire)) {
            const auto seen = sleeper.wakes();
            const auto next = scheduler.poll();
            if (stop_sampler.load(std::memory_order_acquire)) break;
            serving.between_ticks(scheduler.fastest_driver_interval_ns(), next - clock.now());
            sleeper.sleep_until(std::min(next, clock.now() + sleeper.max_wait()), seen);
        }
    }

    void upload_loop() {
        Sleeper& sleeper = *shared.deps.sleeper;
        const Clock& clock = *shared.deps.clock;
        while (!stop_uploader.load(std::memory_order_acquire)) {
            const auto seen = sleeper.wakes();
            const auto next = uploader.poll(false);
            if (stop_uploader.load(std::memory_order_acquire)) break;
            sleeper.sleep_until(std::min(next, clock.now() + sleeper.max_wait()), seen);
        }
        uploader.poll(true);  // what every ring holds goes out
    }
};

SamplingEngine::SamplingEngine(EngineDeps deps) {
    if (!deps.clock) deps.clock = std::make_shared<SystemClock>();
    if (!deps.sleeper) deps.sleeper = std::make_shared<NanosleepSleeper>();
    state_ = std::make_shared<State>(std::move(deps));
}

SamplingEngine::~SamplingEngine() { stop(); }

Result<void> SamplingEngine::add_channel(ChannelSpec spec) {
    if (spec.id.empty()) return make_error(ErrorCode::parameter_missing, "sample channel without id");
    if (spec.points.empty()) return make_error(ErrorCode::syntax_error, "sample channel " + spec.id + " has no data items");
    if (!std::isfinite(spec.sample_interval_ms) || !std::isfinite(spec.upload_interval_ms) || spec.sample_interval_ms <= 0 ||
        spec.upload_interval_ms <= 0 || spec.sample_interval_ms * 1e6 < 1)
        return make_error(ErrorCode::unsupported_get_length,
                          fmt::format("sample channel {}: intervals must be positive (sampleInterval {}, uploadInterval {})",
                                      spec.id, spec.sample_interval_ms, spec.upload_interval_ms));
    if (spec.upload_interval_ms < spec.sample_interval_ms)
        return make_error(ErrorCode::unsupported_get_length,
                          fmt::format("sample channel {}: uploadInterval {} is shorter than sampleInterval {}", spec.id,
                                      spec.upload_interval_ms, spec.sample_interval_ms));
    auto& shared = state_->shared;
    const auto& config = shared.deps.config;
    const double rows_per_upload = std::max(1.0, std::floor(spec.upload_interval_ms / spec.sample_interval_ms));
    // The ring needs `ring_periods` upload periods of rows, and a floor in
    // time (`ring_min_ms`) for the uploader's lateness, which is counted in
    // milliseconds whatever the channel's rate. A floor in rows would give a
    // 300-point channel sampled once a second 64 rows (300 KB) where it needs
    // 4 (docs/performance.md, memory per machine).
    const double floor_rows = std::max(kMinRingRows, std::ceil(config.ring_min_ms / spec.sample_interval_ms));
    const double wanted = std::max(std::ceil(rows_per_upload * config.ring_periods), floor_rows);
    // Capped at half of size_t, so the double converts back exactly.
    const std::size_t max_rows = std::min(std::max(static_cast<std::size_t>(kMinRingRows), config.ring_max_rows),
                                          std::numeric_limits<std::size_t>::max() / 2);
    const std::size_t capacity = static_cast<std::size_t>(std::min(wanted, static_cast<double>(max_rows)));
    // The ring is allocated whole, now: one that cannot be addressed (more
    // than half the address space; a large ring_max_rows on a 32-bit
    // target) is refused instead of wrapping its size.
    const std::size_t bytes = ring_bytes(capacity, spec.points.size());
    // More than the machine's memory is refused before it is asked for: with
    // the kernel's overcommit such a ring may even be granted and the process
    // killed when the ring fills (and under a sanitizer a failed allocation
    // ends the process instead of throwing).
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long page_size = sysconf(_SC_PAGESIZE);
    const double physical = pages > 0 && page_size > 0 ? static_cast<double>(pages) * static_cast<double>(page_size) : 0;
    if (bytes == 0 || bytes > std::numeric_limits<std::size_t>::max() / 2 ||
        (physical > 0 && static_cast<double>(bytes) > physical))
        return make_error(ErrorCode::out_of_range,
                          fmt::format("sample channel {}: a ring of {} rows of {} values does not fit in memory "
                                      "(sampling.ring_max_rows {}, ring_periods {})",
                                      spec.id, capacity, spec.points.size(), config.ring_max_rows, config.ring_periods));
    // On a 64-bit target an addressable ring can still be more than the
    // machine has: the allocation's failure is the same refusal, not a throw.
    std::shared_ptr<ChannelCore> core;
    try {
        core = std::make_shared<ChannelCore>(spec, capacity, shared.policy, config.text_budget_bytes);
    } catch (const std::bad_alloc&) {
        return make_error(ErrorCode::out_of_range,
                          fmt::format("sample channel {}: a ring of {} rows of {} values does not fit in memory "
                                      "(sampling.ring_max_rows {}, ring_periods {})",
                                      spec.id, capacity, spec.points.size(), config.ring_max_rows, config.ring_periods));
    }

    std::lock_guard<std::mutex> lock(shared.mutex);
    for (const auto& c : shared.channels)
        if (!c->removed.load() && c->spec().id == core->spec().id)
            return make_error(ErrorCode::key_error, "sample channel " + core->spec().id + " exists already");
    // Push rows are accepted from now on (before start() they wait in the
    // ring); stop() closes the channel, start() opens it again.
    core->open_.store(true, std::memory_order_release);
    shared.channels.push_back(core);
    shared.version.fetch_add(1, std::memory_order_acq_rel);
    shared.publish_sampled_locked();
    shared.deps.sleeper->wake();
    return ok_result();
}

bool SamplingEngine::remove_channel(const std::string& id) {
    auto& shared = state_->shared;
    std::lock_guard<std::mutex> lock(shared.mutex);
    for (const auto& c : shared.channels) {
        if (c->removed.load() || c->spec().id != id) continue;
        c->open_.store(false, std::memory_order_release);
        c->removed.store(true, std::memory_order_release);
        // No sampler will write to it: push channels have no sampler; a
        // stopped engine's sampler is gone. Else the sampler says so.
        if (c->spec().push || !shared.sampler_running) c->producer_done.store(true, std::memory_order_release);
        shared.version.fetch_add(1, std::memory_order_acq_rel);
        shared.publish_sampled_locked();
        shared.deps.sleeper->wake();
        return true;
    }
    return false;
}

std::vector<ChannelStats> SamplingEngine::stats() const {
    std::lock_guard<std::mutex> lock(state_->shared.mutex);
    std::vector<ChannelStats> out;
    out.reserve(state_->shared.channels.size());
    for (const auto& c : state_->shared.channels) out.push_back(c->snapshot());
    return out;
}

std::uint64_t SamplingEngine::ring_drops() const {
    std::lock_guard<std::mutex> lock(state_->shared.mutex);
    std::uint64_t sum = 0;
    for (const auto& c : state_->shared.channels) sum += c->ring().drops();
    return sum;
}

void SamplingEngine::start() {
    std::lock_guard<std::mutex> life(state_->lifecycle);
    if (state_->running) return;
    auto& shared = state_->shared;
    {
        std::lock_guard<std::mutex> lock(shared.mutex);
        shared.sampler_running = true;
        for (const auto& c : shared.channels) {
            if (c->removed.load()) continue;
            c->producer_done.store(false, std::memory_order_release);
            c->open_.store(true, std::memory_order_release);
        }
    }
    state_->stop_sampler = false;
    state_->stop_uploader = false;
    state_->running = true;
    if (shared.deps.timers) {
        state_->start_on_host();
        return;
    }
    auto* state = state_.get();
    state_->sampler_thread = std::thread([state] {
        core_detail::name_this_thread("nclink-sampler");
        state->sample_loop();
    });
    if (shared.deps.uploader_host) {
        // As upload_loop(): looked at again at least every max_wait(), so a
        // wake() of the sampler's sleeper (a removed channel's last rows)
        // reaches it without the sleeper knowing the host.
        state_->uploader_entry = shared.deps.uploader_host->add([state](core_detail::PollHost::Time) {
            if (state->stop_uploader.load(std::memory_order_acquire)) return core_detail::PollHost::Time::max();
            const auto next = state->uploader.poll(false);
            return std::min(next, std::chrono::steady_clock::now() + state->shared.deps.sleeper->max_wait());
        });
        return;
    }
    state_->uploader_thread = std::thread([state] {
        core_detail::name_this_thread("nclink-upload");
        state->upload_loop();
    });
}

void SamplingEngine::stop() {
    std::unique_lock<std::mutex> life(state_->lifecycle);
    if (!state_->running) return;
    auto& shared = state_->shared;
    state_->stop_sampler = true;
    if (shared.deps.timers) {
        shared.deps.timers->remove(state_->sampler_entry);  // returns when no poll of it runs
    } else {
        shared.deps.sleeper->wake();
        state_->sampler_thread.join();
    }
    {
        std::lock_guard<std::mutex> lock(shared.mutex);
        shared.sampler_running = false;
        for (const auto& c : shared.channels) c->open_.store(false, std::memory_order_release);
    }
    state_->scheduler.reset();  // the timelines restart at the next start()
    state_->stop_uploader = true;
    if (shared.deps.timers) {
        shared.deps.timers->remove(state_->uploader_entry);
        state_->waker->set(nullptr, nullptr);
        state_->uploader.poll(true);  // what every ring holds goes out (on the stopping thread: no poll runs now)
    } else if (shared.deps.uploader_host) {
        shared.deps.uploader_host->remove(state_->uploader_entry);
        state_->uploader_entry.reset();
        state_->uploader.poll(true);  // as above
    } else {
        shared.deps.sleeper->wake();
        state_->uploader_thread.join();
    }
    state_->running = false;
}

void SamplingEngine::set_model(std::shared_ptr<const feature_detail::ModelState> state) {
    {
        std::lock_guard<std::mutex> lock(state_->shared.mutex);
        state_->shared.model = std::move(state);
    }
    state_->shared.model_version.fetch_add(1, std::memory_order_acq_rel);
}

Result<PushChannel> SamplingEngine::push_channel(const std::string& id) const {
    std::lock_guard<std::mutex> lock(state_->shared.mutex);
    for (const auto& c : state_->shared.channels) {
        if (c->removed.load() || c->spec().id != id) continue;
        if (!c->spec().push)
            return make_error(ErrorCode::value_type, "sample channel " + id + " is not push-mode (sampling.push_channels)");
        return PushChannel(c);
    }
    return make_error(ErrorCode::node_not_exists, "no sample channel " + id);
}

std::vector<std::string> SamplingEngine::channel_ids() const {
    std::lock_guard<std::mutex> lock(state_->shared.mutex);
    std::vector<std::string> ids;
    for (const auto& c : state_->shared.channels)
        if (!c->removed.load()) ids.push_back(c->spec().id);
    return ids;
}

bool SamplingEngine::has_channel(const std::string& id) const {
    std::lock_guard<std::mutex> lock(state_->shared.mutex);
    for (const auto& c : state_->shared.channels)
        if (!c->removed.load() && c->spec().id == id) return true;
    return false;
}

RealtimeStatus SamplingEngine::realtime() const {
    std::lock_guard<std::mutex> lock(state_->shared.mutex);
    return state_->shared.realtime;
}

bool SamplingEngine::running() const {
    std::lock_guard<std::mutex> life(state_->lifecycle);
    return state_->running;
}

void SamplingEngine::run_sampling_once() { state_->scheduler.poll(); }
void SamplingEngine::run_upload_once(bool final_flush) { state_->uploader.poll(final_flush); }

}  // namespace nclink::sampling_detail
