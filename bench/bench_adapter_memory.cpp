// Memory: resident set of an adapter serving the simulated mill
// (models/sim-mill.json: ch_fast 1 ms x 6 points, ch_slow 100 ms x 8 points)
// with every sample channel running, through a real mosquitto. Each
// configuration runs in a fresh child process; the baseline is the same
// adapter with sampling disabled, measured in the same run.
//
//   bench_adapter_memory [--seconds N]     (default 5 s per configuration)
#include <nclink/adapter.hpp>
#include <nclink/model.hpp>
#include "sim/sim_driver.hpp"

#include "support/mosquitto_broker.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

namespace {

long status_kb(const char* key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key, 0) == 0) return std::atol(line.c_str() + std::string(key).size());
    return -1;
}

struct Figures {
    long before_kb = 0, running_kb = 0, peak_kb = 0;
    unsigned long long rows = 0;
};

Figures run_child(const std::string& broker, bool sampling, double seconds) {
    Figures f;
    f.before_kb = status_kb("VmRSS:");
    nclink::AdapterConfig config;
    config.broker_url = broker;
    config.model_path = NCLINK_SOURCE_DIR "/models/sim-mill.json";
    config.sampling.enabled = sampling;
    const auto loaded = nclink::load_model_file(config.model_path);
    auto driver = nclink::SimDriver::create(loaded.model).value();
    nclink::Adapter adapter(config, std::move(driver));
    if (!adapter.start().ok()) std::exit(3);
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    f.running_kb = status_kb("VmRSS:");
    f.peak_kb = status_kb("VmHWM:");
    for (const auto& c : adapter.sampling_stats().channels) f.rows += c.rows_published;
    adapter.stop();
    return f;
}

Figures in_child(const std::string& broker, bool sampling, double seconds) {
    int fds[2];
    if (pipe(fds) != 0) std::exit(1);
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        const Figures f = run_child(broker, sampling, seconds);
        if (write(fds[1], &f, sizeof f) != static_cast<ssize_t>(sizeof f)) _exit(1);
        _exit(0);
    }
    close(fds[1]);
    Figures f;
    if (read(fds[0], &f, sizeof f) != static_cast<ssize_t>(sizeof f)) std::fprintf(stderr, "child failed\n");
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return f;
}

}  // namespace

int main(int argc, char** argv) {
    double seconds = 5;
    if (argc == 3 && std::string(argv[1]) == "--seconds") seconds = std::atof(argv[2]);
    nclink::test::MosquittoBroker broker;
    const auto off = in_child(broker.url(), false, seconds);
    const auto on = in_child(broker.url(), true, seconds);
    std::printf("adapter + simulated mill, %.0f s each, RSS in KiB (process before the adapter / running / peak)\n", seconds);
    std::printf("sampling disabled (baseline): %6ld / %6ld / %6ld\n", off.before_kb, off.running_kb, off.peak_kb);
    std::printf("all channels running:         %6ld / %6ld / %6ld   (%llu rows published)\n", on.before_kb, on.running_kb,
                on.peak_kb, on.rows);
    std::printf("sampling costs %+ld KiB resident (running), %+ld KiB peak\n", on.running_kb - off.running_kb,
                on.peak_kb - off.peak_kb);
    return 0;
}
