#include <nclink/adapter_config.hpp>

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace nclink;

TEST_CASE("a configuration file sets every key and resolves paths relative to itself") {
    const auto dir = std::filesystem::temp_directory_path() / "nclink-config-test";
    std::filesystem::create_directories(dir);
    const auto file = dir / "adapter.json";
    std::ofstream(file) << R"({
      "broker": {"url": "ssl://broker.plant:8883", "client_id": "mill-7", "username": "u", "password": "p",
                 "mqtt_version": 5, "keep_alive_s": 30, "clean_session": false,
                 "connect_timeout_ms": 30000, "reconnect_min_ms": 2000, "reconnect_max_ms": 40000,
                 "tls": {"ca_file": "ca.pem", "verify": false}},
      "model": "models/mill.json", "device": "dev-1", "dev_uuid": "line3-mill7", "strict": true,
      "persistence_dir": "state", "standard_typo_topics": false, "offline_buffer_bytes": 1000,
      "max_in_flight": 8, "dedup_window_ms": 500, "dedup_capacity": 10, "request_threads": 3,
      "driver_timeout_ms": 250, "register_timeout_ms": 100, "register_retry_max_ms": 900,
      "heap_keep_bytes": 1048576, "log_level": "debug",
      "driver": {"plugin": "drivers/sim.so", "config": {"seed": 4}}
    })";
    auto loaded = load_adapter_config(file.string());
    INFO((loaded.ok() ? "" : loaded.error().describe()));
    REQUIRE(loaded.ok());
    const AdapterConfig& c = loaded.value();
    CHECK(c.broker_url == "ssl://broker.plant:8883");
    CHECK(c.client_id == "mill-7");
    CHECK(c.mqtt_version == 5);
    CHECK(c.keep_alive == std::chrono::seconds(30));
    CHECK(c.connect_timeout == std::chrono::seconds(30));
    CHECK(c.reconnect_min == std::chrono::seconds(2));
    CHECK(c.reconnect_max == std::chrono::seconds(40));
    CHECK_FALSE(c.clean_session);
    REQUIRE(c.tls.has_value());
    CHECK(c.tls->ca_file == (dir / "ca.pem").string());
    CHECK_FALSE(c.tls->verify_server);
    CHECK(c.model_path == (dir / "models/mill.json").string());
    CHECK(c.persistence_dir == (dir / "state").string());
    CHECK(c.driver_plugin == (dir / "drivers/sim.so").string());
    CHECK(c.driver_config == Json{{"seed", 4}});
    CHECK(c.device_id == "dev-1");
    CHECK(c.dev_uuid == "line3-mill7");
    CHECK(c.strict);
    CHECK_FALSE(c.standard_typo_topics);
    CHECK(c.offline_buffer_bytes == 1000);
    CHECK(c.max_in_flight == 8);
    CHECK(c.dedup_window == std::chrono::milliseconds(500));
    CHECK(c.request_threads == 3);
    CHECK(c.driver_timeout == std::chrono::milliseconds(250));
    CHECK(c.register_retry_max == std::chrono::milliseconds(900));
    CHECK(c.heap_keep_bytes == 1048576);
    CHECK(c.log_level == LogLevel::debug);
    std::filesystem::remove_all(dir);
}

TEST_CASE("configuration mistakes are reported, not ignored") {
    auto unknown = adapter_config_from_json(Json{{"modle", "x.json"}});
    REQUIRE_FALSE(unknown.ok());
    CHECK(unknown.error().code == ErrorCode::keys_of_arguments);
    CHECK_THAT(unknown.error().message, Catch::Contains("modle"));
    auto nested = adapter_config_from_json(Json{{"broker", {{"uri", "tcp://x"}}}});
    REQUIRE_FALSE(nested.ok());
    CHECK_THAT(nested.error().message, Catch::Contains("broker.uri"));
    auto type = adapter_config_from_json(Json{{"strict", "yes"}});
    REQUIRE_FALSE(type.ok());
    CHECK(type.error().code == ErrorCode::value_type);
    CHECK_FALSE(adapter_config_from_json(Json{{"log_level", "loud"}}).ok());
    CHECK(adapter_config_from_json(Json{{"heap_keep_bytes", -1}}).error().code == ErrorCode::value_type);
    CHECK_FALSE(adapter_config_from_json(Json{{"broker", {{"mqtt_version", 3}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"broker", {{"mqtt_version", 0}}}}).ok());  // "auto" is spelt out
    CHECK_FALSE(adapter_config_from_json(Json{{"broker", {{"mqtt_version", "automatic"}}}}).ok());
    // A connection that could never be made, or a retry delay capped below its start.
    auto never = adapter_config_from_json(Json{{"broker", {{"connect_timeout_ms", 0}}}});
    REQUIRE_FALSE(never.ok());
    CHECK(never.error().message == "configuration: broker.connect_timeout_ms must be at least 1");
    CHECK_FALSE(adapter_config_from_json(Json{{"broker", {{"reconnect_min_ms", 0}}}}).ok());
    auto capped = adapter_config_from_json(Json{{"broker", {{"reconnect_min_ms", 5000}, {"reconnect_max_ms", 1000}}}});
    REQUIRE_FALSE(capped.ok());
    CHECK(capped.error().message == "configuration: broker.reconnect_max_ms must be at least reconnect_min_ms");
    CHECK(adapter_config_from_json(Json{{"broker", {{"reconnect_min_ms", 5000}, {"reconnect_max_ms", 5000}}}}).ok());
    // "auto": MQTT 5, or 3.1.1 where the broker refuses 5 (MqttOptions::mqtt_version 0).
    auto automatic = adapter_config_from_json(Json{{"broker", {{"mqtt_version", "auto"}}}});
    REQUIRE(automatic.ok());
    CHECK(automatic.value().mqtt_version == 0);
    CHECK_FALSE(adapter_config_from_json(Json::array()).ok());
    CHECK_FALSE(load_adapter_config("/nonexistent/adapter.json").ok());
}

TEST_CASE("a configuration named without a directory resolves its paths against the current one") {
    const auto dir = std::filesystem::temp_directory_path() / "nclink-config-bare-name";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "adapter.json") << R"({"model": "lathe.json", "driver": {"plugin": "./acme-lathe.so"},
                                               "persistence_dir": "state"})";
    const auto before = std::filesystem::current_path();
    std::filesystem::current_path(dir);
    auto loaded = load_adapter_config("adapter.json");
    std::filesystem::current_path(before);
    REQUIRE(loaded.ok());
    // Absolute, so dlopen() opens that file instead of searching the library path.
    const auto canonical = std::filesystem::canonical(dir);
    CHECK(loaded->driver_plugin == (canonical / "acme-lathe.so").string());
    CHECK(loaded->model_path == (canonical / "lathe.json").string());
    CHECK(loaded->persistence_dir == (canonical / "state").string());
    std::filesystem::remove_all(dir);
}

TEST_CASE("configuration errors say what was meant: nearest key, system reason, URL form") {
    auto typo = adapter_config_from_json(Json{{"broker", {{"uri", "tcp://x"}}}});
    REQUIRE_FALSE(typo.ok());
    CHECK_THAT(typo.error().message, Catch::StartsWith("configuration: broker.uri: unknown key; did you mean \"url\"?"));
    auto top = adapter_config_from_json(Json{{"modle", "x.json"}});
    REQUIRE_FALSE(top.ok());
    CHECK_THAT(top.error().message, Catch::Contains("did you mean \"model\"?"));
    auto far = adapter_config_from_json(Json{{"completely_unrelated", 1}});
    REQUIRE_FALSE(far.ok());
    CHECK_THAT(far.error().message, !Catch::Contains("did you mean"));

    auto missing = load_adapter_config("/nonexistent/adapter.json");
    REQUIRE_FALSE(missing.ok());
    CHECK(missing.error().message == "cannot read configuration file /nonexistent/adapter.json: No such file or directory");
}

TEST_CASE("code overrides a loaded configuration, defaults are documented values") {
    AdapterConfig base;
    CHECK(base.broker_url == "tcp://127.0.0.1:1883");
    CHECK(base.standard_typo_topics);
    CHECK(base.driver_timeout == std::chrono::milliseconds(1000));
    CHECK(base.heap_keep_bytes == std::size_t{32} << 20);
    base.strict = true;
    auto c = adapter_config_from_json(Json{{"model", "m.json"}}, base);
    REQUIRE(c.ok());
    CHECK(c->strict);
    CHECK(c->model_path == "m.json");
}

TEST_CASE("sampling qos channel_qos max_dtu_bytes and overrun_log_interval_ms are read and checked") {
    auto read = adapter_config_from_json(Json{
        {"sampling", {{"qos", 1}, {"channel_qos", {{"ch_fast", 0}}}, {"max_dtu_bytes", 65536}, {"overrun_log_interval_ms", 2500}}}});
    REQUIRE(read.ok());
    CHECK(read->sampling.qos == 1);
    CHECK(read->sampling.channel_qos.at("ch_fast") == 0);
    CHECK(read->sampling.max_dtu_bytes == 65536);
    CHECK(read->sampling.overrun_log_interval == std::chrono::milliseconds(2500));
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"qos", 2}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"channel_qos", {{"ch_fast", "1"}}}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"channel_qos", Json::array({1})}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"max_dtu_bytes", -1}}}}).ok());
    const AdapterConfig defaults;
    CHECK(defaults.sampling.qos == 1);
    CHECK(defaults.sampling.max_dtu_bytes == 1u << 20);
}

TEST_CASE("sampling slice_us is read and checked, default 100") {
    auto read = adapter_config_from_json(Json{{"sampling", {{"slice_us", 250}}}});
    REQUIRE(read.ok());
    CHECK(read->sampling.slice_us == 250);
    REQUIRE(adapter_config_from_json(Json{{"sampling", {{"slice_us", 0}}}}).ok());
    CHECK(adapter_config_from_json(Json{{"sampling", {{"slice_us", 0}}}})->sampling.slice_us == 0);
    // The kernel clamps a slice to 0.1..100 ms: outside that, say so instead.
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"slice_us", 99}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"slice_us", 100001}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"slice_us", -1}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"slice_us", "short"}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"slice_us", 150.5}}}}).ok());
    CHECK(AdapterConfig{}.sampling.slice_us == 100);
}

TEST_CASE("sampling ring_min_ms is read and checked, default 250") {
    auto read = adapter_config_from_json(Json{{"sampling", {{"ring_min_ms", 1000}}}});
    REQUIRE(read.ok());
    CHECK(read->sampling.ring_min_ms == 1000);
    REQUIRE(adapter_config_from_json(Json{{"sampling", {{"ring_min_ms", 0}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"ring_min_ms", -1}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"ring_min_ms", 3600001}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"sampling", {{"ring_min_ms", "long"}}}}).ok());
    CHECK(AdapterConfig{}.sampling.ring_min_ms == 250);
}

TEST_CASE("events qos is read and checked, default 1") {
    auto read = adapter_config_from_json(Json{{"events", {{"qos", 0}}}});
    REQUIRE(read.ok());
    CHECK(read->events.qos == 0);
    CHECK_FALSE(adapter_config_from_json(Json{{"events", {{"qos", 2}}}}).ok());
    CHECK_FALSE(adapter_config_from_json(Json{{"events", {{"qos", "1"}}}}).ok());
    CHECK(AdapterConfig{}.events.qos == 1);
}

TEST_CASE("the metrics section sets the HTTP limits of nclink-sim --metrics, and refuses unusable ones") {
    auto c = adapter_config_from_json(Json::parse(R"({"metrics": {"http_workers": 3, "http_header_timeout_ms": 700,
        "http_keep_alive_ms": 800, "http_write_timeout_ms": 900, "http_max_connections": 20,
        "http_max_connections_per_peer": 2}})"));
    INFO((c.ok() ? "" : c.error().describe()));
    REQUIRE(c.ok());
    CHECK(c->metrics.workers == 3);
    CHECK(c->metrics.header_timeout == std::chrono::milliseconds(700));
    CHECK(c->metrics.keep_alive == std::chrono::milliseconds(800));
    CHECK(c->metrics.write_timeout == std::chrono::milliseconds(900));
    CHECK(c->metrics.max_connections == 20);
    CHECK(c->metrics.max_connections_per_peer == 2);
    // The defaults are the bridge's, with two workers.
    const AdapterConfig d;
    CHECK(d.metrics.workers == 2);
    CHECK(d.metrics.header_timeout == std::chrono::milliseconds(3000));
    CHECK(d.metrics.max_connections_per_peer == 64);

    for (const char* bad :
         {R"({"metrics": {"http_workers": 0}})", R"({"metrics": {"http_max_connections": 0}})",
          R"({"metrics": {"http_header_timeout_ms": 5}})", R"({"metrics": {"http_max_streams": 2}})", R"({"metrics": 3})"}) {
        INFO(bad);
        auto r = adapter_config_from_json(Json::parse(bad));
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().message.find("metrics") != std::string::npos);
    }
}

TEST_CASE("the broker section's failover list is read, and a bad entry is named where it is in the file") {
    auto listed = adapter_config_from_json(
        Json{{"broker", {{"url", "tcp://broker-1.plant:1883"}, {"failover", {"broker-2.plant:1883", "mqtt://broker-3.plant"}}}}});
    INFO((listed.ok() ? "" : listed.error().describe()));
    REQUIRE(listed.ok());
    CHECK(listed->failover_urls == std::vector<std::string>{"broker-2.plant:1883", "mqtt://broker-3.plant"});
    CHECK(AdapterConfig{}.failover_urls.empty());  // default: no failover

    const auto dir = std::filesystem::temp_directory_path() / "nclink-config-failover";
    std::filesystem::create_directories(dir);
    const auto file = dir / "adapter.json";
    std::ofstream(file) << R"({
  "broker": {
    "url": "ssl://broker-1.plant:8883",
    "failover": ["broker-2.plant:8883",
                 "tcp://broker-3.plant:1883"]
  }
})";
    auto mixed = load_adapter_config(file.string());
    REQUIRE_FALSE(mixed.ok());
    CHECK(mixed.error().code == ErrorCode::value_type);
    CHECK(mixed.error().pointer == "/broker/failover/1");
    CHECK_THAT(mixed.error().message,
               Catch::StartsWith(file.string() + ":5:18: configuration: broker.failover[1]: 'tcp://broker-3.plant:1883' does "
                                                 "not use TLS and url 'ssl://broker-1.plant:8883' does"));
    std::filesystem::remove_all(dir);

    auto not_list = adapter_config_from_json(Json{{"broker", {{"failover", "tcp://b:1883"}}}});
    REQUIRE_FALSE(not_list.ok());
    CHECK(not_list.error().message == "configuration: broker.failover must be an array of broker URLs");
    CHECK(not_list.error().pointer == "/broker/failover");
    CHECK_FALSE(adapter_config_from_json(Json{{"broker", {{"failover", {1883}}}}}).ok());
    auto bad = adapter_config_from_json(Json{{"broker", {{"failover", {"b:1884", "b:x"}}}}});
    REQUIRE_FALSE(bad.ok());
    CHECK_THAT(bad.error().message, Catch::StartsWith("configuration: broker.failover[1]: unusable broker URL 'tcp://b:x'"));
    auto same = adapter_config_from_json(Json{{"broker", {{"failover", {"127.0.0.1:1883"}}}}});
    REQUIRE_FALSE(same.ok());
    CHECK_THAT(same.error().message, Catch::Contains("names the broker of url 'tcp://127.0.0.1:1883' again"));
}
