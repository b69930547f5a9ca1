// What an adapter says when it cannot start, and what it does not say: each
// message a newcomer meets on the first day, shown here verbatim.
#include "support/adapter_fixture.hpp"

#include <nclink/mqtt_transport.hpp>
#include <nclink/run_adapter.hpp>

#include <unistd.h>

#include <cstdio>
#include <fstream>

using namespace nclink;
using namespace nclink::test;

namespace {

struct Captured {
    std::mutex mutex;
    std::vector<std::pair<LogLevel, std::string>> lines;
    Logger logger(LogLevel level = LogLevel::info) {
        return Logger(
            [this](LogLevel l, std::string_view m) {
                std::lock_guard<std::mutex> lock(mutex);
                lines.emplace_back(l, std::string(m));
            },
            level);
    }
    std::size_t count(const std::string& part) {
        std::lock_guard<std::mutex> lock(mutex);
        std::size_t n = 0;
        for (const auto& [level, text] : lines) n += text.find(part) != std::string::npos;
        return n;
    }
};

class CountingDriver : public FakeDriver {
public:
    Result<void> open(const DriverContext&) override {
        ++opened;
        return ok_result();
    }
    void close() override { ++closed; }
    int opened = 0, closed = 0;
};

/// Runs run_adapter() with these arguments, capturing its stderr.
std::pair<int, std::string> run(std::vector<std::string> args, std::shared_ptr<Driver> driver) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    std::fflush(stderr);
    std::FILE* capture = std::tmpfile();
    const int saved = dup(fileno(stderr));
    dup2(fileno(capture), fileno(stderr));
    RunAdapterOptions o;
    o.default_config = "";
    const int status = run_adapter(static_cast<int>(argv.size()), argv.data(), std::move(driver), o);
    std::fflush(stderr);
    dup2(saved, fileno(stderr));
    close(saved);
    std::rewind(capture);
    std::string text;
    char buffer[512];
    while (std::size_t n = std::fread(buffer, 1, sizeof buffer, capture)) text.append(buffer, n);
    std::fclose(capture);
    return {status, text};
}

}  // namespace

TEST_CASE("a bad broker URL is refused before the driver opens, with the expected form") {
    AdapterConfig c;
    c.model_path = test_model_path();
    c.broker_url = "localhost:1883";
    auto driver = std::make_shared<CountingDriver>();
    Adapter adapter(c, driver);
    auto r = adapter.start();
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().message ==
          "unusable broker URL 'localhost:1883': it has no scheme (did you mean tcp://localhost:1883?); expected "
          "SCHEME://HOST[:PORT] with SCHEME tcp, mqtt, ssl, mqtts, ws or wss, e.g. tcp://127.0.0.1:1883");
    CHECK(driver->opened == 0);
    CHECK(check_broker_url("http://broker").error().message.find("unknown scheme 'http'") != std::string::npos);
    CHECK(check_broker_url("tcp://broker:1883").ok());
}

TEST_CASE("a missing model file is reported once, with the system's reason, not as a syntax error") {
    Captured log;
    AdapterConfig c;
    c.model_path = "/nonexistent/lathe.json";
    LoopbackBroker broker;
    Adapter adapter(c, std::make_shared<FakeDriver>(), log.logger(LogLevel::trace));
    adapter.use_transport(make_loopback_transport(broker, {"adapter", std::nullopt, {}}));
    auto r = adapter.start();
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::unavailable);
    CHECK(r.error().message == "cannot read the model file /nonexistent/lathe.json: No such file or directory");
    CHECK(log.count("lathe.json") == 0);  // the caller logs the error: once
}

TEST_CASE("starting logs no lost link before the first connection") {
    Captured log;
    AdapterConfig c;
    c.model_path = test_model_path();
    c.persistence_dir = scratch_dir("messages");
    LoopbackBroker broker;
    Adapter adapter(c, std::make_shared<FakeDriver>(), log.logger(LogLevel::info));
    adapter.use_transport(make_loopback_transport(broker, {"adapter", std::nullopt, {}}));
    REQUIRE(adapter.start().ok());
    REQUIRE(eventually([&] { return adapter.state() == AdapterState::normal; }));
    adapter.stop();
    CHECK(log.count("link_lost") == 0);
    CHECK(log.count("-> disconnected") == 0);
    std::filesystem::remove_all(c.persistence_dir);
}

TEST_CASE("run_adapter: usage and configuration errors exit 2 with the reason, --check exits 0") {
    auto driver = std::make_shared<FakeDriver>();
    auto [usage, usage_text] = run({"lathe", "--bogus"}, driver);
    CHECK(usage == 2);
    CHECK_THAT(usage_text, Catch::Contains("lathe: unknown option --bogus"));
    CHECK_THAT(usage_text, Catch::Contains("usage: lathe [options]"));

    auto [url, url_text] = run({"lathe", "--model", test_model_path(), "--broker", "127.0.0.1:1883"}, driver);
    CHECK(url == 2);
    CHECK_THAT(url_text, Catch::Contains("did you mean tcp://127.0.0.1:1883?"));

    auto [no_config, no_config_text] = run({"lathe", "--config", "/nonexistent/adapter.json"}, driver);
    CHECK(no_config == 2);
    CHECK_THAT(no_config_text,
               Catch::Contains("cannot read configuration file /nonexistent/adapter.json: No such file or directory"));

    const auto dir = scratch_dir("run-adapter");
    std::ofstream(dir + "/adapter.json") << R"({"broker": {"uri": "tcp://x"}})";
    auto [typo, typo_text] = run({"lathe", "--config", dir + "/adapter.json"}, driver);
    CHECK(typo == 2);
    CHECK_THAT(typo_text, Catch::Contains("broker.uri: unknown key; did you mean \"url\"?"));
    std::filesystem::remove_all(dir);

    auto [no_model, no_model_text] = run({"lathe"}, driver);
    CHECK(no_model == 2);
    CHECK_THAT(no_model_text, Catch::Contains("no model"));

    auto [check, check_text] = run({"lathe", "--model", test_model_path(), "--check"}, driver);
    CHECK(check == 0);
}
