// push_mode: a firmware's real-time loop writing sample rows straight into
// nclink (docs/sampling.md, "Push mode").
//
// The simulated mill's fast channel `ch_fast` (x/y/z position and speed,
// 1 ms) is made push-mode in the configuration; a fake 1 kHz servo loop
// computes the axis values and pushes one row per cycle. nclink batches the
// rows and publishes a Sample DTU on Sample/{dev}/ch_fast every 100 ms,
// exactly as if it had read the driver. Everything else (Query, Set, the slow
// channel) is served by the simulated driver as usual.
//
//   push_mode [--broker URL] [--seconds N]      (default tcp://127.0.0.1:1883, 10 s)
//   mosquitto_sub -t 'Sample/#' -v               (in another terminal)
#include <nclink/adapter.hpp>
#include <nclink/model.hpp>
#include <nclink/sampling.hpp>
#include "sim/sim_driver.hpp"

#include <time.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

std::int64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void sleep_until_ns(std::int64_t t) {
    timespec ts{};
    ts.tv_sec = t / 1'000'000'000;
    ts.tv_nsec = t % 1'000'000'000;
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
    std::string broker = "tcp://127.0.0.1:1883";
    int seconds = 10;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string arg = argv[i];
        if (arg == "--broker") broker = argv[i + 1];
        else if (arg == "--seconds") seconds = std::atoi(argv[i + 1]);
    }

    nclink::AdapterConfig config;
    config.broker_url = broker;
    config.model_path = NCLINK_EXAMPLE_MODEL;     // models/sim-mill.json
    config.sampling.push_channels = {"ch_fast"};  // its rows come from push(), not from reads
    const nclink::Logger logger(nclink::stderr_sink(), nclink::LogLevel::info);

    const auto loaded = nclink::load_model_file(config.model_path);
    if (!loaded.model) return 1;
    auto driver = nclink::SimDriver::create(loaded.model);
    if (!driver) return 1;
    nclink::Adapter adapter(config, std::move(driver).value(), logger);
    if (auto started = adapter.start(); !started) {
        logger.error("push_mode: {}", started.error().message);
        return 1;
    }

    // Once, outside the real-time loop: the handle.
    auto handle = adapter.push_channel("ch_fast");
    if (!handle) {
        logger.error("push_mode: {}", handle.error().message);
        return 1;
    }
    nclink::PushChannel channel = handle.value();

    // The "servo loop": absolute 1 ms deadlines, one row per cycle. push()
    // is wait-free (no lock, no allocation, no system call), so it is safe
    // here; it returns false only if the row could not be queued.
    const std::int64_t period = 1'000'000;
    std::int64_t next = monotonic_ns();
    std::uint64_t refused = 0;
    const int cycles = seconds * 1000;
    for (int k = 0; k < cycles; ++k) {
        const double t = k * 1e-3;
        nclink::SampleValue row[6] = {
            nclink::SampleValue::float64(100 * std::sin(t)),    // x_position
            nclink::SampleValue::float64(100 * std::cos(t)),    // y_position
            nclink::SampleValue::float64(-5 + 0.1 * t),         // z_position
            nclink::SampleValue::float64(6000 * std::cos(t)),   // x_speed (mm/min)
            nclink::SampleValue::float64(-6000 * std::sin(t)),  // y_speed
            nclink::SampleValue::float64(6),                    // z_speed
        };
        if (!channel.push(row, 6)) ++refused;
        next += period;
        sleep_until_ns(next);
    }

    adapter.stop();
    for (const auto& c : adapter.sampling_stats().channels)
        std::printf("%-8s %s: %llu rows pushed/sampled, %llu published, %llu dropped\n", c.id.c_str(), c.push ? "push" : "pull",
                    static_cast<unsigned long long>(c.rows_sampled), static_cast<unsigned long long>(c.rows_published),
                    static_cast<unsigned long long>(c.drops));
    std::printf("refused pushes: %llu\n", static_cast<unsigned long long>(refused));
    return 0;
}
