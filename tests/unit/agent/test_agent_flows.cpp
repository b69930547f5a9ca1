// The agent's DTU flows over the loopback broker, on a manual clock.
#include "unit/agent/agent_fixture.hpp"

#include <fstream>
#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

// An adapter that answers nothing but announces itself like ours does.
struct QuietAdapter {
    QuietAdapter(AgentFixture& f, const std::string& dev) : side(f.peer(dev, offline_will(dev))) {
        f.announce(*side, dev);
        side->send(topics::probe_version(dev), Json{{"@id", "v1"}, {"guid", dev}, {"version", "1.0.0"}}.dump());
    }
    std::unique_ptr<AppSide> side;
};

bool is_agent_answer(const Json& j) { return j.contains("privateInfo") && j["privateInfo"].contains("agent"); }

}  // namespace

TEST_CASE("register: a valid terminal is accepted on Register/Response/cli_uuid") {
    AgentFixture f;
    const Json answer = f.register_as(*f.app, "mill-1", "r1");
    CHECK(answer["@id"] == "r1");
    CHECK(answer["cli_uuid"] == "mill-1");
    CHECK(answer["code"] == "OK");
    CHECK(f.agent->stats().registrations == 1);
    REQUIRE(terminal(*f.agent, "mill-1"));
    CHECK(terminal(*f.agent, "mill-1")->registered);
}

TEST_CASE("register: a resend answered moments ago waits for its first answer, one 30 s later is answered again") {
    AgentFixture f;
    CHECK(f.register_as(*f.app, "mill-1", "r1")["code"] == "OK");
    // The same request again: its sender heard nothing within its timeout
    // while the answer was queued. The first answer is on its way.
    f.app->send(topics::register_request(), Json{{"@id", "r1"}, {"cli_uuid", "mill-1"}}.dump());
    REQUIRE(eventually([&] { return f.agent->stats().registrations_repeated == 1; }));
    CHECK(f.app->on(topics::register_response("mill-1")).size() == 1);
    CHECK(f.agent->stats().registrations == 1);
    // Half a minute on, a resend may mean the answer was lost: answered again.
    f.advance(std::chrono::seconds(30));
    CHECK(f.register_as(*f.app, "mill-1", "r1")["code"] == "OK");
    CHECK(f.agent->stats().registrations == 2);
    // A new request (another @id) is answered at once.
    CHECK(f.register_as(*f.app, "mill-1", "r2")["code"] == "OK");
    CHECK(f.agent->stats().registrations_repeated == 1);
}

TEST_CASE("register: an unsupported terminal identifier gets 414") {
    AgentFixture f;
    const Json answer = f.register_as(*f.app, "bad id", "r1");
    CHECK(answer["code"] == "NG");
    CHECK(answer["error"] == 414);
    CHECK(answer["reason"] == "unsupported terminal identifier");
    CHECK(f.agent->stats().registrations_refused == 1);
}

TEST_CASE("register: a malformed request with a cli_uuid is answered NG") {
    AgentFixture f;
    const Json answer = f.app_wait_after(*f.app, topics::register_request(), topics::register_response("x"),
                                         Json{{"@id", {{"not", "a scalar"}}}, {"cli_uuid", "x"}});
    CHECK(answer["code"] == "NG");
    CHECK(answer["cli_uuid"] == "x");
    CHECK(f.agent->stats().malformed == 1);
}

TEST_CASE("register: allowlist and credentials give 301 Permission Denied") {
    AgentConfig c;
    c.registration.open = false;
    c.registration.terminals["mes"] = TerminalEntry{"application", "pw"};
    AgentFixture f(c);
    CHECK(f.register_as(*f.app, "stranger", "1")["error"] == 301);
    const Json wrong = f.register_as(*f.app, "mes", "2", Json{{"password", "nope"}});
    CHECK(wrong["reason"] == "Permission Denied");
    CHECK(f.register_as(*f.app, "mes", "3", Json{{"password", "pw"}})["code"] == "OK");
}

TEST_CASE("register: one live registration per adapter id") {
    AgentFixture f;
    QuietAdapter first(f, "mill-1");
    REQUIRE(eventually([&] { return kind_of(*f.agent, "mill-1") == "adapter"; }));
    CHECK(f.register_as(*first.side, "mill-1", "a")["code"] == "OK");
    // a second process claiming the same id while the first is online
    auto second = f.peer("impostor");
    f.announce(*second, "mill-1");
    const Json refused = f.register_as(*second, "mill-1", "b");
    CHECK(refused["error"] == 301);
    // the first one's connection ends (last will): the id is free again
    REQUIRE(f.broker.drop_client("mill-1"));
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "offline"; }));
    f.announce(*second, "mill-1");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "online"; }));
    CHECK(f.register_as(*second, "mill-1", "c")["code"] == "OK");
}

TEST_CASE("discovery: registered adapters the application may access with status and last alive time") {
    AgentConfig c;
    c.access.applications["viewer"]["mill-1"] = access_read;
    AgentFixture f(c);
    QuietAdapter a(f, "mill-1");
    QuietAdapter b(f, "mill-2");
    f.register_as(*a.side, "mill-1", "r1");
    f.register_as(*b.side, "mill-2", "r2");
    f.register_as(*f.app, "some-app", "r3");  // applications are not listed
    REQUIRE(eventually([&] { return kind_of(*f.agent, "mill-2") == "adapter"; }));

    const Json all = f.app_wait_after(*f.app, topics::discovery_request("anyone"), topics::discovery_response("anyone"),
                                      Json{{"@id", "d1"}, {"guid", "anyone"}});
    CHECK(all["code"] == "OK");
    CHECK(all["guid"] == "anyone");
    REQUIRE(all["deviceList"].size() == 2);
    CHECK(all["deviceList"][0]["guid"] == "mill-1");
    CHECK(all["deviceList"][0]["status"] == "online");
    CHECK(all["deviceList"][0]["lastAliveTimeStamp"] == std::to_string(f.clock->wall_ms() / 1000));

    const Json limited = f.app_wait_after(*f.app, topics::discovery_request("viewer"), topics::discovery_response("viewer"),
                                          Json{{"@id", "d2"}, {"guid", "viewer"}});
    REQUIRE(limited["deviceList"].size() == 1);
    CHECK(limited["deviceList"][0]["guid"] == "mill-1");
}

TEST_CASE("discovery: nothing accessible is deviceList null") {
    AgentConfig c;
    c.access.default_rights = access_none;
    AgentFixture f(c);
    QuietAdapter a(f, "mill-1");
    f.register_as(*a.side, "mill-1", "r1");
    const Json none = f.app_wait_after(*f.app, topics::discovery_request("x"), topics::discovery_response("x"),
                                       Json{{"@id", "d"}, {"guid", "x"}});
    CHECK(none["code"] == "OK");
    CHECK(none["deviceList"].is_null());
}

TEST_CASE("discovery: on a link of its own it is asked and answered there, and the main link leaves it alone") {
    // Two loopback brokers stand for the agent's two connections, so what
    // travels on which is seen apart. The second outlives the fixture, which
    // stops the agent.
    LoopbackBroker second;
    AgentFixture f({}, false);
    f.agent = std::make_unique<Agent>(f.config);
    LoopbackOptions main_link, discovery_link;
    main_link.client_id = "agent-main";
    discovery_link.client_id = "agent-main-discovery";
    f.agent->use_transport(make_loopback_transport(f.broker, main_link));
    f.agent->use_discovery_transport(make_loopback_transport(second, discovery_link));
    f.agent->use_clock(f.clock);
    REQUIRE(f.agent->start().ok());
    LoopbackOptions o;
    o.client_id = "mes";
    AppSide mes(make_loopback_transport(second, o));
    mes.subscribe("#");

    QuietAdapter a(f, "mill-1");
    f.register_as(*a.side, "mill-1", "r1");
    // Asked on the Discovery link: answered there, from what the main link brought.
    const Json listed =
        mes.request(topics::discovery_request("mes"), topics::discovery_response("mes"), Json{{"@id", "d1"}, {"guid", "mes"}});
    CHECK(listed["@id"] == "d1");
    REQUIRE(listed["deviceList"].size() == 1);
    CHECK(listed["deviceList"][0]["guid"] == "mill-1");
    CHECK(f.app->on(topics::discovery_response("mes")).empty());  // not on the main link
    // A malformed request gets its answer on the same link.
    mes.send(topics::discovery_request("mes"), Json{{"@id", "d-bad"}, {"guid", 7}}.dump());
    CHECK(mes.wait(topics::discovery_response("mes"), 2)["code"] == "NG");
    // The main link no longer hears Discovery: asked there, nothing answers,
    // while the next request on it still is (so the first was read and passed over).
    f.app->send(topics::discovery_request("other"), Json{{"@id", "d2"}, {"guid", "other"}}.dump());
    CHECK(f.register_as(*f.app, "mill-2", "r2")["code"] == "OK");
    CHECK(f.app->on(topics::discovery_response("other")).empty());
    CHECK(f.agent->stats().discoveries == 1);
    // The Discovery link carries Discovery only: the announcements and
    // registration answers stay on the main link.
    for (const auto& m : mes.inbox) CHECK(m.topic.rfind("Discovery/", 0) == 0);
}

TEST_CASE("notify: the adapter's retained state and last will set its status") {
    AgentFixture f;
    QuietAdapter a(f, "mill-1");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "online"; }));
    REQUIRE(f.broker.drop_client("mill-1"));  // abnormal disconnect: the will says offline
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "offline"; }));
}

TEST_CASE("notify: no DTU for the liveness time is offline and announced retained") {
    AgentConfig c;
    c.adapter_liveness = 5000ms;
    AgentFixture f(c);
    QuietAdapter a(f, "mill-1");
    REQUIRE(eventually([&] { return kind_of(*f.agent, "mill-1") == "adapter"; }));
    f.advance(4000ms);
    a.side->send(topics::sample("mill-1", "ch"), R"({"id":"ch","beginTime":"1","data":[]})");  // a sign of life
    std::this_thread::sleep_for(100ms);
    f.advance(4000ms);
    std::this_thread::sleep_for(100ms);
    CHECK(terminal(*f.agent, "mill-1")->status == "online");
    // Its liveness runs out: asked first (a Probe/Query), still online while
    // the answer may come (request_timeout), then offline.
    const auto asked = f.app->on(topics::probe_query_request("mill-1", "nclink-agent")).size();
    f.advance(1001ms);
    REQUIRE(eventually([&] { return f.app->on(topics::probe_query_request("mill-1", "nclink-agent")).size() == asked + 1; }));
    CHECK(status_of(*f.agent, "mill-1") == "online");
    f.advance(c.request_timeout);
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "offline"; }));
    REQUIRE(eventually([&] {
        const auto seen = f.app->on(topics::notify_state("mill-1"));
        const auto kept = f.broker.retained(topics::notify_state("mill-1"));
        return Json::parse(seen.back().payload) == Json{{"tid", "mill-1"}, {"state", "offline"}} && kept &&
               Json::parse(kept->payload)["state"] == "offline";
    }));
    // it speaks again: online, announced once its own Notify/State has not
    // come within the grace (a Sample DTU may overtake it)
    a.side->send(topics::sample("mill-1", "ch"), R"({"id":"ch","beginTime":"1","data":[]})");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "online"; }));
    f.advance(30s);
    REQUIRE(eventually([&] {
        const auto r = f.broker.retained(topics::notify_state("mill-1"));
        return r && r->payload.find("online") != std::string::npos;
    }));
}

// mosquitto hands a QoS 0 Sample DTU to the agent at once while the
// machine's QoS 1 Notify/State may wait behind thousands of messages.
TEST_CASE("notify: a Sample DTU makes an adapter online at once, announced only if it does not say so itself") {
    AgentFixture f;
    auto side = f.peer("mill-1");
    auto other = f.peer("mill-2");
    const auto online_states = [&](const std::string& tid) {  // whoever said it
        std::size_t n = 0;
        for (const auto& m : f.app->on(topics::notify_state(tid)))
            if (Json::parse(m.payload)["state"] == "online") ++n;
        return n;
    };
    side->send(topics::sample("mill-1", "ch"), R"({"id":"ch","beginTime":"1","data":[]})");
    other->send(topics::sample("mill-2", "ch"), R"({"id":"ch","beginTime":"1","data":[]})");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "online" && status_of(*f.agent, "mill-2") == "online"; }));
    CHECK(kind_of(*f.agent, "mill-1") == "adapter");
    f.advance(10s);
    f.announce(*side, "mill-1");  // its own state, late
    REQUIRE(eventually([&] { return online_states("mill-1") == 1; }));
    f.advance(19s);
    std::this_thread::sleep_for(100ms);
    CHECK(online_states("mill-2") == 0);  // not yet
    f.advance(1s);                        // 30 s after its Sample DTU: mill-2 never said it
    REQUIRE(eventually([&] { return online_states("mill-2") == 1; }));
    REQUIRE(eventually([&] {
        const auto kept = f.broker.retained(topics::notify_state("mill-2"));
        return kept && Json::parse(kept->payload)["state"] == "online";
    }));
    f.advance(60s);
    std::this_thread::sleep_for(100ms);
    CHECK(online_states("mill-1") == 1);  // only its own
    CHECK(online_states("mill-2") == 1);
}

TEST_CASE("notify: an application that goes silent is announced offline") {
    AgentConfig c;
    c.application_liveness = 60000ms;
    AgentFixture f(c);
    f.app->send(topics::discovery_request("mes"), Json{{"@id", "d"}, {"guid", "mes"}}.dump());
    REQUIRE(eventually([&] { return status_of(*f.agent, "mes") == "online"; }));
    REQUIRE(eventually([&] { return f.broker.retained(topics::notify_state("mes")).has_value(); }));
    f.advance(60000ms);
    REQUIRE(eventually([&] { return status_of(*f.agent, "mes") == "offline"; }));
    REQUIRE(eventually([&] {
        const auto r = f.broker.retained(topics::notify_state("mes"));
        return r && r->payload.find("offline") != std::string::npos;
    }));
}

TEST_CASE("version: answered and the model fetched and served from the cache while the adapter is offline") {
    AgentConfig c;
    c.state_dir = scratch_dir("agent-state");
    AgentFixture f(c);
    AdapterConfig ac;
    ac.model_path = test_model_path();
    ac.register_timeout = 200ms;
    Adapter adapter(ac, std::make_shared<FakeDriver>());
    LoopbackOptions o;
    o.client_id = "adapter";
    o.last_will = offline_will("test-dev");
    adapter.use_transport(make_loopback_transport(f.broker, o));
    REQUIRE(adapter.start().ok());

    const Json ack = f.app->wait(topics::probe_version_response("test-dev"));
    CHECK(ack["code"] == "OK");
    CHECK(ack["version"] == "1.0.0");
    CHECK(ack["guid"] == "test-dev");
    REQUIRE(eventually([&] { return f.agent->cached_model("test-dev").has_value(); }));
    CHECK(f.app->on(topics::probe_query_request("test-dev", "nclink-agent")).size() == 1);
    CHECK(eventually([&] { return adapter.stats().registered; }));

    adapter.stop();
    REQUIRE(eventually([&] { return status_of(*f.agent, "test-dev") == "offline"; }));
    const Json cached =
        f.app_wait_after(*f.app, topics::probe_query_request("test-dev", "app"), topics::probe_query_response("test-dev", "app"),
                         Json{{"@id", "p1"}, {"guid", "test-dev"}});
    CHECK(cached["code"] == "OK");
    CHECK(cached["@id"] == "p1");
    CHECK(cached["probe"]["devices"][0]["guid"] == "test-dev");
    CHECK(cached["privateInfo"]["cached"] == true);
    CHECK(cached["privateInfo"]["version"] == "1.0.0");
    CHECK(f.agent->stats().cached_probes == 1);

    // ... and after an agent restart, from the state directory
    f.restart_agent();
    REQUIRE(eventually([&] { return status_of(*f.agent, "test-dev") == "offline"; }));
    CHECK(terminal(*f.agent, "test-dev")->registered);
    const Json again =
        f.app_wait_after(*f.app, topics::probe_query_request("test-dev", "app"), topics::probe_query_response("test-dev", "app"),
                         Json{{"@id", "p2"}, {"guid", "test-dev"}});
    CHECK(again["privateInfo"]["cached"] == true);
    const Json listed = f.app_wait_after(*f.app, topics::discovery_request("app"), topics::discovery_response("app"),
                                         Json{{"@id", "d"}, {"guid", "app"}});
    REQUIRE(listed["deviceList"].size() == 1);
    CHECK(listed["deviceList"][0]["status"] == "offline");
}

TEST_CASE("version: a new version makes the agent fetch the model again") {
    AgentFixture f;
    QuietAdapter a(f, "mill-1");
    REQUIRE(eventually([&] { return f.app->on(topics::probe_query_request("mill-1", "nclink-agent")).size() == 1; }));
    const Json fetch = f.app->wait(topics::probe_query_request("mill-1", "nclink-agent"));
    a.side->send(topics::probe_query_response("mill-1", "nclink-agent"),
                 Json{{"@id", fetch["@id"]}, {"guid", "mill-1"}, {"code", "OK"}, {"probe", {{"version", "1.0.0"}}}}.dump());
    REQUIRE(eventually([&] { return f.agent->cached_model("mill-1").has_value(); }));
    a.side->send(topics::probe_version("mill-1"), Json{{"@id", "v1"}, {"guid", "mill-1"}, {"version", "1.0.0"}}.dump());
    std::this_thread::sleep_for(100ms);
    CHECK(f.app->on(topics::probe_query_request("mill-1", "nclink-agent")).size() == 1);  // same version: no fetch
    a.side->send(topics::probe_version("mill-1"), Json{{"@id", "v2"}, {"guid", "mill-1"}, {"version", "1.1.0"}}.dump());
    REQUIRE(eventually([&] { return f.app->on(topics::probe_query_request("mill-1", "nclink-agent")).size() == 2; }));
}

TEST_CASE("version: a malformed Probe/Version is answered NG") {
    AgentFixture f;
    const Json answer = f.app_wait_after(*f.app, topics::probe_version("mill-1"), topics::probe_version_response("mill-1"),
                                         Json{{"@id", "v"}, {"guid", "mill-1"}});
    CHECK(answer["code"] == "NG");
    CHECK(answer["error"] == 102);
}

TEST_CASE("DEV_UNREACHABLE: a request to an offline adapter is answered by the agent (table 53)") {
    AgentFixture f;
    QuietAdapter a(f, "mill-1");
    f.announce(*a.side, "mill-1", "offline");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "offline"; }));
    const Json answer = f.app_wait_after(*f.app, topics::query_request("mill-1", "mes"), topics::query_response("mill-1", "mes"),
                                         Json{{"@id", "q1"}, {"guid", "mill-1"}, {"ids", {{{"id", "pos"}}}}});
    CHECK(answer["@id"] == "q1");
    CHECK(answer["dev_uuid"] == "mill-1");
    CHECK(answer["cli_uuid"] == "mes");
    CHECK(answer["code"] == "NG");
    CHECK(answer["reason"] == "DEV_UNREACHABLE");
    CHECK(answer["error"] == 301);
    // a Probe/Query with no model cached gets the same
    const Json probe = f.app_wait_after(*f.app, topics::probe_query_request("mill-1", "mes"),
                                        topics::probe_query_response("mill-1", "mes"), Json{{"@id", "p1"}});
    CHECK(probe["reason"] == "DEV_UNREACHABLE");
    CHECK(f.agent->stats().unreachable == 2);
}

TEST_CASE("DEV_UNREACHABLE: the adapter drops while a request waits (8.3.5 and table 54)") {
    AgentFixture f;
    QuietAdapter a(f, "mill-1");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "online"; }));
    f.app->send(topics::set_request("mill-1", "mes"),
                Json{{"@id", "s1"}, {"guid", "mill-1"}, {"values", {{{"id", "ovr"}, {"params", {{"value", 1}}}}}}}.dump());
    REQUIRE(eventually([&] { return f.agent->stats().pending == 1; }));
    REQUIRE(f.broker.drop_client("mill-1"));
    const Json answer = f.app->wait(topics::set_response("mill-1", "mes"));
    CHECK(answer["@id"] == "s1");
    CHECK(answer["reason"] == "DEV_UNREACHABLE");
    CHECK(f.agent->stats().pending == 0);
}

TEST_CASE("Timeout: a request the adapter does not answer in time gets 203 from the agent") {
    AgentConfig c;
    c.request_timeout = 1500ms;
    AgentFixture f(c);
    QuietAdapter a(f, "mill-1");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "online"; }));
    f.app->send(topics::query_request("mill-1", "mes"), Json{{"@id", "q1"}, {"guid", "mill-1"}, {"ids", {"pos"}}}.dump());
    f.app->send(topics::query_request("mill-1", "mes"), Json{{"@id", "q2"}, {"guid", "mill-1"}, {"ids", {"pos"}}}.dump());
    REQUIRE(eventually([&] { return f.agent->stats().pending == 2; }));
    // q2 is answered by the adapter: no 203 for it
    a.side->send(topics::query_response("mill-1", "mes"),
                 Json{{"@id", "q2"}, {"guid", "mill-1"}, {"values", Json::array()}}.dump());
    REQUIRE(eventually([&] { return f.agent->stats().pending == 1; }));
    f.advance(1499ms);
    std::this_thread::sleep_for(100ms);
    CHECK(f.agent->stats().timeouts == 0);
    f.advance(1ms);
    const Json answer = f.app->wait(topics::query_response("mill-1", "mes"), 2);
    CHECK(answer["@id"] == "q1");
    CHECK(answer["code"] == "NG");
    CHECK(answer["error"] == 203);
    CHECK(answer["reason"] == "Timeout");
    CHECK(is_agent_answer(answer));
    CHECK(f.agent->stats().timeouts == 1);
    // the agent's own answer is not taken for a sign of life or an answer
    CHECK(f.agent->stats().pending == 0);
}

TEST_CASE("access control: a request the application may not make is answered 301") {
    AgentConfig c;
    c.access.applications["viewer"]["*"] = access_read;
    AgentFixture f(c);
    QuietAdapter a(f, "mill-1");
    const Json denied = f.app_wait_after(*f.app, topics::set_request("mill-1", "viewer"), topics::set_response("mill-1", "viewer"),
                                         Json{{"@id", "s1"}, {"guid", "mill-1"}, {"values", Json::array()}});
    CHECK(denied["code"] == "NG");
    CHECK(denied["error"] == 301);
    CHECK(denied["reason"] == "Permission Denied");
    CHECK(denied["guid"] == "mill-1");
    const Json call = f.app_wait_after(*f.app, topics::method_call("mill-1", "viewer"), topics::method_result("mill-1", "viewer"),
                                       Json{{"@id", "m1"}, {"id", "m_start"}});
    CHECK(call["error"] == 301);
    CHECK(f.agent->stats().denied == 2);
    // reading is allowed: the request is left to the adapter
    f.app->send(topics::query_request("mill-1", "viewer"), Json{{"@id", "q"}, {"ids", {"pos"}}}.dump());
    REQUIRE(eventually([&] { return f.agent->stats().pending == 1; }));
}

TEST_CASE("access control: with a closed allowlist an unregistered application is answered 301") {
    AgentConfig c;
    c.registration.open = false;
    c.registration.terminals["mes"] = TerminalEntry{"application", ""};
    c.registration.terminals["outsider"] = TerminalEntry{"application", ""};
    AgentFixture f(c);
    QuietAdapter a(f, "mill-1");
    // listed but not registered yet: refused like one without the right
    const Json refused = f.app_wait_after(*f.app, topics::query_request("mill-1", "outsider"),
                                          topics::query_response("mill-1", "outsider"), Json{{"@id", "q1"}, {"ids", {"pos"}}});
    CHECK(refused["error"] == 301);
    CHECK(f.agent->stats().denied == 1);
    CHECK(f.agent->stats().pending == 0);
    // a stranger cannot register, so stays refused
    CHECK(f.register_as(*f.app, "stranger", "r0")["error"] == 301);
    const Json stranger =
        f.app_wait_after(*f.app, topics::set_request("mill-1", "stranger"), topics::set_response("mill-1", "stranger"),
                         Json{{"@id", "s1"}, {"values", Json::array()}});
    CHECK(stranger["error"] == 301);
    // once registered, the request is left to the adapter
    CHECK(f.register_as(*f.app, "mes", "r1")["code"] == "OK");
    f.app->send(topics::query_request("mill-1", "mes"), Json{{"@id", "q2"}, {"ids", {"pos"}}}.dump());
    REQUIRE(eventually([&] { return f.agent->stats().pending == 1; }));
    CHECK(f.agent->stats().denied == 2);
}

TEST_CASE("a retained request replayed by the broker is ignored") {
    AgentFixture f({}, false);
    f.app->send(topics::query_request("mill-1", "mes"), Json{{"@id", "q1"}, {"ids", {"pos"}}}.dump(), true);
    REQUIRE(eventually([&] { return f.broker.retained(topics::query_request("mill-1", "mes")).has_value(); }));
    f.start_agent();  // subscribing replays it, flagged retained
    REQUIRE(eventually([&] { return f.agent->stats().ignored_retained == 1; }));
    CHECK(f.agent->stats().pending == 0);
}

TEST_CASE("persistence: registrations survive an agent restart") {
    AgentConfig c;
    c.state_dir = scratch_dir("agent-registry");
    AgentFixture f(c);
    QuietAdapter a(f, "mill-1");
    f.register_as(*a.side, "mill-1", "r1");
    REQUIRE(eventually([&] { return kind_of(*f.agent, "mill-1") == "adapter"; }));
    f.restart_agent();
    const auto t = terminal(*f.agent, "mill-1");
    REQUIRE(t);
    CHECK(t->registered);
    CHECK(t->kind == "adapter");
    const Json listed = f.app_wait_after(*f.app, topics::discovery_request("app"), topics::discovery_response("app"),
                                         Json{{"@id", "d"}, {"guid", "app"}});
    REQUIRE(listed["deviceList"].size() == 1);
    CHECK(listed["deviceList"][0]["guid"] == "mill-1");
}

TEST_CASE("persistence: an unreadable registry stops the agent from starting") {
    AgentConfig c;
    c.state_dir = scratch_dir("agent-broken");
    {
        std::ofstream bad(c.state_dir + "/registry.json");
        bad << "{ not json";
    }
    AgentFixture f(c, false);
    Agent agent(f.config);
    agent.use_transport(make_loopback_transport(f.broker, LoopbackOptions{"agent-x", std::nullopt, {}}));
    const auto started = agent.start();
    REQUIRE_FALSE(started.ok());
    CHECK(started.error().code == ErrorCode::syntax_error);
}

TEST_CASE("malformed discovery and state DTUs are answered or counted and the agent keeps serving") {
    AgentFixture f;
    f.app->send(topics::discovery_request("mes"), "not json");
    const Json answer = f.app->wait(topics::discovery_response("mes"));
    CHECK(answer["code"] == "NG");
    CHECK(answer["error"] == 412);
    CHECK(answer["guid"] == "mes");
    f.app->send(topics::notify_state("mill-1"), R"({"tid":"mill-1","state":"sideways"})");
    REQUIRE(eventually([&] { return f.agent->stats().malformed == 2; }));
    CHECK(f.register_as(*f.app, "mes", "r")["code"] == "OK");
}

TEST_CASE("discovery: an agent started without its state lists an online adapter from its retained state") {
    AgentFixture f({}, false);
    // Before the agent: an adapter with its retained online state, and an
    // application whose retained state an earlier agent announced.
    auto adapter = f.peer("mill-1", offline_will("mill-1"));
    adapter->subscribe(topics::probe_query_request("mill-1", "+"));
    f.announce(*adapter, "mill-1");
    f.announce(*f.app, "some-app");
    f.start_agent();
    // The state does not say what kind of terminal: the agent asks for the
    // model; an adapter answers, an application does not.
    const std::string probe_topic = topics::probe_query_request("mill-1", f.config.agent_id);
    const Json probe = adapter->wait(probe_topic);
    CHECK(f.app->on(topics::probe_query_request("some-app", f.config.agent_id)).size() == 1);
    adapter->send(topics::probe_query_response("mill-1", f.config.agent_id),
                  Json{{"@id", probe["@id"]}, {"guid", "mill-1"}, {"code", "OK"}, {"probe", {{"id", "m"}}}}.dump());
    REQUIRE(eventually([&] { return kind_of(*f.agent, "mill-1") == "adapter"; }));
    const Json list = f.app_wait_after(*f.app, topics::discovery_request("viewer"), topics::discovery_response("viewer"),
                                       Json{{"@id", "d"}, {"guid", "viewer"}});
    REQUIRE(list["deviceList"].is_array());
    REQUIRE(list["deviceList"].size() == 1);
    CHECK(list["deviceList"][0]["guid"] == "mill-1");
    CHECK(list["deviceList"][0]["status"] == "online");
    // Asked once per online period.
    f.announce(*adapter, "mill-1");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(adapter->on(probe_topic).size() == 1);
}
