// Methods through the wire: the simulated mill behind an Adapter, a real
// mosquitto, the client library and the `nclink call`/`control` commands.
// The adapter and the simulator share a ManualClock: the test moves time, so
// progress and Method/Status follow it, never the wall clock.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>
#include "sim/sim_driver.hpp"
#include <nclink/topics.hpp>

#include "support/cli.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/sim_mill_rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>
#include <random>
#include <thread>

using namespace nclink;
using nclink::test::cli_built;
using nclink::test::run_cli;
using Run = nclink::test::CliRun;
using namespace std::chrono_literals;
using nclink::test::eventually;
using nclink::test::MosquittoBroker;
using nclink::test::ScratchDir;
using nclink::test::sim_for;
using nclink::test::sim_mill_path;
using nclink::test::started_adapter;
using nclink::test::started_client;
namespace fs = std::filesystem;

namespace {

const std::string kDev = nclink::test::kSimMillDevice;

struct Rig : nclink::test::SimMillRig {
    fs::path root = scratch.path;
    fs::path programs = root / "prog";
    fs::path outside = root / "outside";
    std::shared_ptr<ManualClock> clock = std::make_shared<ManualClock>();
    std::shared_ptr<SimDriver> sim;

    explicit Rig(std::size_t max_running = 4) : SimMillRig({}, "nclink-itest-methods-") {
        fs::create_directories(programs);
        fs::create_directories(outside);
        config.persistence_dir = (root / "state").string();
        config.register_timeout = 200ms;
        config.sampling.enabled = false;  // not under test (its threads wait on the ManualClock)
        config.methods.max_running = max_running;
        config.methods.status_period = 100ms;
        config.driver_config = Json{{"program_dir", programs.string()}, {"transfer_rate", 1024}};
        SimOptions options;
        options.clock = clock;
        sim = sim_for(config.model_path, options);
        driver = sim;
        start(clock);
        client = make_client("mes-1", 10s);
    }

    fs::path make_file(const std::string& name, std::size_t bytes) {
        const fs::path path = outside / name;
        std::ofstream out(path, std::ios::binary);
        for (std::size_t i = 0; i < bytes; ++i) out.put(static_cast<char>('0' + i % 10));
        return path;
    }
    std::size_t program_entries() const {
        return static_cast<std::size_t>(std::distance(fs::directory_iterator(programs), fs::directory_iterator()));
    }
};

/// One call in flight: its statuses and its result, filled on the client's dispatch thread.
struct Call {
    std::mutex mutex;
    std::vector<MethodStatus> statuses;
    std::promise<Result<MethodResult>> promise;
    std::future<Result<MethodResult>> future = promise.get_future();

    void start(Client& client, const std::string& method, Json args) {
        client.call_method_async(
            kDev, method, std::move(args),
            [this](const MethodStatus& s) {
                std::lock_guard<std::mutex> lock(mutex);
                statuses.push_back(s);
            },
            [this](Result<MethodResult> r) { promise.set_value(std::move(r)); });
    }
    std::vector<MethodStatus> seen() {
        std::lock_guard<std::mutex> lock(mutex);
        return statuses;
    }
    double progress() {
        auto s = seen();
        return s.empty() || !s.back().progress ? -1 : *s.back().progress;
    }
    bool phase_seen(const std::string& phase) {
        for (const auto& s : seen())
            if (s.status == phase) return true;
        return false;
    }
    bool done() { return future.wait_for(0s) == std::future_status::ready; }
};

}  // namespace

TEST_CASE("a program transfer called through mosquitto reports its progress and finishes") {
    Rig rig;
    const fs::path source = rig.make_file("O1234.nc", 8 * 1024);  // 8 s at 1 KiB/s
    Call call;
    call.start(*rig.client, "program_transfer", Json{{"source", source.string()}});
    REQUIRE(eventually([&] { return call.phase_seen("executing"); }));
    while (!call.done()) {
        rig.clock->advance(500ms);
        std::this_thread::sleep_for(20ms);
    }
    auto result = call.future.get();
    REQUIRE(result.ok());
    CHECK(result->result == "finished");
    CHECK(result->status.ok);
    CHECK((*result->return_value)["bytes"] == 8192);
    CHECK(fs::file_size(rig.programs / "O1234.nc") == 8192);
    const auto statuses = call.seen();
    REQUIRE(statuses.size() >= 4);
    CHECK(statuses[0].status == "waiting");
    bool midway = false;
    double last = 0;
    for (const auto& s : statuses) {
        if (!s.progress) continue;
        CHECK(*s.progress >= last);
        last = *s.progress;
        midway = midway || (*s.progress > 0 && *s.progress < 100);
    }
    CHECK(midway);
}

TEST_CASE("stop, resume and cancel of a program transfer through mosquitto leave no partial file") {
    Rig rig;
    const fs::path source = rig.make_file("O5000.nc", 64 * 1024);  // 64 s of the clock
    Call call;
    call.start(*rig.client, "program_transfer", Json{{"source", source.string()}, {"destination", "O5000"}});
    REQUIRE(eventually([&] { return call.phase_seen("executing"); }));
    rig.clock->advance(3s);
    REQUIRE(eventually([&] {
        rig.clock->advance(100ms);
        return call.progress() > 0;
    }));

    REQUIRE(rig.client->control_method(kDev, "program_transfer", Client::MethodAction::stop).ok());
    REQUIRE(eventually([&] {
        rig.clock->advance(100ms);  // the chunk under way completes; the next checkpoint pauses
        return call.phase_seen("stopped");
    }));
    const double paused_at = call.progress();
    rig.clock->advance(5s);
    std::this_thread::sleep_for(100ms);
    rig.clock->advance(200ms);  // a periodic Status while paused
    REQUIRE(eventually([&] { return call.seen().back().status == "stopped" && call.seen().size() >= 2; }));
    CHECK(call.progress() == paused_at);

    REQUIRE(rig.client->control_method(kDev, "program_transfer", Client::MethodAction::resume).ok());
    REQUIRE(eventually([&] {
        rig.clock->advance(200ms);
        return call.progress() > paused_at;
    }));
    CHECK(call.progress() < 100);

    REQUIRE(rig.client->control_method(kDev, "program_transfer", Client::MethodAction::cancel).ok());
    auto result = call.future.get();
    REQUIRE(result.ok());
    CHECK(result->result == "canceled");
    CHECK(rig.program_entries() == 0);  // neither O5000 nor a temp file
    auto late = rig.client->control_method(kDev, "program_transfer", Client::MethodAction::cancel);
    REQUIRE_FALSE(late.ok());
    CHECK(late.error().code == ErrorCode::unavailable);
    CHECK(late.error().message.find("not running") != std::string::npos);
}

TEST_CASE("rejected calls and controls are answered through mosquitto") {
    Rig rig;
    auto unknown = rig.client->call_method(kDev, "self_destruct", nullptr);
    REQUIRE(unknown.ok());
    CHECK(unknown->result == "error");
    CHECK(unknown->status.error == 401);
    auto no_source = rig.client->call_method(kDev, "program_transfer", Json{{"operation", "push"}});
    REQUIRE(no_source.ok());
    CHECK(no_source->status.error == 102);
    auto extra = rig.client->call_method(kDev, "feed_hold", Json{{"force", true}});
    REQUIRE(extra.ok());
    CHECK(extra->status.error == 409);
    auto driver_refusal = rig.client->call_method(kDev, "program_transfer", Json{{"source", "/nonexistent/O1"}});
    REQUIRE(driver_refusal.ok());
    CHECK(driver_refusal->result == "error");
    CHECK(driver_refusal->status.error == 202);
    CHECK((*driver_refusal->private_info)["message"].get<std::string>().find("/nonexistent/O1") != std::string::npos);

    // An action outside stop/resume/cancel, sent raw (the client only sends valid ones).
    MqttOptions o;
    o.broker_url = rig.broker.url();
    o.client_id = "raw-app";
    auto raw = make_mqtt_transport(o).value();
    std::mutex mutex;
    std::vector<Json> answers;
    raw->set_message_handler([&](const Message& m) {
        std::lock_guard<std::mutex> lock(mutex);
        answers.push_back(Json::parse(m.payload));
    });
    REQUIRE(raw->subscribe({topics::method_control_response(kDev, std::string_view("raw-app"))}, 1).ok());
    REQUIRE(raw->start().ok());
    REQUIRE(eventually([&] { return raw->state() == LinkState::connected; }));
    REQUIRE(eventually([&] {
        (void)raw->publish({topics::method_control_request(kDev, std::string_view("raw-app")),
                            R"({"@id":"k1","guid":"nclink-sim-mill-01","id":"program_transfer","action":"pause"})", 1, false});
        return eventually(
            [&] {
                std::lock_guard<std::mutex> lock(mutex);
                return !answers.empty();
            },
            300ms);
    }));
    {
        std::lock_guard<std::mutex> lock(mutex);
        CHECK(answers[0]["error"] == 418);
        CHECK(answers[0]["reason"] == "method action type error");
    }
    raw->stop(0ms);
}

TEST_CASE("concurrent calls through mosquitto run up to the limit and the next is refused 417") {
    Rig rig(2);
    Call a, b;
    a.start(*rig.client, "program_transfer", Json{{"source", rig.make_file("A.nc", 4096).string()}});
    b.start(*rig.client, "program_transfer", Json{{"source", rig.make_file("B.nc", 4096).string()}});
    REQUIRE(eventually([&] { return a.phase_seen("executing") && b.phase_seen("executing"); }));
    auto third = rig.client->call_method(kDev, "feed_hold", nullptr);
    REQUIRE(third.ok());
    CHECK(third->result == "error");
    CHECK(third->status.error == 417);
    CHECK(third->status.reason == "Insufficient method resources");
    while (!a.done() || !b.done()) {
        rig.clock->advance(500ms);
        std::this_thread::sleep_for(20ms);
    }
    CHECK(a.future.get()->result == "finished");
    CHECK(b.future.get()->result == "finished");
    CHECK(fs::file_size(rig.programs / "A.nc") == 4096);
    CHECK(fs::file_size(rig.programs / "B.nc") == 4096);
    auto again = rig.client->call_method(kDev, "feed_hold", nullptr);
    REQUIRE(again.ok());
    CHECK(again->result == "finished");
}

TEST_CASE("cycle start, feed hold and reset move the simulated mill as queries show") {
    Rig rig;
    auto hold = rig.client->call_method(kDev, "feed_hold", nullptr);
    REQUIRE(hold.ok());
    CHECK(hold->result == "finished");
    CHECK((*hold->return_value)["status"] == "holding");
    CHECK(rig.query_one("status") == "holding");
    REQUIRE(rig.client->call_method(kDev, "cycle_start", Json::object())->result == "finished");
    CHECK(rig.query_one("status") == "running");
    REQUIRE(rig.client->call_method(kDev, "reset", nullptr)->result == "finished");
    CHECK(rig.query_one("status") == "free");
    CHECK(rig.query_one("line_number") == "0");
}

TEST_CASE("nclink call and nclink control against the simulated mill") {
    if (!cli_built()) {
        WARN("bin/nclink not built (NCLINK_BUILD_TOOLS=OFF): skipped");
        return;
    }
    Rig rig;
    const std::string common = "--broker " + rig.broker.url() + " --timeout 10000 ";
    auto hold = run_cli("call " + common + kDev + " feed_hold");
    CHECK(hold.status == 0);
    CHECK(hold.out.find("status waiting") != std::string::npos);
    CHECK(hold.out.find("finished\n") != std::string::npos);
    CHECK(hold.out.find("\"holding\"") != std::string::npos);
    CHECK(rig.query_one("status") == "holding");

    auto unknown = run_cli("call " + common + "--json --device " + kDev + " self_destruct");
    CHECK(unknown.status == 1);
    const std::string trimmed = unknown.out.substr(0, unknown.out.find_last_not_of('\n') + 1);
    const Json last = Json::parse(trimmed.substr(trimmed.rfind('\n') == std::string::npos ? 0 : trimmed.rfind('\n') + 1));
    CHECK(last["error"] == 401);

    // A paced transfer: the CLI prints progress lines while the test moves the clock.
    const fs::path source = rig.make_file("O7.nc", 4096);
    std::atomic<bool> done{false};
    std::thread ticker([&] {
        while (!done) {
            rig.clock->advance(250ms);
            std::this_thread::sleep_for(15ms);
        }
    });
    auto transfer = run_cli("call " + common + kDev + " program_transfer '{\"source\":\"" + source.string() + "\"}'");
    done = true;
    ticker.join();
    CHECK(transfer.status == 0);
    CHECK(transfer.out.find("status executing") != std::string::npos);
    CHECK(transfer.out.find("finished\n") != std::string::npos);
    CHECK(fs::file_size(rig.programs / "O7.nc") == 4096);

    auto idle = run_cli("control " + common + kDev + " program_transfer cancel");
    CHECK(idle.status == 1);
    CHECK(idle.out.find("NG 202 Unavailable") != std::string::npos);
    CHECK(run_cli("control " + common + kDev + " program_transfer pause").status == 2);
    CHECK(run_cli("call " + common).status == 2);
    CHECK(run_cli("call " + common + kDev + " feed_hold '[1]'").status == 2);
}
