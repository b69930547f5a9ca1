// Query and Set round trips through a real mosquitto: an application (bare
// paho) sends Query/Request/{dev}/{ex} (or Set/Request) and waits for the
// response, answered by an nclink Adapter with an in-memory driver; Query of
// 1 item and 100 items, Set of 1 value. The floor, measured in the same run
// through the same broker: a bare paho echo answering the same request with a
// payload of the adapter's response size, from inside its message callback.
// TCP_NODELAY is on for every client and the broker.
//
//   bench_query_roundtrip [round_trips=2000] [rounds=3]
//
// The adapter and the echo each run in a process of their own, as they would
// in a plant (child_process.hpp says why that matters with paho); the two
// requesters share this one. Floor and adapter requests alternate one by one
// so machine noise hits both alike.
#include <nclink/adapter.hpp>
#include <nclink/topics.hpp>

#include "bench_util.hpp"
#include "child_process.hpp"
#include "paho_echo.hpp"
#include "support/mosquitto_broker.hpp"

#include <mqtt/async_client.h>

#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <string>

using namespace nclink;

namespace {

const char* kDev = "bench-dev";
const char* kEx = "bench-app";

class MemoryDriver final : public Driver {
public:
    DriverInfo info() const override { return {"memory", "1", true}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = Json(123.456 + static_cast<double>(i));
    }
    Result<void> write(const WriteRequest&) override { return ok_result(); }
};

// A paho client that publishes a request and waits for the next message.
class Requester {
public:
    Requester(const std::string& url, const std::string& id, const std::string& reply_topic, int port)
        : client_(url, id, mqtt::create_options(MQTTVERSION_3_1_1), nullptr) {
        client_.set_message_callback([this](mqtt::const_message_ptr) {
            std::lock_guard<std::mutex> lock(mutex_);
            ++received_;
            cv_.notify_one();
        });
        bench::connect_and_subscribe(client_, reply_topic, port);
    }
    ~Requester() { client_.disconnect()->wait(); }

    double round_trip_us(const std::string& topic, const std::string& payload) {
        std::unique_lock<std::mutex> lock(mutex_);
        const std::uint64_t target = received_ + 1;
        const auto start = bench::now_ns();
        client_.publish(topic, payload.data(), payload.size(), 1, false);
        cv_.wait(lock, [&] { return received_ >= target; });
        return static_cast<double>(bench::now_ns() - start) / 1000.0;
    }

private:
    mqtt::async_client client_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::uint64_t received_ = 0;
};

// ---------------------------------------------------------------- children
// Lines on stdin; "stop" ends either child.

// The adapter under test. "stats" prints the request_seconds count and sum
// of Query and Set: the adapter's own time per request, from admission to
// the answer handed to paho.
int adapter_child(int port) {
    AdapterConfig config;
    config.model_path = std::string(NCLINK_SOURCE_DIR) + "/tests/data/adapter-test-model.json";
    config.broker_url = "tcp://127.0.0.1:" + std::to_string(port);
    config.dev_uuid = kDev;
    config.log_level = LogLevel::warn;
    Adapter adapter(config, std::make_shared<MemoryDriver>(), Logger(stderr_sink(), LogLevel::warn));
    if (auto started = adapter.start(); !started) {
        std::fprintf(stderr, "adapter: %s\n", started.error().describe().c_str());
        return 1;
    }
    while (adapter.state() != AdapterState::normal) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::printf("ready\n");
    std::fflush(stdout);
    std::string line;
    while (std::getline(std::cin, line) && line != "stop") {
        if (line != "stats") continue;
        auto seconds = adapter.traffic_stats().request_seconds;
        Json out = Json{{"cpu_s", bench::process_cpu_seconds()}};
        for (const char* kind : {"query_request", "set_request"})
            out[kind] = Json::array({seconds[kind].count, seconds[kind].sum});
        std::printf("%s\n", out.dump().c_str());
        std::fflush(stdout);
    }
    adapter.stop();
    return 0;
}

// The floor. "reply <text>" sets the answer (one line: compact JSON), then "ok".
int echo_child(int port) {
    // The answer is the payload last given, the adapter's answer size.
    std::mutex mutex;
    std::string reply;
    bench::PahoEcho echo("tcp://127.0.0.1:" + std::to_string(port), "bench-echo", "Floor/Request", port,
                         [&](const mqtt::message&, mqtt::async_client& client) {
                             std::lock_guard<std::mutex> lock(mutex);
                             client.publish("Floor/Response", reply.data(), reply.size(), 1, false);
                         });
    std::printf("ready\n");
    std::fflush(stdout);
    std::string line;
    while (std::getline(std::cin, line) && line != "stop") {
        if (line == "cpu") {
            std::printf("%.6f\n", bench::process_cpu_seconds());
        } else if (line.rfind("reply ", 0) == 0) {
            std::lock_guard<std::mutex> lock(mutex);
            reply = line.substr(6);
            std::printf("ok\n");
        }
        std::fflush(stdout);
    }
    return 0;
}

struct Figures {
    std::vector<double> samples;
};

// Every request gets its own @id: the adapter (rightly) ignores a repeated one.
// Floor and adapter requests alternate one by one, so a slower moment of the
// machine (a VM's neighbours, a frequency change) falls on both alike; whole
// rounds of one then the other let such a moment move the ratio by 0.3x.
void measure(Requester& floor_app, const std::string& floor_topic, Requester& app, const std::string& topic,
             const std::string& payload_tail, int n, Figures& floor, Figures& sdk) {
    static std::uint64_t counter = 0;
    auto payload = [&] { return "{\"@id\":\"b" + std::to_string(++counter) + "\"," + payload_tail; };
    for (int i = 0; i < 100; ++i) {  // warm up
        floor_app.round_trip_us(floor_topic, payload());
        app.round_trip_us(topic, payload());
    }
    floor.samples.reserve(floor.samples.size() + static_cast<std::size_t>(n));
    sdk.samples.reserve(sdk.samples.size() + static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        floor.samples.push_back(floor_app.round_trip_us(floor_topic, payload()));
        sdk.samples.push_back(app.round_trip_us(topic, payload()));
    }
}

std::string set_payload() {
    const Json values = Json::array({Json{{"id", "feed_ovr_cfg"}, {"params", {{"value", 42}}}}});
    return Json{{"guid", kDev}, {"values", values}}.dump().substr(1);
}

std::string query_payload(int items) {
    Json ids = Json::array();
    for (int i = 0; i < items; ++i) ids.push_back(Json{{"id", i % 2 ? "pos" : "ovr"}});
    // Without the leading '{': measure() prepends a fresh "@id".
    return Json{{"guid", kDev}, {"ids", ids}}.dump().substr(1);
}

}  // namespace

int main(int argc, char** argv) {
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    if (argc >= 3 && std::string(argv[1]) == "--adapter-child") return adapter_child(std::atoi(argv[2]));
    if (argc >= 3 && std::string(argv[1]) == "--echo-child") return echo_child(std::atoi(argv[2]));
    const int n = argc > 1 ? std::atoi(argv[1]) : 2000;
    const int rounds = argc > 2 ? std::atoi(argv[2]) : 3;
    test::MosquittoBroker broker;
    const std::string url = broker.url();
    const std::string port = std::to_string(broker.port());
    bench::Child adapter({"bench_query_roundtrip", "--adapter-child", port});
    bench::Child echo({"bench_query_roundtrip", "--echo-child", port});
    // The adapter's own time per request: {kind: [count, sum of seconds]}, and its CPU seconds.
    const auto inside = [&adapter] {
        adapter.say("stats");
        return Json::parse(adapter.read_line());
    };
    const auto echo_cpu = [&echo] {
        echo.say("cpu");
        return std::stod(echo.read_line());
    };

    const std::string floor_request_topic = "Floor/Request";
    const std::string floor_reply_topic = "Floor/Response";

    std::printf("Query and Set round trips through mosquitto (QoS 1, TCP_NODELAY everywhere), %d round trips x %d rounds\n", n,
                rounds);
    std::printf("%-10s %-8s %10s %10s %10s %8s\n", "request", "path", "p50 us", "p99 us", "max us", "bytes");
    struct Case {
        const char* kind;
        int items;
    };
    for (const Case c : {Case{"Query", 1}, Case{"Query", 100}, Case{"Set", 1}}) {
        const int items = c.items;
        const bool set = std::string(c.kind) == "Set";
        const std::string payload = set ? set_payload() : query_payload(items);
        const std::string request_topic = set ? topics::set_request(kDev, kEx) : topics::query_request(kDev, kEx);
        const std::string reply_topic = set ? topics::set_response(kDev, kEx) : topics::query_response(kDev, kEx);
        // Size the floor's answer like the adapter's.
        std::string adapter_reply;
        {
            mqtt::async_client probe(url, "bench-sizer", mqtt::create_options(MQTTVERSION_3_1_1), nullptr);
            std::mutex m;
            std::condition_variable cv;
            probe.set_message_callback([&](mqtt::const_message_ptr msg) {
                std::lock_guard<std::mutex> lock(m);
                adapter_reply = msg->to_string();
                cv.notify_one();
            });
            probe.connect()->wait();
            probe.subscribe(set ? topics::set_response(kDev, "sizer") : topics::query_response(kDev, "sizer"), 1)->wait();
            const std::string sized = "{\"@id\":\"sizer-" + std::string(c.kind) + std::to_string(items) + "\"," + payload;
            const std::string sizer_topic = set ? topics::set_request(kDev, "sizer") : topics::query_request(kDev, "sizer");
            probe.publish(sizer_topic, sized.data(), sized.size(), 1, false);
            std::unique_lock<std::mutex> lock(m);
            cv.wait(lock, [&] { return !adapter_reply.empty(); });
            lock.unlock();
            probe.disconnect()->wait();
        }
        echo.say(("reply " + adapter_reply).c_str());
        if (echo.read_line() != "ok") throw std::runtime_error("echo child did not take the reply");
        Requester app(url, "bench-app", reply_topic, broker.port());
        Requester floor_app(url, "bench-floor-app", floor_reply_topic, broker.port());
        Figures floor, sdk;
        const char* kind_key = set ? "set_request" : "query_request";
        const Json before_all = inside();
        const double echo_before = echo_cpu();
        for (int r = 0; r < rounds; ++r) measure(floor_app, floor_request_topic, app, request_topic, payload, n, floor, sdk);
        const Json after_all = inside();
        const double echo_after = echo_cpu();
        const Json& before = before_all[kind_key];
        const Json& after = after_all[kind_key];
        const double f50 = bench::median(floor.samples), s50 = bench::median(sdk.samples);
        const std::string label = std::string(c.kind) + " " + std::to_string(items);
        std::printf("%-10s %-8s %10.1f %10.1f %10.1f %8zu\n", label.c_str(), "floor", f50, bench::percentile(floor.samples, 99),
                    bench::maximum(floor.samples), adapter_reply.size());
        std::printf("%-10s %-8s %10.1f %10.1f %10.1f %8zu\n", label.c_str(), "adapter", s50, bench::percentile(sdk.samples, 99),
                    bench::maximum(sdk.samples), adapter_reply.size());
        std::printf("%-10s ratio    %10.2fx (median adapter / median floor; target %s)\n", label.c_str(), s50 / f50,
                    items == 1 ? "<= 1.2x" : "<= 1.5x");
        // What of the difference is nclink's own work and what the hand-offs
        // around it; and the CPU each side spent per request (warm-up
        // included alike), which the VM's noise moves far less than latency.
        const auto count = after[0].get<double>() - before[0].get<double>();
        if (count > 0) {
            std::printf("%-10s inside   %10.1f us mean, admitted to answer handed to paho\n", label.c_str(),
                        (after[1].get<double>() - before[1].get<double>()) / count * 1e6);
            const double adapter_cpu = (after_all["cpu_s"].get<double>() - before_all["cpu_s"].get<double>()) / count * 1e6;
            const double floor_cpu = (echo_after - echo_before) / count * 1e6;
            std::printf("%-10s cpu      %10.1f us per request, echo %.1f us: %.2fx\n", label.c_str(), adapter_cpu, floor_cpu,
                        adapter_cpu / floor_cpu);
        }
    }
    adapter.say("stop");
    echo.say("stop");
    return 0;
}
