// A request flood against the simulated mill through mosquitto
// (docs/security.md, "Floods"): 20,000 requests sent as fast as the link
// takes them, half valid Query, the rest malformed, huge (1,000 items),
// 300-deep or bad Set. Measures, for the 1 ms channel (ch_fast), the share of
// null rows before (quiet), during the flood, and how long after the burst
// was sent the adapter answers a Query again; plus shed / handled counts and
// RSS. Each run is done twice: with the bounded intake (max_pending_requests
// 256, the default) and with it effectively unbounded, in the same run.
//
//   bench_request_flood [--rt-priority N] [--runs N] [--request-threads N] [--plain-broker] [--trace] [--paho]
//                       [requests=20000] [quiet_ms=2000]
//
// --paho runs the adapter on the paho transport of libnclink-plant (what it
// ran on when the stall of docs/performance.md was captured; that transport
// has no ack watchdog) instead of libmosquitto.
//
// --rt-priority runs the sampling thread at SCHED_FIFO N (sampling.rt_priority;
// needs CAP_SYS_NICE): whether the deadlines then hold during the flood.
// --request-threads N sets the adapter's request workers (request_threads,
// default 1).
// --runs N repeats each intake N times (the adapter went deaf after
// a burst in 2 of 5 runs) and prints, per intake, the share of runs in which
// a clean Query from a fresh client was answered within 1 s of the burst,
// the null-row share during the burst and the time to the first clean
// answer. "stalls" counts the adapter's MQTT links dropped and remade because
// nothing in flight was acknowledged (TransportStats::stalled_links,
// docs/delivery.md). --plain-broker runs mosquitto with its own defaults (no shipped
// settings, default queue limits), as a plant might. --trace prints the
// adapter's counters every 100 ms through the burst (received, handled,
// shed, malformed, repeats, pending, outbox depth, in flight, published,
// ch_fast rows) with the broker's $SYS counters (published once a second, the
// broker's shortest period); a run that stays deaf prints it anyway. The
// flooding client, as in the issue, also subscribes to the answers and the
// 1 ms channel.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/model.hpp>
#if NCLINK_BENCH_PAHO
#include <nclink/paho_transport.hpp>
#endif

#include "sim/sim_driver.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/request_flood.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <optional>
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

struct Options {
    std::size_t requests = 20000;
    std::chrono::milliseconds quiet{2000};
    int rt_priority = 0;
    int runs = 1;
    std::size_t request_threads = 0;  // 0: the adapter's default
    bool plain_broker = false;
    bool trace = false;
    bool paho = false;
};

struct RunResult {
    bool answered_within_1s = false;
    std::optional<double> answer_ms;  ///< none: no clean answer within the give-up time
    double null_share_flood = 0;
    double flood_values = 0, flood_nulls = 0;  ///< the fast channel's values during the burst, and the null ones
};

// One look at the adapter's counters (and the broker's latest $SYS values).
struct Sample {
    double t_ms = 0;
    std::uint64_t received = 0, handled = 0, shed = 0, rejected = 0, repeats = 0, published = 0, fast_rows = 0;
    std::size_t pending = 0, buffered = 0, in_flight = 0;
    std::string broker;
};

// The broker's $SYS counters as they arrive (mosquitto publishes them every
// sys_interval, at least a second).
class SysWatch {
public:
    explicit SysWatch(const std::string& url) {
        MqttOptions m;
        m.broker_url = url;
        m.client_id = "bench-sys";
        transport_ = make_mqtt_transport(m).value();
        transport_->set_message_handler([this](const Message& msg) {
            std::lock_guard<std::mutex> lock(mutex_);
            values_[msg.topic.substr(std::string("$SYS/broker/").size())] = msg.payload;
        });
        (void)transport_->start();
        (void)transport_->subscribe({"$SYS/broker/messages/#", "$SYS/broker/publish/messages/#", "$SYS/broker/store/messages/#",
                                     "$SYS/broker/clients/connected", "$SYS/broker/load/messages/received/1min"},
                                    0);
    }
    ~SysWatch() { transport_->stop(); }
    std::string line() const {
        std::lock_guard<std::mutex> lock(mutex_);
        std::string out;
        for (const char* key :
             {"messages/received", "messages/sent", "publish/messages/dropped", "store/messages/count", "clients/connected"}) {
            auto it = values_.find(key);
            out += std::string(" ") + key + "=" + (it == values_.end() ? "?" : it->second);
        }
        return out;
    }

private:
    std::unique_ptr<Transport> transport_;
    mutable std::mutex mutex_;
    std::map<std::string, std::string> values_;
};

RunResult run(const std::string& label, std::size_t max_pending, const Options& opt) {
    test::MosquittoOptions bo;
    if (opt.plain_broker) {
        bo.shipped_settings = false;
        bo.large_queues = false;
    }
    bo.extra_config = "sys_interval 1\n";
    test::MosquittoBroker broker(bo);
    AdapterConfig config;
    config.broker_url = broker.url();
    config.model_path = std::string(NCLINK_SOURCE_DIR) + "/models/sim-mill.json";
    config.log_level = LogLevel::error;
    config.max_pending_requests = max_pending;
    config.register_timeout = 200ms;
    config.sampling.rt_priority = opt.rt_priority;  // 0: normal scheduling
    if (opt.request_threads > 0) config.request_threads = opt.request_threads;
    const auto loaded = load_model_file(config.model_path);
    auto created = SimDriver::create(loaded.model, SimOptions{});
    std::shared_ptr<SimDriver> sim = std::move(created).value();
    Adapter adapter(config, sim, Logger(stderr_sink(), LogLevel::error));
#if NCLINK_BENCH_PAHO
    if (opt.paho) {
        MqttOptions m;
        m.broker_url = broker.url();
        m.client_id = "bench-adapter-paho";
        m.outbox.max_in_flight = config.max_in_flight;
        m.outbox.max_bytes = config.offline_buffer_bytes;
        adapter.use_transport(make_paho_transport(m, Logger(stderr_sink(), LogLevel::error)).value());
    }
#endif
    if (!adapter.start().ok()) std::abort();
    while (adapter.stats().transport.connects == 0) std::this_thread::sleep_for(10ms);
    SysWatch sys(broker.url());

    auto make_probe = [&](const std::string& id) {
        MqttOptions m;
        m.broker_url = broker.url();
        ClientOptions o;
        o.ex_cid = id;
        o.default_timeout = 200ms;
        auto probe = Client::create(m, o).value();
        (void)probe->start();
        probe->wait_connected(10s);
        return probe;
    };
    auto answers = [&](Client& probe) {
        auto r = probe.query(kDev, {QueryItem{"x_position", std::nullopt}});
        return r.ok() && (*r)[0].status.ok;
    };
    {
        auto probe = make_probe("bench-probe-before");
        while (!answers(*probe)) {
        }
        probe->stop();
    }

    const auto quiet_start = fast_channel(adapter);
    std::this_thread::sleep_for(opt.quiet);
    const auto quiet_end = fast_channel(adapter);

    auto flooder = test::flood_transport(broker.url(), "flooder");
    std::atomic<std::uint64_t> flooder_got{0};
    flooder->set_message_handler([&](const Message&) { ++flooder_got; });
    (void)flooder->start();
    while (flooder->state() != LinkState::connected) std::this_thread::sleep_for(5ms);
    // As in the issue: the flooding client takes the answers and the 1 ms channel.
    (void)flooder->subscribe({"Query/Response/" + kDev + "/#", "Set/Response/" + kDev + "/#", "Sample/" + kDev + "/#"}, 0);
    std::this_thread::sleep_for(200ms);

    // The adapter's counters every 100 ms from just before the burst.
    std::vector<Sample> samples;
    std::atomic<bool> sampling{true};
    const auto t0 = std::chrono::steady_clock::now();
    std::thread sampler([&] {
        while (sampling) {
            const auto st = adapter.stats();
            Sample s;
            s.t_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            s.received = st.transport.received;
            s.handled = st.requests;
            s.shed = st.shed;
            s.rejected = st.rejected;
            s.repeats = st.ignored_duplicates;
            s.pending = st.pending_requests;
            s.buffered = st.transport.buffered;
            s.in_flight = st.transport.in_flight;
            s.published = st.transport.published;
            s.fast_rows = fast_channel(adapter).rows;
            s.broker = sys.line();
            samples.push_back(std::move(s));
            std::this_thread::sleep_for(100ms);
        }
    });

    const auto before = adapter.stats();
    const auto flood_start = fast_channel(adapter);
    for (std::size_t i = 0; i < opt.requests; ++i) (void)flooder->publish(test::flood_message(i, kDev, "flooder", "x_position"));
    (void)flooder->flush(600s);
    const auto sent = std::chrono::steady_clock::now();
    const auto flood_end = fast_channel(adapter);
    const long rss_flood = rss_kib();
    // A fresh client's clean Query, retried until answered or 15 s passed.
    RunResult result;
    {
        auto probe = make_probe("bench-probe-after");
        const auto give_up = sent + 15s;
        while (std::chrono::steady_clock::now() < give_up) {
            if (answers(*probe)) {
                result.answer_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sent).count();
                break;
            }
        }
        probe->stop();
    }
    result.answered_within_1s = result.answer_ms && *result.answer_ms <= 1000.0;
    result.null_share_flood = null_row_share(flood_start, flood_end);
    result.flood_values = static_cast<double>(flood_end.rows - flood_start.rows) * static_cast<double>(flood_end.points);
    result.flood_nulls = static_cast<double>(flood_end.nulls - flood_start.nulls);
    // The backlog drained: everything counted.
    for (int i = 0; i < 100 && adapter.stats().pending_requests > 0; ++i) std::this_thread::sleep_for(100ms);
    sampling = false;
    sampler.join();
    const auto after = adapter.stats();
    const double send_ms = std::chrono::duration<double, std::milli>(sent - t0).count();
    std::printf("%-10s %10.0f %10.2f %10.2f %10.2f %10s %9llu %9llu %9llu %9ld %7llu\n", label.c_str(),
                static_cast<double>(opt.requests) / (send_ms / 1000.0), 100.0 * null_row_share(quiet_start, quiet_end),
                100.0 * result.null_share_flood, 100.0 * missed_row_share(flood_start, flood_end),
                result.answer_ms ? std::to_string(static_cast<long>(*result.answer_ms)).c_str() : "DEAF",
                static_cast<unsigned long long>(after.requests - before.requests),
                static_cast<unsigned long long>(after.shed - before.shed),
                static_cast<unsigned long long>(after.rejected - before.rejected), rss_flood,
                static_cast<unsigned long long>(after.transport.stalled_links));
    // The flooding client is an nclink link too: when it is made again, it
    // sends what was unacknowledged again (docs/delivery.md), and the
    // adapter then sees more requests than the burst had.
    if (const auto f = flooder->stats(); f.connects > 1 || f.stalled_links > 0)
        std::printf("  the flooding client's link was made %llu times (%llu taken for dead); it published %llu messages\n",
                    static_cast<unsigned long long>(f.connects), static_cast<unsigned long long>(f.stalled_links),
                    static_cast<unsigned long long>(f.published));
    if (opt.trace || !result.answer_ms) {
        std::printf("  trace (ms from burst start; burst sent at %.0f ms; flooder received %llu):\n", send_ms,
                    static_cast<unsigned long long>(flooder_got.load()));
        std::printf("  %7s %8s %8s %7s %7s %7s %7s %7s %7s %8s %8s  broker $SYS\n", "t", "recv", "handled", "shed", "malf",
                    "repeat", "pending", "outbox", "inflt", "publ", "fastrows");
        for (const auto& x : samples)
            std::printf("  %7.0f %8llu %8llu %7llu %7llu %7llu %7zu %7zu %7zu %8llu %8llu %s\n", x.t_ms,
                        static_cast<unsigned long long>(x.received), static_cast<unsigned long long>(x.handled),
                        static_cast<unsigned long long>(x.shed), static_cast<unsigned long long>(x.rejected),
                        static_cast<unsigned long long>(x.repeats), x.pending, x.buffered, x.in_flight,
                        static_cast<unsigned long long>(x.published), static_cast<unsigned long long>(x.fast_rows),
                        x.broker.c_str());
    }
    flooder->stop();
    adapter.stop();
    return result;
}

void summary(const std::string& label, const std::vector<RunResult>& results) {
    std::size_t within = 0;
    std::vector<double> nulls, answers;
    double values = 0, null_values = 0;  // every run's burst together
    for (const auto& r : results) {
        within += r.answered_within_1s ? 1 : 0;
        nulls.push_back(100.0 * r.null_share_flood);
        if (r.answer_ms) answers.push_back(*r.answer_ms);
        values += r.flood_values;
        null_values += r.flood_nulls;
    }
    std::sort(nulls.begin(), nulls.end());
    std::sort(answers.begin(), answers.end());
    std::printf(
        "%s: %zu runs, clean Query answered within 1 s after the burst in %zu (%.0f %%); "
        "never answered (15 s) in %zu; null rows during the burst median %.2f %% max %.2f %%, all runs together %.2f %%; "
        "first clean answer median %.0f ms max %.0f ms\n",
        label.c_str(), results.size(), within, 100.0 * static_cast<double>(within) / static_cast<double>(results.size()),
        results.size() - answers.size(), nulls[nulls.size() / 2], nulls.back(), values > 0 ? 100.0 * null_values / values : 0.0,
        answers.empty() ? -1.0 : answers[answers.size() / 2], answers.empty() ? -1.0 : answers.back());
}

}  // namespace

int main(int argc, char** argv) {
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    Options opt;
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--rt-priority" && i + 1 < argc) opt.rt_priority = std::atoi(argv[++i]);
        else if (a == "--runs" && i + 1 < argc) opt.runs = std::max(1, std::atoi(argv[++i]));
        else if (a == "--request-threads" && i + 1 < argc)
            opt.request_threads = static_cast<std::size_t>(std::max(1, std::atoi(argv[++i])));
        else if (a == "--plain-broker") opt.plain_broker = true;
        else if (a == "--trace") opt.trace = true;
        else if (a == "--paho") opt.paho = true;
        else args.push_back(a);
    }
    if (!args.empty()) opt.requests = std::strtoull(args[0].c_str(), nullptr, 10);
    if (args.size() > 1) opt.quiet = std::chrono::milliseconds(std::atoi(args[1].c_str()));
#if !NCLINK_BENCH_PAHO
    if (opt.paho) {
        std::fprintf(stderr, "bench_request_flood: --paho needs libnclink-plant (NCLINK_BUILD_PLANT)\n");
        return 2;
    }
#endif
    std::printf("request flood: %zu requests (1/2 valid Query, 1/8 each malformed, 1000-item, 300-deep, bad Set), QoS 0%s%s%s\n",
                opt.requests, opt.rt_priority > 0 ? ", sampler SCHED_FIFO" : ", normal scheduling",
                opt.plain_broker ? ", mosquitto with its defaults" : ", mosquitto with tools/mosquitto/nclink.conf",
                opt.paho ? ", adapter on paho" : ", adapter on libmosquitto");
    std::printf("%-10s %10s %10s %10s %10s %10s %9s %9s %9s %9s %7s\n", "intake", "sent/s", "null% quiet", "null% flood",
                "of it late", "answer ms", "handled", "shed", "rejected", "RSS KiB", "stalls");
    std::vector<RunResult> bounded, unbounded;
    for (int i = 0; i < opt.runs; ++i) {
        bounded.push_back(run("bounded", 256, opt));
        unbounded.push_back(run("unbounded", std::numeric_limits<std::size_t>::max() / 2, opt));
    }
    summary("bounded", bounded);
    summary("unbounded", unbounded);
    return 0;
}
