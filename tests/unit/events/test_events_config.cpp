// The "events" section of the adapter configuration (src/events/events_config.cpp).
#include <nclink/adapter_config.hpp>

#include <catch2/catch.hpp>

using namespace nclink;

TEST_CASE("events config: defaults and every key") {
    const EventsConfig defaults;
    CHECK(defaults.max_events == 64);
    CHECK(defaults.poll_interval == std::chrono::milliseconds(100));
    CHECK(defaults.max_queued_values == 65536);

    auto config =
        adapter_config_from_json(Json::parse(R"({"events":{"max_events":3,"poll_interval_ms":0,"max_queued_values":10}})"));
    REQUIRE(config.ok());
    CHECK(config->events.max_events == 3);
    CHECK(config->events.poll_interval == std::chrono::milliseconds(0));
    CHECK(config->events.max_queued_values == 10);
}

TEST_CASE("events config: unknown keys wrong types and zero queue are refused") {
    auto unknown = adapter_config_from_json(Json::parse(R"({"events":{"max_event":3}})"));
    REQUIRE_FALSE(unknown.ok());
    CHECK(unknown.error().code == ErrorCode::keys_of_arguments);
    CHECK(unknown.error().message.find("events.max_event") != std::string::npos);
    auto type = adapter_config_from_json(Json::parse(R"({"events":{"poll_interval_ms":"fast"}})"));
    REQUIRE_FALSE(type.ok());
    CHECK(type.error().code == ErrorCode::value_type);
    auto negative = adapter_config_from_json(Json::parse(R"({"events":{"max_events":-1}})"));
    REQUIRE_FALSE(negative.ok());
    auto zero = adapter_config_from_json(Json::parse(R"({"events":{"max_queued_values":0}})"));
    REQUIRE_FALSE(zero.ok());
    CHECK(zero.error().code == ErrorCode::out_of_range);
    auto not_object = adapter_config_from_json(Json::parse(R"({"events":[]})"));
    REQUIRE_FALSE(not_object.ok());
}
