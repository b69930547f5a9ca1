// Topic builders, parser, mirror rule, typo spellings and subscriptions.
#include <nclink/topics.hpp>

#include <catch2/catch.hpp>

#include <algorithm>

using namespace nclink;

namespace {

ParsedTopic parsed(TopicKind kind, std::string dev, std::optional<std::string> ex = std::nullopt,
                   std::optional<std::string> channel = std::nullopt, Spelling spelling = Spelling::standard) {
    ParsedTopic p;
    p.kind = kind;
    p.dev = std::move(dev);
    p.ex = std::move(ex);
    p.channel = std::move(channel);
    p.spelling = spelling;
    return p;
}

void check_round_trip(const std::string& topic, const ParsedTopic& expected) {
    INFO(topic);
    const auto p = parse_topic(topic);
    REQUIRE(p);
    CHECK(*p == expected);
    CHECK(build_topic(*p) == topic);
    CHECK(topic_kind(topic) == expected.kind);  // the copy-free classification agrees
}

}  // namespace

TEST_CASE("every topic of the docs/wire.md table builds and parses") {
    using K = TopicKind;
    check_round_trip(topics::register_request(), parsed(K::register_request, ""));
    check_round_trip(topics::register_response("dev"), parsed(K::register_response, "dev"));
    check_round_trip(topics::discovery_request("ex"), parsed(K::discovery_request, "", "ex"));
    check_round_trip(topics::discovery_response("ex"), parsed(K::discovery_response, "", "ex"));
    check_round_trip(topics::probe_version("dev"), parsed(K::probe_version, "dev"));
    check_round_trip(topics::notify_state("dev"), parsed(K::notify_state, "dev"));
    check_round_trip(topics::sample("dev", "cn1"), parsed(K::sample, "dev", std::nullopt, "cn1"));
    check_round_trip(topics::dynamic_sample("dev", "ex", "cn1"), parsed(K::dynamic_sample, "dev", "ex", "cn1"));

    CHECK(topics::register_request() == "Register/Request");
    CHECK(topics::register_response("d") == "Register/Response/d");
    CHECK(topics::discovery_request("e") == "Discovery/Request/e");
    CHECK(topics::probe_version("d") == "Probe/Version/d");
    CHECK(topics::probe_version_response("d") == "Probe/Version/Response/d");
    CHECK(topics::probe_query_request("d", "e") == "Probe/Query/Request/d/e");
    CHECK(topics::probe_set_response("d") == "Probe/Set/Response/d");
    CHECK(topics::query_request("d") == "Query/Request/d");
    CHECK(topics::query_response("d", "e") == "Query/Response/d/e");
    CHECK(topics::set_request("d", "e") == "Set/Request/d/e");
    CHECK(topics::sample("d", "c") == "Sample/d/c");
    CHECK(topics::dynamic_sample("d", "e", "c") == "Sample/d/e/c");
    CHECK(topics::notify_state("t") == "Notify/State/t");
    CHECK(topics::sample_register_request("d", "e") == "Register/Sample/Request/d/e");
    CHECK(topics::sample_register_response("d", "e", Spelling::typo) == "Reigster/Sample/Response/d/e");
    CHECK(topics::sample_unregister_response("d", "e", Spelling::typo) == "Unreigster/Sample/Response/d/e");
    CHECK(topics::method_call("d", "e") == "Method/Call/d/e");
    CHECK(topics::method_status("d", "e") == "Method/Status/d/e");
    CHECK(topics::method_result("d", "e") == "Method/Result/d/e");
    CHECK(topics::method_control_request("d") == "Method/Control/Request/d");
    CHECK(topics::method_control_response("d", "e") == "Method/Control/Response/d/e");
    CHECK(topics::event_register_response("d", "e") == "Register/Event/Response/d/e");
    CHECK(topics::event_unregister_request("d") == "Unregister/Event/Request/d");
    CHECK(topics::event("d", "e") == "Event/d/e");

    // The {dev}[/{ex}] kinds, with and without ex, in both spellings where they exist.
    for (K kind : {K::probe_version_response,
                   K::probe_query_request,
                   K::probe_query_response,
                   K::probe_set_request,
                   K::probe_set_response,
                   K::query_request,
                   K::query_response,
                   K::set_request,
                   K::set_response,
                   K::sample_register_request,
                   K::sample_register_response,
                   K::sample_unregister_request,
                   K::sample_unregister_response,
                   K::method_call,
                   K::method_status,
                   K::method_result,
                   K::method_control_request,
                   K::method_control_response,
                   K::event_register_request,
                   K::event_register_response,
                   K::event_unregister_request,
                   K::event_unregister_response,
                   K::event}) {
        INFO(to_string(kind));
        for (const auto& ex : {std::optional<std::string>(), std::optional<std::string>("ex_cid")}) {
            check_round_trip(build_topic(parsed(kind, "dev_uuid", ex)), parsed(kind, "dev_uuid", ex));
            if (has_typo_spelling(kind)) {
                const auto typo = parsed(kind, "dev_uuid", ex, std::nullopt, Spelling::typo);
                const std::string topic = build_topic(typo);
                CHECK((topic.rfind("Reigster/", 0) == 0 || topic.rfind("Unreigster/", 0) == 0));
                check_round_trip(topic, typo);
            }
        }
    }
}

TEST_CASE("both spellings parse to the same command and report the spelling") {
    auto standard = parse_topic("Unregister/Event/Request/dev/ex");
    auto typo = parse_topic("Unreigster/Event/Request/dev/ex");
    REQUIRE(standard);
    REQUIRE(typo);
    CHECK(standard->kind == TopicKind::event_unregister_request);
    CHECK(typo->kind == TopicKind::event_unregister_request);
    CHECK(standard->spelling == Spelling::standard);
    CHECK(typo->spelling == Spelling::typo);
    CHECK(parse_topic("Reigster/Sample/Response/dev")->kind == TopicKind::sample_register_response);
}

TEST_CASE("mirror rule: the response mirrors the request's shape") {
    CHECK(response_topic("Query/Request/dev/ex") == std::string("Query/Response/dev/ex"));
    CHECK(response_topic("Query/Request/dev") == std::string("Query/Response/dev"));
    CHECK(response_topic("Set/Request/dev/ex") == std::string("Set/Response/dev/ex"));
    CHECK(response_topic("Probe/Query/Request/dev") == std::string("Probe/Query/Response/dev"));
    CHECK(response_topic("Probe/Set/Request/dev/ex") == std::string("Probe/Set/Response/dev/ex"));
    CHECK(response_topic("Probe/Version/dev") == std::string("Probe/Version/Response/dev"));
    CHECK(response_topic("Method/Call/dev/ex") == std::string("Method/Result/dev/ex"));
    CHECK(response_topic("Method/Control/Request/dev/ex") == std::string("Method/Control/Response/dev/ex"));
    CHECK(response_topic("Discovery/Request/ex") == std::string("Discovery/Response/ex"));
    CHECK(response_topic("Reigster/Event/Request/dev/ex") == std::string("Register/Event/Response/dev/ex"));
    CHECK_FALSE(response_topic("Register/Request"));  // needs the payload's cli_uuid
    CHECK_FALSE(response_topic("Query/Response/dev/ex"));
    CHECK_FALSE(response_topic("Sample/dev/cn1"));
    CHECK_FALSE(response_topic("not a topic"));
}

TEST_CASE("response_topics adds the standard's literal typo spelling when asked") {
    using V = std::vector<std::string>;
    CHECK(response_topics("Register/Sample/Request/dev/ex") ==
          V{"Register/Sample/Response/dev/ex", "Reigster/Sample/Response/dev/ex"});
    CHECK(response_topics("Unregister/Sample/Request/dev") ==
          V{"Unregister/Sample/Response/dev", "Unreigster/Sample/Response/dev"});
    CHECK(response_topics("Reigster/Event/Request/dev/ex") ==
          V{"Register/Event/Response/dev/ex", "Reigster/Event/Response/dev/ex"});
    CHECK(response_topics("Unregister/Event/Request/dev/ex") ==
          V{"Unregister/Event/Response/dev/ex", "Unreigster/Event/Response/dev/ex"});
    CHECK(response_topics("Register/Event/Request/dev/ex", false) == V{"Register/Event/Response/dev/ex"});
    CHECK(response_topics("Query/Request/dev/ex") == V{"Query/Response/dev/ex"});
    CHECK(response_topics("Query/Response/dev/ex").empty());
}

TEST_CASE("malformed topics are rejected") {
    for (const char* topic : {"",
                              "/",
                              "Query",
                              "Query/Request",
                              "Query/Request/",
                              "/Query/Request/dev",
                              "Query/Request//ex",
                              "Query/Request/dev/ex/",
                              "Query/Request/dev/ex/more",
                              "Query/Reqest/dev",
                              "query/request/dev",
                              "Querry/Request/dev",
                              "Query/Request/+",
                              "Query/Request/dev/#",
                              "Register/Request/dev",
                              "Register/Response",
                              "Register/Response/a/b",
                              "Discovery/Request",
                              "Discovery/Request/a/b",
                              "Sample/dev",
                              "Sample/dev/a/b/c",
                              "Notify/State",
                              "Notify/State/a/b",
                              "Method/Call",
                              "Method/Control/dev",
                              "Probe/Version",
                              "Probe/Version/a/b/c/d",
                              "Event",
                              "Event/d/e/f",
                              "Regster/Sample/Request/dev",
                              "Register/Sample/Request",
                              "Unknown/Request/dev"}) {
        INFO(topic);
        CHECK_FALSE(parse_topic(topic));
        CHECK_FALSE(topic_kind(topic));
    }
    CHECK_FALSE(parse_topic(std::string_view("Query/Request/d\0v", 17)));
    CHECK_FALSE(topic_kind(std::string_view("Query/Request/d\0v", 17)));
}

TEST_CASE("adapter subscriptions cover every request it serves, both spellings") {
    const auto subs = topics::adapter_subscriptions("dev");
    auto has = [&](const std::string& f) { return std::find(subs.begin(), subs.end(), f) != subs.end(); };
    CHECK(has("Register/Response/dev"));
    CHECK(has("Probe/Version/Response/dev"));
    CHECK(has("Probe/Version/Response/dev/+"));
    CHECK(has("Query/Request/dev"));
    CHECK(has("Query/Request/dev/+"));
    CHECK(has("Reigster/Sample/Request/dev/+"));
    CHECK(has("Unreigster/Event/Request/dev"));
    CHECK(has("Method/Control/Request/dev/+"));
    // Every request topic an application may use reaches the adapter, and
    // no filter of one adapter matches another adapter's topics.
    for (const std::string topic :
         {"Query/Request/dev", "Query/Request/dev/ex", "Set/Request/dev/ex", "Probe/Query/Request/dev/ex",
          "Probe/Set/Request/dev", "Register/Sample/Request/dev/ex", "Reigster/Sample/Request/dev/ex",
          "Unregister/Sample/Request/dev", "Unreigster/Sample/Request/dev/ex", "Register/Event/Request/dev/ex",
          "Reigster/Event/Request/dev", "Unregister/Event/Request/dev/ex", "Unreigster/Event/Request/dev/ex",
          "Method/Call/dev/ex", "Method/Control/Request/dev/ex", "Register/Response/dev", "Probe/Version/Response/dev/ex"}) {
        INFO(topic);
        CHECK(std::any_of(subs.begin(), subs.end(), [&](const std::string& f) { return topic_matches(f, topic); }));
        std::string other = topic;
        other.replace(other.find("dev"), 3, "dev2");
        CHECK_FALSE(std::any_of(subs.begin(), subs.end(), [&](const std::string& f) { return topic_matches(f, other); }));
    }
}

TEST_CASE("topic filter matching") {
    CHECK(topic_matches("a/b", "a/b"));
    CHECK(topic_matches("a/+", "a/b"));
    CHECK_FALSE(topic_matches("a/+", "a/b/c"));
    CHECK_FALSE(topic_matches("a/+", "a"));
    CHECK(topic_matches("a/#", "a/b/c"));
    CHECK(topic_matches("a/#", "a"));
    CHECK(topic_matches("#", "a/b"));
    CHECK_FALSE(topic_matches("a/b", "a/b/c"));
    CHECK_FALSE(topic_matches("a/b/c", "a/b"));
    CHECK(topic_matches("+/+", "a/b"));
    CHECK_FALSE(topic_matches("a/b", "a/c"));
}
