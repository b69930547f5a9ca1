// A request flood against the simulated mill through mosquitto
// (docs/security.md, "Floods"): 20,000 requests sent as fast as the link
// takes them, half valid Query, the rest malformed, huge (1,000 items),
// 300-deep or bad Set. Measures, for the 1 ms channel (ch_fast), the share of
// null rows before (quiet), during the flood, and how long after the burst
// was sent the adapter answers a Query again; plus shed / handled counts and
// RSS. Each run is done twice: with the bounded intake (max_pending_requests
// 256, the default) and with it effectively unbounded, in the same run.
//
//   bench_request_flood [--rt-priority N] [requests=20000] [quiet_ms=2000]
//
// --rt-priority runs the sampling thread at SCHED_FIFO N (sampling.rt_priority;
// needs CAP_SYS_NICE): whether the deadlines then hold during the flood.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/model.hpp>

#include "sim/sim_driver.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/request_flood.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

using namespace nclink;
using namespace std::chrono_literals;

namespace {

const std::string kDev = "nclink-sim-mill-01";

struct ChannelCount {
    std::uint64_t rows = 0, nulls = 0, points = 1, overruns = 0;
};

ChannelCount fast_channel(const Adapter& adapter) {
    ChannelCount c;
    const Json stats = to_json(adapter.stats());
    const Json* channels = nullptr;
    if (stats["features"].contains("sampling")) channels = &stats["features"]["sampling"]["channels"];
    if (!channels || !channels->is_array()) return c;
    for (const auto& ch : *channels) {
        if (ch.value("id", "") != "ch_fast") continue;
        c.rows = ch.value("rows_sampled", std::uint64_t{0});
        c.nulls = ch.value("null_values", std::uint64_t{0});
        c.points = std::max<std::uint64_t>(1, ch.value("points", std::uint64_t{1}));
        c.overruns = ch.value("overruns", std::uint64_t{0});
    }
    return c;
}

/// Share of the rows between two counts that were missed ticks (the sampler
/// ran late), as opposed to reads that found the driver busy.
double missed_row_share(const ChannelCount& a, const ChannelCount& b) {
    const double rows = static_cast<double>(b.rows - a.rows);
    if (rows <= 0) return 0;
    return static_cast<double>(b.overruns - a.overruns) / rows;
}

/// Share of null rows between two counts (a busy driver nulls whole rows).
double null_row_share(const ChannelCount& a, const ChannelCount& b) {
    const double rows = static_cast<double>(b.rows - a.rows);
    if (rows <= 0) return 0;
    return static_cast<double>(b.nulls - a.nulls) / static_cast<double>(b.points) / rows;
}

long rss_kib() {
    std::ifstream status("/proc/self/status");
    std::string key;
    long value = 0;
    while (status >> key) {
        if (key == "VmRSS:") {
            status >> value;
            return value;
        }
        status.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    }
    return 0;
}

void run(const std::string& label, std::size_t max_pending, std::size_t requests, std::chrono::milliseconds quiet,
         int rt_priority) {
    test::MosquittoBroker broker;
    AdapterConfig config;
    config.broker_url = broker.url();
    config.model_path = std::string(NCLINK_SOURCE_DIR) + "/models/sim-mill.json";
    config.log_level = LogLevel::error;
    config.max_pending_requests = max_pending;
    config.register_timeout = 200ms;
    config.sampling.rt_priority = rt_priority;  // 0: normal scheduling
    const auto loaded = load_model_file(config.model_path);
    auto created = SimDriver::create(loaded.model, SimOptions{});
    std::shared_ptr<SimDriver> sim = std::move(created).value();
    Adapter adapter(config, sim, Logger(stderr_sink(), LogLevel::error));
    if (!adapter.start().ok()) std::abort();
    while (adapter.stats().transport.connects == 0) std::this_thread::sleep_for(10ms);

    MqttOptions m;
    m.broker_url = broker.url();
    ClientOptions o;
    o.ex_cid = "bench-probe";
    o.default_timeout = 200ms;
    auto probe = Client::create(m, o).value();
    (void)probe->start();
    probe->wait_connected(10s);
    auto answers = [&] {
        auto r = probe->query(kDev, {QueryItem{"x_position", std::nullopt}});
        return r.ok() && (*r)[0].status.ok;
    };
    while (!answers()) {
    }

    const auto quiet_start = fast_channel(adapter);
    std::this_thread::sleep_for(quiet);
    const auto quiet_end = fast_channel(adapter);

    auto flooder = test::flood_transport(broker.url(), "flooder");
    (void)flooder->start();
    while (flooder->state() != LinkState::connected) std::this_thread::sleep_for(5ms);
    const auto before = adapter.stats();
    const auto flood_start = fast_channel(adapter);
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < requests; ++i) (void)flooder->publish(test::flood_message(i, kDev, "flooder", "x_position"));
    (void)flooder->flush(600s);
    const auto sent = std::chrono::steady_clock::now();
    const auto flood_end = fast_channel(adapter);
    const long rss_flood = rss_kib();
    while (!answers()) {
    }
    const auto back = std::chrono::steady_clock::now();
    // The backlog drained: everything counted.
    for (int i = 0; i < 600 && adapter.stats().pending_requests > 0; ++i) std::this_thread::sleep_for(100ms);
    const auto after = adapter.stats();
    const double send_ms = std::chrono::duration<double, std::milli>(sent - t0).count();
    std::printf("%-10s %10.0f %10.2f %10.2f %10.2f %10.0f %9llu %9llu %9llu %9ld\n", label.c_str(),
                static_cast<double>(requests) / (send_ms / 1000.0), 100.0 * null_row_share(quiet_start, quiet_end),
                100.0 * null_row_share(flood_start, flood_end), 100.0 * missed_row_share(flood_start, flood_end),
                std::chrono::duration<double, std::milli>(back - sent).count(),
                static_cast<unsigned long long>(after.requests - before.requests),
                static_cast<unsigned long long>(after.shed - before.shed),
                static_cast<unsigned long long>(after.rejected - before.rejected), rss_flood);
    flooder->stop();
    probe->stop();
    adapter.stop();
}

}  // namespace

int main(int argc, char** argv) {
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    int rt_priority = 0;
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() >= 2 && args[0] == "--rt-priority") {
        rt_priority = std::atoi(args[1].c_str());
        args.erase(args.begin(), args.begin() + 2);
    }
    const std::size_t requests = !args.empty() ? std::strtoull(args[0].c_str(), nullptr, 10) : 20000;
    const auto quiet = std::chrono::milliseconds(args.size() > 1 ? std::atoi(args[1].c_str()) : 2000);
    std::printf("request flood: %zu requests (1/2 valid Query, 1/8 each malformed, 1000-item, 300-deep, bad Set), QoS 0%s\n",
                requests, rt_priority > 0 ? ", sampler SCHED_FIFO" : ", normal scheduling");
    std::printf("%-10s %10s %10s %10s %10s %10s %9s %9s %9s %9s\n", "intake", "sent/s", "null% quiet", "null% flood",
                "of it late", "answer ms", "handled", "shed", "rejected", "RSS KiB");
    run("bounded", 256, requests, quiet, rt_priority);
    run("unbounded", std::numeric_limits<std::size_t>::max() / 2, requests, quiet, rt_priority);
    return 0;
}
