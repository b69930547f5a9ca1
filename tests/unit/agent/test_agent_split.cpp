// Several agent instances without $share ("instances"/"instance"):
// the split rule with fixed ids (a change of the hash is a change of the
// contract between instances of different builds, so it must fail here), and
// two agents on one loopback broker with plain subscriptions.
#include "unit/agent/agent_fixture.hpp"

#include "agent/access.hpp"
#include "agent/instance_split.hpp"

#include <thread>

using namespace nclink;
using namespace nclink::agent_detail;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

ParsedTopic topic_of(const std::string& topic) { return parse_topic(topic).value(); }

}  // namespace

TEST_CASE("instance split: FNV-1a 32 of the id's bytes") {
    // The published test vectors of FNV-1a 32.
    CHECK(fnv1a_32("") == 0x811c9dc5u);
    CHECK(fnv1a_32("a") == 0xe40c292cu);
    CHECK(fnv1a_32("foobar") == 0xbf9cf968u);
    CHECK(fnv1a_32("mill-1") == 0x030e7801u);
    // Bytes, not characters: the UTF-8 of a Chinese id, bytes above 0x7f taken unsigned.
    CHECK(fnv1a_32("\xe6\x9c\xba\xe5\xba\x8a-1") == 0xa3395524u);
}

TEST_CASE("instance split: fixed ids go to fixed instances") {
    struct Row {
        const char* id;
        unsigned of2, of3;
    };
    const Row rows[] = {{"mill-1", 1, 0},   {"mill-2", 0, 0}, {"mes-1", 0, 1},
                        {"test-dev", 1, 2}, {"t0", 1, 0},     {"\xe6\x9c\xba\xe5\xba\x8a-1", 0, 2}};
    for (const auto& row : rows) {
        INFO(row.id);
        CHECK(instance_of(row.id, 1) == 0);
        CHECK(instance_of(row.id, 2) == row.of2);
        CHECK(instance_of(row.id, 3) == row.of3);
    }
    CHECK(instance_of("mill-1", 0) == 0);  // never a division by zero
}

TEST_CASE("instance split: each request kind goes by the terminal the documentation names") {
    const unsigned n = 3;
    // Register/Request: by cli_uuid, from the payload; none readable: instance 0.
    CHECK(answering_instance(topic_of("Register/Request"), R"({"@id":"r","cli_uuid":"test-dev"})", n) == 2u);
    CHECK(answering_instance(topic_of("Register/Request"), R"({"@id":"r","cli_uuid":"mes-1"})", n) == 1u);
    CHECK(answering_instance(topic_of("Register/Request"), "not json", n) == 0u);
    CHECK(answering_instance(topic_of("Register/Request"), R"({"@id":"r","cli_uuid":7})", n) == 0u);
    CHECK(answering_instance(topic_of("Register/Request"), R"(["cli_uuid"])", n) == 0u);
    // Discovery: by the asking application.
    CHECK(answering_instance(topic_of("Discovery/Request/mes-1"), "{}", n) == 1u);
    // Probe/Version: by the adapter.
    CHECK(answering_instance(topic_of("Probe/Version/test-dev"), "{}", n) == 2u);
    // Requests to adapters: by dev (test-dev: 2), never by ex (mes-1: 1), with or without ex.
    CHECK(answering_instance(topic_of(topics::query_request("test-dev", "mes-1")), "{}", n) == 2u);
    CHECK(answering_instance(topic_of(topics::probe_query_request("test-dev")), "{}", n) == 2u);
    for (TopicKind kind : adapter_request_kinds()) {
        INFO(to_string(kind));
        const ParsedTopic request{kind, "test-dev", std::string("mes-1"), std::nullopt, Spelling::standard};
        CHECK(answering_instance(request, "{}", n) == 2u);
    }
    // What every instance handles alike: responses, states, samples, events.
    for (const std::string& watched :
         {topics::register_response("test-dev"), topics::notify_state("test-dev"), topics::probe_version_response("test-dev"),
          topics::query_response("test-dev", "mes-1"), topics::method_status("test-dev", "mes-1"), topics::event("test-dev"),
          topics::sample("test-dev", "ch1")}) {
        INFO(watched);
        CHECK_FALSE(answering_instance(topic_of(watched), "{}", n).has_value());
    }
}

TEST_CASE("instance split: every id belongs to exactly one of the instances") {
    for (unsigned n : {1u, 2u, 3u, 5u}) {
        std::vector<unsigned> per(n, 0);
        for (int i = 0; i < 200; ++i) {
            const std::string id = "line-" + std::to_string(i);
            const unsigned k = instance_of(id, n);
            REQUIRE(k < n);
            ++per[k];
        }
        for (unsigned k = 0; k < n; ++k) {
            INFO("instances " << n << ", instance " << k);
            CHECK(per[k] > 200 / n / 2);  // no instance starves on a numbered fleet
        }
    }
}

TEST_CASE("instance split: the combinations the agent refuses") {
    AgentConfig c;
    CHECK_FALSE(split_problem(c).has_value());  // 1 of 1 with the default share group: today's agent
    c.share_group = "";
    c.instances = 2;
    c.instance = 1;
    CHECK_FALSE(split_problem(c).has_value());
    c.instance = 2;
    REQUIRE(split_problem(c).has_value());
    CHECK(std::string(split_problem(c)->key) == "instance");
    c.instance = 0;
    c.instances = 0;
    REQUIRE(split_problem(c).has_value());
    CHECK(std::string(split_problem(c)->key) == "instances");
    c.instances = 2;
    c.share_group = "g";
    REQUIRE(split_problem(c).has_value());
    CHECK(std::string(split_problem(c)->key) == "instances");
    // An Agent built in code is refused at start, as the file would be.
    Agent agent(c);
    LoopbackBroker broker;
    agent.use_transport(make_loopback_transport(broker, LoopbackOptions{}));
    auto started = agent.start();
    REQUIRE_FALSE(started.ok());
    CHECK(started.error().code == ErrorCode::out_of_range);
    CHECK_THAT(started.error().message, Catch::Contains("share_group"));
}

namespace {

// Two agents, instance 0 and 1 of 2, on one loopback broker (plain
// subscriptions: it has no $share), an application side seeing everything.
struct SplitPair {
    explicit SplitPair(AgentConfig base = {}) {
        app = side("app");
        app->subscribe("#");
        base.share_group = "";
        base.instances = 2;
        for (unsigned k = 0; k < 2; ++k) {
            AgentConfig c = base;
            c.instance = k;
            agents[k] = std::make_unique<Agent>(c);
            LoopbackOptions o;
            o.client_id = "agent-" + std::to_string(k);
            agents[k]->use_transport(make_loopback_transport(broker, o));
            agents[k]->use_clock(clock);
            REQUIRE(agents[k]->start().ok());
            REQUIRE(eventually([&] { return agents[k]->stats().transport.connects >= 1; }));
        }
    }
    ~SplitPair() {
        for (auto& a : agents)
            if (a) a->stop(0ms);
    }
    std::unique_ptr<AppSide> side(const std::string& id) {
        LoopbackOptions o;
        o.client_id = id;
        return std::make_unique<AppSide>(make_loopback_transport(broker, o));
    }
    /// Sums a counter over both instances.
    template <class F>
    std::uint64_t both(F f) {
        return f(agents[0]->stats()) + f(agents[1]->stats());
    }

    LoopbackBroker broker;
    std::shared_ptr<ManualClock> clock = std::make_shared<ManualClock>();
    std::unique_ptr<AppSide> app;
    std::unique_ptr<Agent> agents[2];
};

}  // namespace

// mill-2 and mes-1 hash to instance 0, mill-1 and t0 to instance 1 (above).
TEST_CASE("two instances without $share: every request is answered once, by the instance of its terminal") {
    AgentConfig c;
    c.request_timeout = 1500ms;
    SplitPair f(c);
    for (const char* tid : {"mill-1", "mill-2"}) {
        f.app->send(topics::register_request(), Json{{"@id", std::string("r-") + tid}, {"cli_uuid", tid}}.dump());
        f.app->send(topics::probe_version(tid), Json{{"@id", std::string("v-") + tid}, {"guid", tid}, {"version", "1"}}.dump());
        f.app->send(topics::query_request(tid, "mes-1"), Json{{"@id", std::string("q-") + tid}, {"ids", {"pos"}}}.dump());
    }
    for (const char* ex : {"mes-1", "t0"})
        f.app->send(topics::discovery_request(ex), Json{{"@id", std::string("d-") + ex}, {"guid", ex}}.dump());
    // The queries wait for their adapters in their owners only.
    REQUIRE(eventually([&] { return f.agents[0]->stats().pending == 1 && f.agents[1]->stats().pending == 1; }));
    f.clock->advance(1500ms);  // both time out: 203 from the owner
    REQUIRE(eventually([&] { return f.both([](const AgentStats& s) { return s.timeouts; }) == 2; }));
    std::this_thread::sleep_for(100ms);  // room for a second answer to show up

    for (const char* tid : {"mill-1", "mill-2"}) {
        INFO(tid);
        CHECK(f.app->on(topics::register_response(tid)).size() == 1);
        CHECK(f.app->on(topics::probe_version_response(tid)).size() == 1);
        CHECK(f.app->on(topics::query_response(tid, "mes-1")).size() == 1);
    }
    for (const char* ex : {"mes-1", "t0"}) {
        INFO(ex);
        CHECK(f.app->on(topics::discovery_response(ex)).size() == 1);
    }
    for (unsigned k = 0; k < 2; ++k) {
        INFO("instance " << k);
        const AgentStats s = f.agents[k]->stats();
        CHECK(s.registrations == 1);
        CHECK(s.versions == 1);
        CHECK(s.discoveries == 1);
        CHECK(s.timeouts == 1);
    }
    // Each instance also learned the registration the other accepted.
    REQUIRE(eventually([&] {
        for (auto& agent : f.agents)
            for (const char* tid : {"mill-1", "mill-2"}) {
                const auto t = terminal(*agent, tid);
                if (!t || !t->registered) return false;
            }
        return true;
    }));
}

TEST_CASE("two instances without $share: a request of the other share is still its sender's sign of life") {
    AgentConfig c;
    c.application_liveness = 60000ms;
    SplitPair f(c);
    // mes-1's Discovery is instance 0's to answer; instance 1 sees mes-1 alive too.
    f.app->send(topics::discovery_request("mes-1"), Json{{"@id", "d"}, {"guid", "mes-1"}}.dump());
    REQUIRE(eventually([&] { return status_of(*f.agents[1], "mes-1") == "online"; }));
    CHECK(kind_of(*f.agents[1], "mes-1") == "application");
    CHECK(f.agents[1]->stats().discoveries == 0);
    // So it does not take mes-1 for gone while mes-1 only talks to instance 0.
    f.clock->advance(50000ms);
    f.app->send(topics::query_request("mill-2", "mes-1"), Json{{"@id", "q"}, {"ids", {"pos"}}}.dump());
    REQUIRE(eventually([&] { return f.agents[0]->stats().pending == 1; }));
    f.clock->advance(20000ms);
    std::this_thread::sleep_for(100ms);
    CHECK(status_of(*f.agents[1], "mes-1") == "online");
    CHECK(f.agents[1]->stats().pending == 0);  // not its request to watch
}

TEST_CASE("two instances without $share: an online terminal of unknown kind is asked once, by its instance") {
    SplitPair f;
    auto mill = f.side("mill-1");  // instance 1's
    mill->send(topics::notify_state("mill-1"), Json{{"tid", "mill-1"}, {"state", "online"}}.dump(), true);
    const std::string ask = topics::probe_query_request("mill-1", "nclink-agent");
    f.app->wait(ask);
    std::this_thread::sleep_for(100ms);  // room for a second question to show up
    CHECK(f.app->on(ask).size() == 1);
    // Its answer, watched by both, tells both that mill-1 is an adapter.
    mill->send(
        topics::probe_query_response("mill-1", "nclink-agent"),
        Json{{"@id", Json::parse(f.app->on(ask)[0].payload)["@id"]}, {"guid", "mill-1"}, {"code", "OK"}, {"probe", Json::object()}}
            .dump());
    REQUIRE(
        eventually([&] { return kind_of(*f.agents[0], "mill-1") == "adapter" && kind_of(*f.agents[1], "mill-1") == "adapter"; }));
}

TEST_CASE("two instances without $share: while one is down its share goes unanswered") {
    SplitPair f;
    f.agents[1]->stop(0ms);
    f.app->send(topics::register_request(), Json{{"@id", "r1"}, {"cli_uuid", "mill-1"}}.dump());  // instance 1's
    f.app->send(topics::register_request(), Json{{"@id", "r2"}, {"cli_uuid", "mill-2"}}.dump());  // instance 0's
    f.app->wait(topics::register_response("mill-2"));
    std::this_thread::sleep_for(200ms);
    CHECK(f.app->on(topics::register_response("mill-1")).empty());  // no takeover (docs/agent.md)
    CHECK(f.agents[0]->stats().registrations == 1);
}
