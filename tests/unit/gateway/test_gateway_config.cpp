// The gateway's one file: defaults laid under each machine, ids and GUIDs
// unique, typos refused, paths relative to the file.
#include <nclink/gateway.hpp>

#include <catch2/catch.hpp>

using namespace nclink;

TEST_CASE("gateway config: each machine is the defaults with its own keys over them") {
    const Json json = Json::parse(R"({
        "defaults": {"broker": {"url": "tcp://10.0.0.5:1883"}, "request_threads": 1, "model": "models/mill.json"},
        "machines": [
            {"id": "mill-1", "dev_uuid": "guid-1", "driver": {"config": {"seed": 7}}},
            {"dev_uuid": "guid-2", "model": "/abs/lathe.json", "broker": {"url": "tcp://10.0.0.6:1883"}}
        ],
        "start_threads": 8,
        "timer_threads": 3,
        "request_threads": 5,
        "driver_threads": 6,
        "work_threads": 7,
        "mqtt_connect_max": 16
    })");
    auto config = gateway_config_from_json(json, "/etc/nclink");
    REQUIRE(config.ok());
    REQUIRE(config->machines.size() == 2);
    const auto& a = config->machines[0];
    CHECK(a.id == "mill-1");
    CHECK(a.adapter.dev_uuid == "guid-1");
    CHECK(a.adapter.broker_url == "tcp://10.0.0.5:1883");
    CHECK(a.adapter.request_threads == 1);
    CHECK(a.adapter.model_path == "/etc/nclink/models/mill.json");
    CHECK(a.adapter.driver_config["seed"] == 7);
    const auto& b = config->machines[1];
    CHECK(b.id == "guid-2");  // no id: its GUID
    CHECK(b.adapter.model_path == "/abs/lathe.json");
    CHECK(b.adapter.broker_url == "tcp://10.0.0.6:1883");
    CHECK(config->start_threads == 8);
    CHECK(config->timer_threads == 3);
    CHECK(config->request_threads == 5);
    CHECK(config->driver_threads == 6);
    CHECK(config->work_threads == 7);
    CHECK(config->mqtt_connect_max == 16);
    // unset: sized to the box at start
    auto plain = gateway_config_from_json(Json::parse(R"({"machines": []})"));
    REQUIRE(plain.ok());
    CHECK(plain->timer_threads == 0);
    CHECK(plain->driver_threads == 0);
    CHECK(plain->work_threads == 0);
    CHECK(plain->mqtt_connect_max == 64);
    auto negative = gateway_config_from_json(Json::parse(R"({"machines": [], "driver_threads": -1})"));
    REQUIRE_FALSE(negative.ok());
    CHECK(negative.error().message.find("driver_threads") != std::string::npos);
}

TEST_CASE("gateway config: a GUID or an id listed twice is refused with 413") {
    auto twice_guid = gateway_config_from_json(Json::parse(
        R"({"machines": [{"id": "a", "dev_uuid": "g", "model": "m.json"}, {"id": "b", "dev_uuid": "g", "model": "m.json"}]})"));
    REQUIRE_FALSE(twice_guid.ok());
    CHECK(twice_guid.error().code == ErrorCode::keys_of_arguments);
    CHECK(twice_guid.error().message.find("machines[1]") != std::string::npos);
    auto twice_id = gateway_config_from_json(Json::parse(
        R"({"machines": [{"id": "a", "dev_uuid": "g1", "model": "m.json"}, {"id": "a", "dev_uuid": "g2", "model": "m.json"}]})"));
    REQUIRE_FALSE(twice_id.ok());
    CHECK(twice_id.error().code == ErrorCode::keys_of_arguments);
}

TEST_CASE("gateway config: unknown keys and wrong types are named") {
    auto typo_top = gateway_config_from_json(Json::parse(R"({"machine": []})"));
    REQUIRE_FALSE(typo_top.ok());
    CHECK(typo_top.error().message.find("machine") != std::string::npos);
    auto typo_machine = gateway_config_from_json(Json::parse(R"({"machines": [{"modle": "m.json"}]})"));
    REQUIRE_FALSE(typo_machine.ok());
    CHECK(typo_machine.error().message.find("machines[0]") != std::string::npos);
    CHECK(typo_machine.error().message.find("modle") != std::string::npos);
    auto typo_defaults = gateway_config_from_json(Json::parse(R"({"defaults": {"brokr": {}}, "machines": []})"));
    REQUIRE_FALSE(typo_defaults.ok());
    CHECK(typo_defaults.error().message.find("defaults") != std::string::npos);
    auto not_array = gateway_config_from_json(Json::parse(R"({"machines": {}})"));
    REQUIRE_FALSE(not_array.ok());
    CHECK(not_array.error().code == ErrorCode::value_type);
    CHECK_FALSE(gateway_config_from_json(Json::parse(R"({})")).ok());
}

TEST_CASE("gateway: a machine without a driver is refused and nothing is left reserved") {
    GatewayConfig config;
    Gateway gateway(config);  // no driver factory
    MachineConfig m;
    m.id = "x";
    m.adapter.model_path = "m.json";
    const auto refused = gateway.add_machine(m);
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().code == ErrorCode::parameter_missing);
    CHECK(gateway.machines().empty());
    CHECK_FALSE(gateway.remove_machine("x").ok());
}

TEST_CASE("gateway config: mqtt_client picks the machines' MQTT client and refuses anything else") {
    auto plain = gateway_config_from_json(Json::parse(R"({"machines": []})"));
    REQUIRE(plain.ok());
    CHECK(plain->mqtt_client == "mosquitto");  // one epoll thread for every machine's connection
    auto paho = gateway_config_from_json(Json::parse(R"({"machines": [], "mqtt_client": "paho"})"));
    REQUIRE(paho.ok());
    CHECK(paho->mqtt_client == "paho");
    auto other = gateway_config_from_json(Json::parse(R"({"machines": [], "mqtt_client": "hivemq"})"));
    REQUIRE_FALSE(other.ok());
    CHECK(other.error().code == ErrorCode::out_of_range);
    CHECK(other.error().message.find("mqtt_client") != std::string::npos);
    auto typed = gateway_config_from_json(Json::parse(R"({"machines": [], "mqtt_client": 1})"));
    REQUIRE_FALSE(typed.ok());
    CHECK(typed.error().code == ErrorCode::value_type);
}
