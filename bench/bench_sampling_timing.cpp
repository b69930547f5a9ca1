// Sampling timing: how late the ticks of a 1 ms channel of 20 points start,
// against the floor measured in the same run: a bare clock_nanosleep
// (CLOCK_MONOTONIC, TIMER_ABSTIME) loop with the same scheduling settings.
// Also checks that every row is present in the published DTUs.
//
//   bench_sampling_timing [--seconds N] [--points N] [--rt-priority P]
//                         [--timer-slack NS] [--cpu N] [--slice-us N] [--worker-reads]
//
// Target: p50 and p99 within 50 us of the floor; every row present.
#include "bench_util.hpp"

#include "sampling/realtime.hpp"
#include "sampling/sampling_engine.hpp"
#include "sampling/sleeper.hpp"

#include <nclink/json.hpp>

#include <time.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>

using namespace nclink;
using namespace nclink::bench;

namespace {

struct Options {
    double seconds = 10;
    std::size_t points = 20;
    SamplingConfig sampling;
};

/// 20 doubles that change every read: what a cheap servo-position driver costs.
class FastDriver : public Driver {
public:
    DriverInfo info() const override { return {"fast", "1", false}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        ++n_;
        for (std::size_t i = 0; i < points.size(); ++i)
            results[i] = Json(static_cast<double>(n_) * 0.001 + static_cast<double>(i));
    }

private:
    std::uint64_t n_ = 0;
};

void report(const char* name, const std::vector<double>& late_us) {
    std::printf("%-28s ticks %7zu  p50 %7.1f  p99 %7.1f  p99.9 %8.1f  max %9.1f us\n", name, late_us.size(), median(late_us),
                percentile(late_us, 99), percentile(late_us, 99.9), maximum(late_us));
}

std::vector<double> bare_loop(const Options& o) {
    std::vector<double> late;
    std::thread t([&] {
        (void)sampling_detail::apply_realtime(o.sampling, Logger{});
        const std::int64_t period = 1'000'000;
        const std::size_t ticks = static_cast<std::size_t>(o.seconds * 1000);
        late.reserve(ticks);
        std::int64_t deadline = now_ns() + period;
        for (std::size_t k = 0; k < ticks; ++k) {
            timespec ts{static_cast<time_t>(deadline / 1'000'000'000), static_cast<long>(deadline % 1'000'000'000)};
            clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
            late.push_back(static_cast<double>(now_ns() - deadline) / 1000.0);
            deadline += period;
        }
    });
    t.join();
    return late;
}

struct EngineRun {
    std::vector<double> late_us;
    ChannelStats stats;
    std::size_t rows_in_dtus = 0;
    std::size_t bad_dtus = 0;
    std::size_t dtus = 0;
};

EngineRun engine_run(const Options& o) {
    EngineRun run;
    auto driver = std::make_shared<FastDriver>();
    driver_detail::DriverRunner runner(driver, {}, Logger{});
    std::mutex mutex;
    std::vector<std::string> payloads;
    payloads.reserve(static_cast<std::size_t>(o.seconds * 10) + 16);
    run.late_us.reserve(static_cast<std::size_t>(o.seconds * 1000) + 16);

    sampling_detail::EngineDeps deps;
    deps.driver = &runner;
    deps.clock = std::make_shared<SystemClock>();
    deps.sleeper = std::make_shared<sampling_detail::NanosleepSleeper>();
    deps.config = o.sampling;
    deps.dev = "bench";
    deps.sink = [&](Message m) {
        std::lock_guard<std::mutex> lock(mutex);
        payloads.push_back(std::move(m.payload));
    };
    deps.tick_observer = [&](const std::string&, std::int64_t late_ns) {
        run.late_us.push_back(static_cast<double>(late_ns) / 1000.0);
    };
    sampling_detail::SamplingEngine engine(std::move(deps));
    sampling_detail::ChannelSpec spec;
    spec.id = "ch_fast";
    for (std::size_t i = 0; i < o.points; ++i) spec.points.push_back(PointRef{"p" + std::to_string(i), DataKind::single});
    spec.sample_interval_ms = 1;
    spec.upload_interval_ms = 100;
    spec.topic = "Sample/bench/ch_fast";
    if (!engine.add_channel(spec).ok()) std::abort();
    engine.start();
    std::this_thread::sleep_for(std::chrono::duration<double>(o.seconds));
    engine.stop();
    runner.stop();
    run.stats = engine.stats().at(0);
    for (const auto& p : payloads) {
        const Json dtu = Json::parse(p);
        ++run.dtus;
        const auto& data = dtu.at("data");
        if (data.size() != o.points) ++run.bad_dtus;
        const std::size_t rows = data.at(0).at("data").size();
        for (const auto& column : data)
            if (column.at("data").size() != rows) ++run.bad_dtus;
        run.rows_in_dtus += rows;
    }
    return run;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (arg == "--seconds") o.seconds = std::atof(next().c_str());
        else if (arg == "--points") o.points = static_cast<std::size_t>(std::atoi(next().c_str()));
        else if (arg == "--rt-priority") o.sampling.rt_priority = std::atoi(next().c_str());
        else if (arg == "--timer-slack") o.sampling.timer_slack_ns = std::atol(next().c_str());
        else if (arg == "--slice-us") o.sampling.slice_us = std::atoi(next().c_str());
        else if (arg == "--cpu") o.sampling.cpu = std::atoi(next().c_str());
        else if (arg == "--worker-reads") o.sampling.direct_reads = false;
        else {
            std::fprintf(stderr,
                         "usage: bench_sampling_timing [--seconds N] [--points N] [--rt-priority P] [--timer-slack NS] [--cpu N] "
                         "[--slice-us N] [--worker-reads]\n");
            return 2;
        }
    }
    std::printf("1 ms channel, %zu points, %.0f s each; rt_priority %d, timer_slack_ns %ld, cpu %d, slice_us %d, %s reads\n",
                o.points, o.seconds, o.sampling.rt_priority, o.sampling.timer_slack_ns, o.sampling.cpu, o.sampling.slice_us,
                o.sampling.direct_reads ? "direct" : "worker");
    const auto floor = bare_loop(o);
    const auto run = engine_run(o);
    report("floor: bare clock_nanosleep", floor);
    report("nclink sampling engine", run.late_us);
    std::printf("difference (engine - floor):  p50 %+7.1f  p99 %+7.1f  p99.9 %+8.1f us\n", median(run.late_us) - median(floor),
                percentile(run.late_us, 99) - percentile(floor, 99), percentile(run.late_us, 99.9) - percentile(floor, 99.9));
    const auto& s = run.stats;
    std::printf(
        "rows: sampled %llu, published %llu, in %zu DTUs %zu rows (malformed DTUs %zu); overruns %llu (null rows), skipped %llu, "
        "drops %llu\n",
        static_cast<unsigned long long>(s.rows_sampled), static_cast<unsigned long long>(s.rows_published), run.dtus,
        run.rows_in_dtus, run.bad_dtus, static_cast<unsigned long long>(s.overruns),
        static_cast<unsigned long long>(s.skipped_ticks), static_cast<unsigned long long>(s.drops));
    const bool all_rows = s.rows_published == s.rows_sampled && run.rows_in_dtus == s.rows_published && s.drops == 0 &&
                          s.skipped_ticks == 0 && run.bad_dtus == 0;
    std::printf("every row present: %s\n", all_rows ? "yes" : "NO");
    return 0;
}
