// End-to-end sampling throughput: an nclink Adapter (its own process, reading
// an in-memory driver) -> mosquitto -> a paho subscriber counting DTUs.
// For 1, 10 and 50 channels the number of points per row goes up until a load
// is no longer lossless (two runs in a row); for the largest lossless load,
// the adapter's CPU per million points is compared with the irreducible work
// measured in the same run: encoding the same DTUs (SampleEncoder) + a bare
// paho publisher (also its own process) sending the same bytes, at the same
// pace, through the same broker to the same subscriber.
//
//   bench_sampling_throughput [--json-reads] [--no-value-checks] [--system-heap] [--slice-us N] [--rt-priority N]
//   [seconds_per_run=3] [rounds=3] [qos=0] [channels points]
//
// With `channels points` only that load runs (no search), e.g. under a profiler.
// The bench's driver implements the typed Driver::read_samples(); with
// --json-reads it implements read() only, so every value goes through Json.
// --system-heap leaves glibc's heap policy as it is in the adapter and the
// floor publisher (AdapterConfig::heap_keep_bytes = 0), to measure what
// keeping freed memory saves (nclink/heap.hpp).
// --no-value-checks turns off the chapter-7 checks of sampled values
// (AdapterConfig::check_values), to measure what they cost.
// --slice-us N sets the sampling thread's time slice (sampling.slice_us;
// 0 = the kernel's default), to measure what the default 100 us saves.
// --rt-priority runs the adapter's sampling thread at SCHED_FIFO N with 1 ns
// timer slack (sampling.rt_priority / timer_slack_ns), as on a firmware host.
//
// Lossless = every DTU the adapter published reached the subscriber, no ring
// drop, nothing dropped by the spool or the transport, and at most 1% of the
// values null (a null is a sample not taken: the sampler ran a period late,
// which on this VM happens to 0.3-0.9% of 1 ms ticks even when idle, see
// docs/sampling.md). Channels are dynamic
// channels (Register/Sample) of `points` copies of one item, 1 ms sample,
// 100 ms upload. CPU = getrusage of the adapter process between "all channels
// registered" and "stopped and flushed" (so it includes the final flush).
// Beside the target, the bench prints what a bare loop waking every sample
// interval costs (thread CPU), per million points at that load: the floor
// does not include it, and at 1 channel x 500 points it is ~0.4x of it.
#include <nclink/adapter.hpp>
#include <nclink/heap.hpp>
#include <nclink/sample_encoder.hpp>
#include <nclink/topics.hpp>

#include "alloc_counter.hpp"
#include "bench_util.hpp"
#include "child_process.hpp"
#include "support/mosquitto_broker.hpp"
#include "transport/tcp_nodelay.hpp"

#include <mqtt/async_client.h>

#include <fmt/format.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <deque>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <string>
#include <thread>

extern char** environ;

using namespace nclink;
using namespace std::chrono_literals;

namespace {

const char* kDev = "test-dev";  // the test model's device
const char* kEx = "bench-app";
constexpr int kSampleMs = 1;
constexpr int kUploadMs = 100;
constexpr std::size_t kRows = kUploadMs / kSampleMs;
constexpr double kMaxNullShare = 0.01;

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) / 1e9;
}

class MemoryDriver final : public Driver {
public:
    explicit MemoryDriver(bool typed) : typed_(typed) {}
    DriverInfo info() const override { return {"memory", "1", true}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = Json(123.456 + static_cast<double>(i));
    }
    bool read_samples(const std::vector<PointRef>& points, SampleValue* out) override {
        if (!typed_) return false;
        for (std::size_t i = 0; i < points.size(); ++i) out[i] = SampleValue::float64(123.456 + static_cast<double>(i));
        return true;
    }

private:
    const bool typed_;
};

bool g_json_reads = false;       // --json-reads (parent and adapter child)
int g_rt_priority = 0;           // --rt-priority N (parent and adapter child)
bool g_no_value_checks = false;  // --no-value-checks (parent and adapter child)
bool g_system_heap = false;      // --system-heap (parent and both children)
int g_slice_us = -1;             // --slice-us N (parent and adapter child; -1 = the config's default)

// ---------------------------------------------------------------- child processes
// Both children talk over stdin/stdout lines: "mark" starts the CPU window,
// "stop" ends the run; the child then prints one JSON line and exits.

int adapter_child(int port) {
    AdapterConfig config;
    config.broker_url = "tcp://127.0.0.1:" + std::to_string(port);
    config.model_path = std::string(NCLINK_SOURCE_DIR) + "/tests/data/adapter-test-model.json";
    config.register_timeout = 60000ms;
    config.sampling.max_dynamic_channels = 64;
    config.check_values = !g_no_value_checks;
    if (g_system_heap) config.heap_keep_bytes = 0;
    if (g_slice_us >= 0) config.sampling.slice_us = g_slice_us;
    if (g_rt_priority > 0) {
        config.sampling.rt_priority = g_rt_priority;
        config.sampling.timer_slack_ns = 1;
    }
    Adapter adapter(config, std::make_shared<MemoryDriver>(!g_json_reads), Logger(stderr_sink(), LogLevel::warn));
    if (!adapter.start().ok()) return 1;
    std::printf("ready\n");
    std::fflush(stdout);
    double start = 0;
    std::string line;
    // Rows and DTUs of the dynamic channels, for allocations per row / DTU.
    const auto counts = [&adapter] {
        std::pair<std::uint64_t, std::uint64_t> rows_dtus{0, 0};
        const auto stats = adapter.stats();  // the loop below reads into it
        for (const auto& c : stats.features.at("sampling")["channels"]) {
            if (!c.contains("owner_ex")) continue;
            rows_dtus.first += c["rows_sampled"].get<std::uint64_t>();
            rows_dtus.second += c["dtus_published"].get<std::uint64_t>();
        }
        return rows_dtus;
    };
    std::pair<std::uint64_t, std::uint64_t> at_mark{0, 0};
    while (std::getline(std::cin, line)) {
        if (line == "mark") {
            start = bench::process_cpu_seconds();
            at_mark = counts();
            bench::alloc::start();
        }
        if (line == "stop") break;
    }
    // Steady state only: the allocations of stopping are not counted.
    bench::alloc::stop();
    const auto at_stop = counts();
    Json allocs = Json::object();
    for (const auto& [thread, n] : bench::alloc::by_thread_name()) allocs[thread] = n;
    const auto stop0 = std::chrono::steady_clock::now();
    adapter.stop(10000ms);
    if (std::getenv("NCLINK_BENCH_DEBUG"))
        std::fprintf(stderr, "adapter stop took %.3f s\n",
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - stop0).count());
    const double cpu = bench::process_cpu_seconds() - start;
    const auto stats = adapter.stats();
    std::printf("%s\n", Json{{"cpu_s", cpu},
                             {"sampling", stats.features.at("sampling")},
                             {"transport_dropped", stats.transport.dropped},
                             {"allocs", allocs},
                             {"window_rows", at_stop.first - at_mark.first},
                             {"window_dtus", at_stop.second - at_mark.second}}
                            .dump()
                            .c_str());
    return 0;
}

// Publishes `count` payloads (sizes given) round-robin at `per_second`
// messages/s, at most `window` unacknowledged, then waits for completion.
int publisher_child(int port, int qos, const std::string& payload_file, std::size_t count, double per_second) {
    std::ifstream in(payload_file, std::ios::binary);
    std::vector<std::string> payloads;
    std::string line;
    while (std::getline(in, line)) payloads.push_back(line);
    if (payloads.empty()) return 1;
    // The heap policy the adapter process has (AdapterConfig::heap_keep_bytes
    // by default), so the floor is measured under the same allocator.
    if (!g_system_heap) keep_freed_heap(max_heap_keep_bytes);
    mqtt::async_client client("tcp://127.0.0.1:" + std::to_string(port), "bench-floor",
                              mqtt::create_options(MQTTVERSION_3_1_1, 64 + 16), nullptr);
    auto options = mqtt::connect_options_builder().clean_session(true).max_inflight(64).finalize();
    if (!client.connect(options)->wait_for(10s)) return 1;
    transport_detail::apply_tcp_nodelay_to_peer("127.0.0.1", port);
    std::printf("ready\n");
    std::fflush(stdout);
    std::getline(std::cin, line);  // "mark"
    const double start = bench::process_cpu_seconds();
    std::deque<mqtt::delivery_token_ptr> window;
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < count; ++i) {
        std::this_thread::sleep_until(t0 + std::chrono::duration<double>(static_cast<double>(i) / per_second));
        const std::string& p = payloads[i % payloads.size()];
        const std::string topic = topics::dynamic_sample(kDev, kEx, "dyn" + std::to_string(i % payloads.size() + 1));
        while (window.size() >= 64) {
            window.front()->wait();
            window.pop_front();
        }
        window.push_back(client.publish(topic, p.data(), p.size(), qos, false));
    }
    for (auto& t : window) t->wait();
    const double cpu = bench::process_cpu_seconds() - start;
    std::getline(std::cin, line);  // "stop"
    client.disconnect()->wait_for(2s);
    std::printf("%s\n", Json{{"cpu_s", cpu}}.dump().c_str());
    return 0;
}

// ---------------------------------------------------------------- parent side

// Subscribes to every dynamic channel of bench-app, counts DTUs and bytes,
// and registers channels through the same connection.
class App {
public:
    explicit App(int port, int qos) : client_("tcp://127.0.0.1:" + std::to_string(port), kEx) {
        client_.set_message_callback([this](mqtt::const_message_ptr m) {
            std::lock_guard<std::mutex> lock(mutex_);
            if (m->get_topic().rfind("Sample/", 0) == 0) {
                ++dtus_;
                bytes_ += m->get_payload().size();
            } else {
                last_reply_ = m->to_string();
                cv_.notify_all();
            }
        });
        auto options = mqtt::connect_options_builder().clean_session(true).finalize();
        client_.connect(options)->wait();
        transport_detail::apply_tcp_nodelay_to_peer("127.0.0.1", port);
        client_.subscribe(topics::dynamic_sample(kDev, kEx, "+"), qos)->wait();
        client_.subscribe(topics::sample_register_response(kDev, kEx), 1)->wait();
    }
    ~App() {
        try {
            client_.disconnect()->wait_for(2s);
        } catch (...) {
        }
    }
    /// The reply's code, "" when none came within 10 s.
    std::string register_channel(int points, int qos) {
        Json ids = Json::array();
        for (int i = 0; i < points; ++i) ids.push_back(Json{{"id", "pos"}});
        Json request{{"@id", "r" + std::to_string(++counter_)},
                     {"guid", kDev},
                     {"sampleInterval", kSampleMs},
                     {"uploadInterval", kUploadMs},
                     {"ids", ids}};
        if (qos) request["privateInfo"] = Json{{"qos", qos}};
        std::unique_lock<std::mutex> lock(mutex_);
        last_reply_.clear();
        lock.unlock();
        client_.publish(topics::sample_register_request(kDev, kEx), request.dump(), 1, false)->wait();
        lock.lock();
        if (!cv_.wait_for(lock, 10s, [&] { return !last_reply_.empty(); })) return "";
        const Json reply = Json::parse(last_reply_, nullptr, false);
        return reply.is_object() ? reply.value("code", "?") : "?";
    }
    std::uint64_t dtus() {
        std::lock_guard<std::mutex> lock(mutex_);
        return dtus_;
    }
    void reset() {
        std::lock_guard<std::mutex> lock(mutex_);
        dtus_ = 0;
        bytes_ = 0;
    }

private:
    mqtt::async_client client_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::uint64_t dtus_ = 0, bytes_ = 0;
    std::string last_reply_;
    int counter_ = 0;
};

struct RunResult {
    bool lossless = false;
    double cpu_s = 0;
    std::uint64_t points = 0;  // points published
    std::uint64_t dtus = 0, received = 0, drops = 0, nulls = 0, overruns = 0, spool_dropped = 0, transport_dropped = 0;
    double seconds = 0;
    // Heap allocations between mark and stop, by thread name, and the rows
    // and DTUs of that window (empty when the build cannot count).
    std::map<std::string, std::uint64_t> allocs;
    std::uint64_t window_rows = 0, window_dtus = 0;
    double per_million() const { return points ? cpu_s / (static_cast<double>(points) / 1e6) : 0; }
    double points_per_s() const { return seconds > 0 ? static_cast<double>(points) / seconds : 0; }
    double null_share() const { return points ? static_cast<double>(nulls) / static_cast<double>(points) : 0; }
};

RunResult run_adapter(int port, int channels, int points, int qos, double seconds) {
    RunResult r;
    std::vector<std::string> args{"bench_sampling_throughput", "--adapter-child", std::to_string(port)};
    if (g_json_reads) args.push_back("--json-reads");
    if (g_no_value_checks) args.push_back("--no-value-checks");
    if (g_system_heap) args.push_back("--system-heap");
    if (g_slice_us >= 0) {
        args.push_back("--slice-us");
        args.push_back(std::to_string(g_slice_us));
    }
    if (g_rt_priority > 0) {
        args.push_back("--rt-priority");
        args.push_back(std::to_string(g_rt_priority));
    }
    bench::Child child(args);
    App app(port, qos);
    std::this_thread::sleep_for(300ms);  // the adapter subscribes after connecting
    for (int c = 0; c < channels; ++c) {
        // The first request may go out before the adapter's subscription is
        // in place: it is asked again. Later ones go unanswered only when the
        // channels already running saturate the adapter or the broker (at
        // 50 x 500 on 2 vCPUs): that load is past the limit, not the end of
        // the bench.
        std::string code = app.register_channel(points, qos);
        for (int retry = 0; c == 0 && code.empty() && retry < 2; ++retry) code = app.register_channel(points, qos);
        if (code != "OK") {
            std::printf("    (Register/Sample of channel %d: %s)\n", c + 1,
                        code.empty() ? "no answer within 10 s" : ("answered " + code).c_str());
            return r;  // not lossless; the child stops at the end of its input
        }
    }
    child.say("mark");
    const auto t0 = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    child.say("stop");
    // The sampling window; the rows the stop flushes were sampled within it.
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Json out = Json::parse(child.read_line());
    r.cpu_s = out["cpu_s"].get<double>();
    if (std::getenv("NCLINK_BENCH_DEBUG")) std::fprintf(stderr, "%s\n", out.dump(1).c_str());
    for (const auto& c : out["sampling"]["channels"]) {
        if (!c.contains("owner_ex")) continue;  // the model's own channel
        r.dtus += c["dtus_published"].get<std::uint64_t>();
        r.points += c["rows_published"].get<std::uint64_t>() * c["points"].get<std::uint64_t>();
        r.drops += c["drops"].get<std::uint64_t>();
        r.nulls += c["null_values"].get<std::uint64_t>();
        r.overruns += c["overruns"].get<std::uint64_t>();
    }
    r.spool_dropped = out["sampling"]["spool"]["dropped"].get<std::uint64_t>();
    r.transport_dropped = out["transport_dropped"].get<std::uint64_t>();
    if (bench::alloc::available()) {
        for (const auto& [thread, n] : out["allocs"].items()) r.allocs[thread] = n.get<std::uint64_t>();
        r.window_rows = out["window_rows"].get<std::uint64_t>();
        r.window_dtus = out["window_dtus"].get<std::uint64_t>();
    }
    // Stragglers: the subscriber may still be reading.
    for (int i = 0; i < 100 && app.dtus() < r.dtus; ++i) std::this_thread::sleep_for(20ms);
    r.received = app.dtus();
    r.lossless = r.received == r.dtus && r.drops == 0 && r.spool_dropped == 0 && r.transport_dropped == 0 &&
                 r.null_share() <= kMaxNullShare;
    return r;
}

/// Thread CPU of one wake-up of a bare loop sleeping to absolute deadlines
/// one sample interval apart (what any sampler pays per tick before it reads
/// anything), measured over `ticks` ticks.
double wakeup_cpu_s(int ticks) {
    double cost = 0;
    std::thread loop([&] {
        timespec next{};
        clock_gettime(CLOCK_MONOTONIC, &next);
        const double c0 = thread_cpu_seconds();
        for (int i = 0; i < ticks; ++i) {
            next.tv_nsec += kSampleMs * 1'000'000L;
            if (next.tv_nsec >= 1'000'000'000L) {
                next.tv_nsec -= 1'000'000'000L;
                ++next.tv_sec;
            }
            clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
        }
        cost = (thread_cpu_seconds() - c0) / ticks;
    });
    loop.join();
    return cost;
}

/// A Sample DTU of the adapter's shape (points x rows doubles).
std::string encode_dtu(SampleEncoder& encoder, int points, std::size_t rows, int channel, std::int64_t t) {
    std::vector<SampleValue> values(static_cast<std::size_t>(points) * rows);
    for (std::size_t p = 0; p < static_cast<std::size_t>(points); ++p)
        for (std::size_t row = 0; row < rows; ++row)
            values[p * rows + row] = SampleValue::float64(123.456 + static_cast<double>(p));
    const std::string id = "dyn" + std::to_string(channel);
    SampleDtuHeader header;
    header.guid = kDev;
    header.channel_id = id;
    header.begin_time_ms = t;
    return std::string(encoder.encode(header, SampleBlock{values.data(), static_cast<std::size_t>(points), rows}));
}

/// The floor for `adapter`: encoding its DTUs + a bare publisher sending them.
double run_floor(int port, int channels, int points, int qos, const RunResult& adapter, double& encode_s, double& publish_s) {
    SampleEncoder encoder;
    // Encode as many DTUs as the adapter did, of the same mean number of rows
    // (it splits DTUs at sampling.max_dtu_bytes), in thread CPU time.
    const std::size_t rows = std::max<std::size_t>(
        1, static_cast<std::size_t>(static_cast<double>(adapter.points) / points / static_cast<double>(adapter.dtus) + 0.5));
    std::vector<std::string> payloads;
    const double e0 = thread_cpu_seconds();
    for (std::uint64_t i = 0; i < adapter.dtus; ++i) {
        std::string dtu = encode_dtu(encoder, points, rows, static_cast<int>(i % static_cast<std::uint64_t>(channels)) + 1,
                                     1763719200000 + static_cast<std::int64_t>(i));
        if (payloads.size() < static_cast<std::size_t>(channels)) payloads.push_back(std::move(dtu));
        bench::do_not_optimize(dtu);
    }
    encode_s = thread_cpu_seconds() - e0;
    const std::string file = "/tmp/nclink-bench-floor-" + std::to_string(::getpid()) + ".txt";
    {
        std::ofstream out(file, std::ios::binary);
        for (const auto& p : payloads) out << p << '\n';
    }
    App app(port, qos);
    const double per_second = static_cast<double>(adapter.dtus) / adapter.seconds;
    std::vector<std::string> args{
        "bench_sampling_throughput",  "--publisher-child",       std::to_string(port), std::to_string(qos), file,
        std::to_string(adapter.dtus), std::to_string(per_second)};
    if (g_system_heap) args.push_back("--system-heap");
    bench::Child child(args);
    child.say("mark");
    child.say("stop");
    const Json out = Json::parse(child.read_line());
    std::remove(file.c_str());
    publish_s = out["cpu_s"].get<double>();
    for (int i = 0; i < 100 && app.dtus() < adapter.dtus; ++i) std::this_thread::sleep_for(20ms);
    if (app.dtus() != adapter.dtus)
        std::printf("    (floor publisher: %llu of %llu DTUs arrived)\n", static_cast<unsigned long long>(app.dtus()),
                    static_cast<unsigned long long>(adapter.dtus));
    return encode_s + publish_s;
}

}  // namespace

/// Heap allocations of the adapter in its steady state (the first round at
/// the largest lossless load): the sampler thread's per row, which must be
/// zero, and the rest per DTU (a DTU is a message: its text, the outbox's
/// entry, paho's copy).
void report_allocations(const RunResult& r) {
    if (!bench::alloc::available()) {
        std::printf("     heap allocations: not counted in a sanitizer build\n");
        return;
    }
    if (r.window_rows == 0 || r.window_dtus == 0) return;
    std::uint64_t sampler = 0, uploader = 0, total = 0;
    std::string others;
    for (const auto& [thread, n] : r.allocs) {
        total += n;
        if (thread == "nclink-sampler") sampler += n;
        else if (thread.rfind("nclink-work", 0) == 0) uploader += n;  // uploader and outbox: the background threads
        else if (n > 0) others += fmt::format("{}{} {}", others.empty() ? "" : ", ", thread, n);
    }
    const auto rows = static_cast<double>(r.window_rows), dtus = static_cast<double>(r.window_dtus);
    // The sampler allocates nothing per row (test_steady_allocations); what
    // it shows here are the lines it logs for missed ticks.
    std::printf(
        "     heap allocations in steady state (%llu rows, %llu DTUs): sampler thread %llu (%.4f per row), "
        "background threads (uploader, outbox) %.1f per DTU, whole adapter %.1f per DTU = %.3f per row [%s]\n",
        static_cast<unsigned long long>(r.window_rows), static_cast<unsigned long long>(r.window_dtus),
        static_cast<unsigned long long>(sampler), static_cast<double>(sampler) / rows, static_cast<double>(uploader) / dtus,
        static_cast<double>(total) / dtus, static_cast<double>(total) / rows, others.c_str());
}

int run(int argc, char** argv);

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_sampling_throughput: %s\n", e.what());
        return 1;
    }
}

int run(int argc, char** argv) {
    // --json-reads may come anywhere; the other arguments are positional.
    std::vector<char*> kept;
    for (int i = 0; i < argc; ++i) {
        if (std::string(argv[i]) == "--json-reads") g_json_reads = true;
        else if (std::string(argv[i]) == "--no-value-checks") g_no_value_checks = true;
        else if (std::string(argv[i]) == "--system-heap") g_system_heap = true;
        else if (std::string(argv[i]) == "--slice-us" && i + 1 < argc) g_slice_us = std::atoi(argv[++i]);
        else if (std::string(argv[i]) == "--rt-priority" && i + 1 < argc) g_rt_priority = std::atoi(argv[++i]);
        else kept.push_back(argv[i]);
    }
    argc = static_cast<int>(kept.size());
    argv = kept.data();
    if (argc >= 3 && std::string(argv[1]) == "--adapter-child") return adapter_child(std::atoi(argv[2]));
    if (argc >= 7 && std::string(argv[1]) == "--publisher-child")
        return publisher_child(std::atoi(argv[2]), std::atoi(argv[3]), argv[4], std::strtoull(argv[5], nullptr, 10),
                               std::atof(argv[6]));
    const double seconds = argc > 1 ? std::atof(argv[1]) : 3.0;
    const int rounds = argc > 2 ? std::atoi(argv[2]) : 3;
    const int qos = argc > 3 ? std::atoi(argv[3]) : 0;

    test::MosquittoBroker broker;
    std::printf(
        "sampling throughput: %d ms sample, %d ms upload, QoS %d, %.1f s per run, %d rounds at the max load, %s reads, "
        "sampler %s, %s\n",
        kSampleMs, kUploadMs, qos, seconds, rounds, g_json_reads ? "Json (read())" : "typed (read_samples())",
        g_rt_priority > 0 ? ("SCHED_FIFO " + std::to_string(g_rt_priority)).c_str()
        : g_slice_us == 0
            ? "SCHED_OTHER, the kernel's slice"
            : ("SCHED_OTHER, slice " + std::to_string(g_slice_us < 0 ? SamplingConfig{}.slice_us : g_slice_us) + " us").c_str(),
        g_system_heap ? "glibc's default heap policy" : "freed heap kept");
    std::printf("%8s %7s %12s %12s %8s %8s %9s %s\n", "channels", "points", "points/s", "DTUs", "lost", "null %", "cpu_s",
                "lossless");
    std::vector<int> channel_counts{1, 10, 50}, point_counts{10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000, 20000, 50000};
    if (argc > 5) {
        channel_counts = {std::atoi(argv[4])};
        point_counts = {std::atoi(argv[5])};
    }
    for (int channels : channel_counts) {
        int best = 0;
        RunResult best_run;
        for (int points : point_counts) {
            if (channels * points > 50000) break;
            // A load that is not lossless runs once more before it ends the
            // search: one stall of the VM (a burst of ticks a period late)
            // must not stand for what the adapter carries. Both lines print.
            RunResult r;
            for (int attempt = 0; attempt < 2; ++attempt) {
                r = run_adapter(broker.port(), channels, points, qos, seconds);
                std::printf("%8d %7d %12.0f %12llu %8lld %8.2f %9.3f %s%s\n", channels, points, r.points_per_s(),
                            static_cast<unsigned long long>(r.dtus),
                            static_cast<long long>(r.dtus) - static_cast<long long>(r.received), 100.0 * r.null_share(), r.cpu_s,
                            r.lossless ? "yes" : "NO", attempt > 0 ? " (again)" : "");
                std::fflush(stdout);
                if (r.lossless) break;
            }
            if (!r.lossless) break;
            best = points;
            best_run = r;
        }
        if (best == 0) {
            std::printf("  %d channel(s): no lossless load found\n", channels);
            continue;
        }
        // Rounds at the largest lossless load: adapter and floor alternate.
        std::vector<double> adapter_pm, floor_pm, encode_pm, publish_pm, wake_pm, rates;
        for (int round = 0; round < rounds; ++round) {
            const RunResult r = round == 0 ? best_run : run_adapter(broker.port(), channels, best, qos, seconds);
            if (!r.lossless) std::printf("    (round %d not lossless)\n", round + 1);
            double encode_s = 0, publish_s = 0;
            const double floor_s = run_floor(broker.port(), channels, best, qos, r, encode_s, publish_s);
            const double millions = static_cast<double>(r.points) / 1e6;
            adapter_pm.push_back(r.per_million());
            floor_pm.push_back(floor_s / millions);
            encode_pm.push_back(encode_s / millions);
            publish_pm.push_back(publish_s / millions);
            // One wake-up per tick serves every channel (they share the grid).
            const double ticks_per_s = 1000.0 / kSampleMs;
            wake_pm.push_back(wakeup_cpu_s(1000) * ticks_per_s / (r.points_per_s() / 1e6));
            rates.push_back(r.points_per_s());
        }
        const double a = bench::median(adapter_pm), f = bench::median(floor_pm);
        std::printf(
            "  => %d channel(s) x %d points: %.0f points/s lossless; CPU s per million points: adapter %.3f "
            "[%.3f-%.3f], floor %.3f (encode %.3f + bare paho publish %.3f); ratio %.2fx (target <= 1.5x)\n",
            channels, best, bench::median(rates), a, bench::minimum(adapter_pm), bench::maximum(adapter_pm), f,
            bench::median(encode_pm), bench::median(publish_pm), f > 0 ? a / f : 0);
        // Not part of the target, what it leaves out: the floor sends
        // the same DTUs but never wakes at the sample rate, which a sampler
        // must; at small loads that alone is a large share of the floor.
        const double w = bench::median(wake_pm);
        std::printf(
            "     the %d ms wake-ups alone (a bare clock_nanosleep loop, same run): %.3f s per million points; "
            "adapter / (floor + wake-ups) %.2fx\n",
            kSampleMs, w, f + w > 0 ? a / (f + w) : 0);
        report_allocations(best_run);
        std::fflush(stdout);
    }
    return 0;
}
