// Footprint of one adapter in its steady state (bench/footprint.sh prints it
// per architecture, docs/footprint.md): the simulated mill
// (models/sim-mill.json: ch_fast 1 ms x 6 points, ch_slow 100 ms x 8 points)
// through a real mosquitto on a free loopback port, as nclink-sim runs it.
// After a warm-up it counts, until the end:
//   - heap allocations of the sampler thread per sample row (the sampling
//     path: the goal is none), and of the whole process per Sample DTU;
//   - the threads the adapter started (names from /proc/self/task), which
//     under qemu-user leaves qemu's own thread out, as it existed before.
// And, as the floor in the same run, what libmosquitto itself allocates per
// message (a bare client publishing messages of the DTUs' size at each QoS
// and reading the acknowledgements): the adapter's own allocations per DTU
// are the whole process's less that floor.
// Prints key=value lines (one "thread=NAME" per adapter thread).
//
//   bench_footprint [--seconds N] [--warmup N]   (defaults 60 and 10)
#include "alloc_counter.hpp"

#include <nclink/adapter.hpp>
#include <nclink/model.hpp>
#include "sim/sim_driver.hpp"

#include "support/mosquitto_broker.hpp"

#include <dirent.h>
#include <mosquitto.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace {

/// Thread id -> name of every thread of this process now.
std::map<long, std::string> threads_now() {
    std::map<long, std::string> out;
    DIR* dir = opendir("/proc/self/task");
    if (dir == nullptr) return out;
    while (const dirent* e = readdir(dir)) {
        if (e->d_name[0] == '.') continue;
        std::string name;
        std::ifstream comm(std::string("/proc/self/task/") + e->d_name + "/comm");
        std::getline(comm, name);
        out[std::atol(e->d_name)] = name;
    }
    closedir(dir);
    return out;
}

struct Counts {
    std::uint64_t rows = 0, dtus = 0;
};

Counts counts(const nclink::Adapter& adapter) {
    Counts c;
    for (const auto& ch : adapter.sampling_stats().channels) {
        c.rows += ch.rows_sampled;
        c.dtus += ch.dtus_published;
    }
    return c;
}

/// Heap allocations per message of a bare libmosquitto client (its own
/// loop thread, as the adapter's) publishing `count` messages of `bytes` at
/// `qos` and waiting for every on_publish: the floor under the adapter's
/// allocations per DTU. -1 when it could not run.
double mosquitto_floor(int port, int qos, std::size_t bytes, int count) {
    struct Acks {
        std::atomic<int> published{0};
        std::atomic<bool> connected{false};
    } acks;
    mosquitto* m = mosquitto_new(nullptr, true, &acks);
    if (m == nullptr) return -1;
    mosquitto_connect_callback_set(m, [](mosquitto*, void* self, int rc) {
        if (rc == 0) static_cast<Acks*>(self)->connected = true;
    });
    mosquitto_publish_callback_set(m, [](mosquitto*, void* self, int) { ++static_cast<Acks*>(self)->published; });
    double per = -1;
    if (mosquitto_connect(m, "127.0.0.1", port, 30) == MOSQ_ERR_SUCCESS && mosquitto_loop_start(m) == MOSQ_ERR_SUCCESS) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
        while (!acks.connected && std::chrono::steady_clock::now() < until)
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        const std::string topic = "Sample/footprint-floor-device-0000/ch_fast";
        const std::string payload(bytes, 'x');
        auto publish = [&](int n) {
            const int goal = acks.published + n;
            for (int i = 0; i < n; ++i) {
                mosquitto_publish(m, nullptr, topic.c_str(), static_cast<int>(payload.size()), payload.data(), qos, false);
                std::this_thread::sleep_for(std::chrono::milliseconds(1));  // one at a time, as the adapter's DTUs
            }
            while (acks.published < goal && std::chrono::steady_clock::now() < until + std::chrono::seconds(30))
                std::this_thread::sleep_for(std::chrono::milliseconds(1));
        };
        if (acks.connected) {
            publish(20);  // warm
            nclink::bench::alloc::reset();
            nclink::bench::alloc::start();
            publish(count);
            nclink::bench::alloc::stop();
            std::uint64_t total = 0;
            for (const auto& [name, n] : nclink::bench::alloc::by_thread_name()) total += n;
            per = static_cast<double>(total) / count;
        }
        mosquitto_disconnect(m);
        mosquitto_loop_stop(m, false);
    }
    mosquitto_destroy(m);
    return per;
}

}  // namespace

int main(int argc, char** argv) {
    double seconds = 60, warmup = 10;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string arg = argv[i];
        if (arg == "--seconds") seconds = std::atof(argv[i + 1]);
        else if (arg == "--warmup") warmup = std::atof(argv[i + 1]);
        else {
            std::fprintf(stderr, "usage: bench_footprint [--seconds N] [--warmup N]\n");
            return 2;
        }
    }
    if (warmup >= seconds) warmup = seconds / 3;

    nclink::test::MosquittoBroker broker;
    nclink::AdapterConfig config;
    config.broker_url = broker.url();
    config.model_path = NCLINK_SOURCE_DIR "/models/sim-mill.json";
    const auto loaded = nclink::load_model_file(config.model_path);
    if (!loaded.model) {
        std::fprintf(stderr, "bench_footprint: cannot load %s\n", config.model_path.c_str());
        return 1;
    }
    auto driver = nclink::SimDriver::create(loaded.model);
    if (!driver.ok()) {
        std::fprintf(stderr, "bench_footprint: %s\n", driver.error().describe().c_str());
        return 1;
    }
    const auto before = threads_now();
    nclink::Adapter adapter(config, std::move(driver).value(), nclink::Logger(nclink::stderr_sink(), nclink::LogLevel::warn));
    if (const auto started = adapter.start(); !started.ok()) {
        std::fprintf(stderr, "bench_footprint: start: %s\n", started.error().describe().c_str());
        return 1;
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(warmup));

    const Counts at_mark = counts(adapter);
    nclink::bench::alloc::start();
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds - warmup));
    nclink::bench::alloc::stop();
    const Counts at_end = counts(adapter);

    std::vector<std::string> adapter_threads;
    for (const auto& [tid, name] : threads_now())
        if (before.count(tid) == 0) adapter_threads.push_back(name);
    std::uint64_t sampler = 0, total = 0;
    const auto by_thread = nclink::bench::alloc::by_thread_name();
    for (const auto& [name, n] : by_thread) {
        total += n;
        if (name == "nclink-sampler") sampler += n;
    }
    adapter.stop();
    // About a ch_fast DTU (100 rows of 6 values); the count of allocations
    // of a publish does not depend on its size.
    constexpr std::size_t mean_bytes = 5000;

    const auto rows = at_end.rows - at_mark.rows, dtus = at_end.dtus - at_mark.dtus;
    std::printf("counted_allocations=%d\n", nclink::bench::alloc::available() ? 1 : 0);
    std::printf("window_s=%.1f\nrows=%llu\ndtus=%llu\n", seconds - warmup, static_cast<unsigned long long>(rows),
                static_cast<unsigned long long>(dtus));
    std::printf("sampler_allocs=%llu\ntotal_allocs=%llu\n", static_cast<unsigned long long>(sampler),
                static_cast<unsigned long long>(total));
    std::printf("allocs_per_row=%.4f\n", rows > 0 ? static_cast<double>(sampler) / static_cast<double>(rows) : -1.0);
    std::printf("allocs_per_dtu=%.2f\n", dtus > 0 ? static_cast<double>(total) / static_cast<double>(dtus) : -1.0);
    for (const auto& [name, n] : by_thread) std::printf("allocs_of=%s %llu\n", name.c_str(), static_cast<unsigned long long>(n));
    // The floor: what libmosquitto allocates per message of this size,
    // measured here after the adapter stopped (its counts stand above).
    const double floor_qos1 = mosquitto_floor(broker.port(), 1, mean_bytes, 500);
    const double floor_qos0 = mosquitto_floor(broker.port(), 0, mean_bytes, 500);
    std::printf("floor_message_bytes=%zu\n", mean_bytes);
    std::printf("mosquitto_allocs_per_message_qos1=%.2f\nmosquitto_allocs_per_message_qos0=%.2f\n", floor_qos1, floor_qos0);
    // The mill's channels publish at QoS 1 (the default, "qos").
    if (dtus > 0 && floor_qos1 >= 0)
        std::printf("nclink_allocs_per_dtu=%.2f\n", static_cast<double>(total) / static_cast<double>(dtus) - floor_qos1);
    std::printf("adapter_threads=%zu\n", adapter_threads.size());
    for (const auto& name : adapter_threads) std::printf("thread=%s\n", name.c_str());
    return rows > 0 && dtus > 0 ? 0 : 1;
}
