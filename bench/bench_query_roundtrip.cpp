// Query and Set round trips through a real mosquitto: an application (bare
// paho) sends Query/Request/{dev}/{ex} (or Set/Request) and waits for the
// response, answered by an nclink Adapter with an in-memory driver; Query of
// 1 item and 100 items, Set of 1 value. The floor, measured in the same run through the same broker: a bare
// paho echo answering the same request with a payload of the adapter's
// response size. TCP_NODELAY is on for every client and the broker.
//
//   bench_query_roundtrip [round_trips=2000] [rounds=3]
//
// Floor and adapter requests alternate one by one so machine noise hits both alike.
#include <nclink/adapter.hpp>
#include <nclink/topics.hpp>

#include "bench_util.hpp"
#include "support/mosquitto_broker.hpp"
#include "transport/tcp_nodelay.hpp"

#include <mqtt/async_client.h>

#include <condition_variable>
#include <cstdio>
#include <cstdlib>
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

void connect_and_subscribe(mqtt::async_client& client, const std::string& topic, int port) {
    auto options = mqtt::connect_options_builder().clean_session(true).mqtt_version(MQTTVERSION_3_1_1).finalize();
    if (!client.connect(options)->wait_for(std::chrono::seconds(10)))
        throw std::runtime_error("connect of " + client.get_client_id() + " timed out");
    detail::apply_tcp_nodelay_to_peer("127.0.0.1", port);
    if (!client.subscribe(topic, 1)->wait_for(std::chrono::seconds(10)))
        throw std::runtime_error("subscribe of " + client.get_client_id() + " timed out");
}

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
        connect_and_subscribe(client_, reply_topic, port);
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

// The floor: answers every request at once with a fixed payload.
class Echo {
public:
    Echo(const std::string& url, const std::string& request_topic, std::string reply_topic, std::string reply, int port)
        : client_(url, "bench-echo", mqtt::create_options(MQTTVERSION_3_1_1), nullptr),
          reply_topic_(std::move(reply_topic)),
          reply_(std::move(reply)) {
        client_.set_message_callback([this](mqtt::const_message_ptr) {
            client_.publish(reply_topic_, reply_.data(), reply_.size(), 1, false);
        });
        connect_and_subscribe(client_, request_topic, port);
    }
    ~Echo() { client_.disconnect()->wait(); }

private:
    mqtt::async_client client_;
    std::string reply_topic_;
    std::string reply_;
};

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
    const int n = argc > 1 ? std::atoi(argv[1]) : 2000;
    const int rounds = argc > 2 ? std::atoi(argv[2]) : 3;
    test::MosquittoBroker broker;
    const std::string url = broker.url();

    AdapterConfig config;
    config.model_path = std::string(NCLINK_SOURCE_DIR) + "/tests/data/adapter-test-model.json";
    config.broker_url = url;
    config.dev_uuid = kDev;
    config.log_level = LogLevel::warn;
    Adapter adapter(config, std::make_shared<MemoryDriver>());
    if (auto started = adapter.start(); !started) {
        std::fprintf(stderr, "adapter: %s\n", started.error().describe().c_str());
        return 1;
    }
    while (adapter.state() != AdapterState::normal) std::this_thread::sleep_for(std::chrono::milliseconds(5));

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
        Requester app(url, "bench-app", reply_topic, broker.port());
        Requester floor_app(url, "bench-floor-app", floor_reply_topic, broker.port());
        Echo echo(url, floor_request_topic, floor_reply_topic, adapter_reply, broker.port());
        Figures floor, sdk;
        const auto kind_key = set ? "set_request" : "query_request";
        const auto inside_before = adapter.traffic_stats().request_seconds[kind_key];
        for (int r = 0; r < rounds; ++r) measure(floor_app, floor_request_topic, app, request_topic, payload, n, floor, sdk);
        const double f50 = bench::median(floor.samples), s50 = bench::median(sdk.samples);
        const std::string label = std::string(c.kind) + " " + std::to_string(items);
        std::printf("%-10s %-8s %10.1f %10.1f %10.1f %8zu\n", label.c_str(), "floor", f50, bench::percentile(floor.samples, 99),
                    bench::maximum(floor.samples), adapter_reply.size());
        std::printf("%-10s %-8s %10.1f %10.1f %10.1f %8zu\n", label.c_str(), "adapter", s50, bench::percentile(sdk.samples, 99),
                    bench::maximum(sdk.samples), adapter_reply.size());
        std::printf("%-10s ratio    %10.2fx (median adapter / median floor; target %s)\n", label.c_str(), s50 / f50,
                    items == 1 ? "<= 1.2x" : "<= 1.5x");
        // The adapter's own view (admission to answer handed to paho, its
        // request_seconds histogram): what of the difference is nclink's
        // work and what is the hand-offs around it.
        const auto inside = adapter.traffic_stats().request_seconds[kind_key];
        if (inside.count > inside_before.count)
            std::printf("%-10s inside   %10.1f us mean, admitted to answer handed to paho\n", label.c_str(),
                        (inside.sum - inside_before.sum) / static_cast<double>(inside.count - inside_before.count) * 1e6);
    }
    adapter.stop();
    return 0;
}
