// The agent's pure pieces: terminal ids, presence, registration decisions,
// access rights, configuration, and the generated mosquitto ACL.
#include <nclink/agent.hpp>

#include "agent/access.hpp"
#include "agent/agent_mqtt_options.hpp"
#include "agent/model_cache.hpp"
#include "agent/pending_announcements.hpp"
#include "agent/pending_forwards.hpp"
#include "agent/presence.hpp"
#include "agent/registrar.hpp"
#include "agent/terminal_id.hpp"

#include <nclink/topics.hpp>

#include <catch2/catch.hpp>

#include <map>
#include <set>
#include <sstream>

using namespace nclink;
using namespace nclink::agent_detail;
using namespace std::chrono_literals;

namespace {

TerminalIdRule rule(RegistrationPolicy p = {}) { return TerminalIdRule::make(p).value(); }

RegisterRequest reg(const std::string& cli, const std::string& id, Json private_info = nullptr) {
    RegisterRequest r;
    r.msg_id = Json(id);
    r.cli_uuid = cli;
    if (!private_info.is_null()) r.private_info = private_info;
    return r;
}

}  // namespace

TEST_CASE("terminal ids: one topic level of printable UTF-8 is accepted") {
    const auto r = rule();
    CHECK(r.check("mill-7").ok());
    CHECK(r.check("机床_01").ok());
    CHECK(r.check("a.b:c@d").ok());
}

TEST_CASE("terminal ids: separators wildcards spaces control characters and $ get 414") {
    const auto r = rule();
    for (const char* bad : {"", "a/b", "a+b", "a#", "has space", "tab\there", "$SYS", "\xff\xfe"}) {
        INFO(bad);
        const auto checked = r.check(bad);
        REQUIRE_FALSE(checked.ok());
        CHECK(checked.error().code == ErrorCode::unsupported_terminal_id);
    }
    CHECK_FALSE(r.check(std::string(129, 'x')).ok());
}

TEST_CASE("terminal ids: id_pattern narrows what is accepted and must be a regex") {
    RegistrationPolicy p;
    p.id_pattern = "line[0-9]+-.*";
    const auto r = rule(p);
    CHECK(r.check("line3-mill").ok());
    CHECK_FALSE(r.check("mill").ok());
    p.id_pattern = "([";
    CHECK(TerminalIdRule::make(p).error().code == ErrorCode::value_type);
}

TEST_CASE("presence: liveness runs out after the configured time and a DTU brings the terminal back") {
    Presence presence(1000ms, 0ms);
    ManualClock clock;
    presence.set_kind("dev", Kind::adapter);
    CHECK(presence.saw_dtu("dev", clock.now(), 1));
    CHECK(presence.status("dev") == Status::online);
    clock.advance(999ms);
    CHECK(presence.expire(clock.now()).empty());
    clock.advance(1ms);
    CHECK(presence.expire(clock.now()) == std::vector<std::string>{"dev"});
    CHECK(presence.status("dev") == Status::offline);
    CHECK(presence.expire(clock.now()).empty());  // said once
    CHECK(presence.saw_dtu("dev", clock.now(), 2));
    CHECK(presence.online_periods("dev") == 2);
}

TEST_CASE("presence: with an answer window an adapter is asked before it is offline, applications are not") {
    Presence presence(1000ms, 1000ms);
    presence.set_answer_window(300ms);
    ManualClock clock;
    presence.set_kind("dev", Kind::adapter);
    presence.set_kind("app", Kind::application);
    presence.saw_dtu("dev", clock.now(), 1);
    presence.saw_dtu("app", clock.now(), 1);
    clock.advance(999ms);
    CHECK(presence.questions(clock.now()).empty());
    clock.advance(1ms);
    CHECK(presence.questions(clock.now()) == std::vector<std::string>{"dev"});
    CHECK(presence.questions(clock.now()).empty());  // asked once
    CHECK(presence.expire(clock.now()) == std::vector<std::string>{"app"});
    CHECK(presence.status("dev") == Status::online);
    // An answer (any DTU) within the window: online, liveness from the answer.
    clock.advance(200ms);
    CHECK_FALSE(presence.saw_dtu("dev", clock.now(), 2));
    clock.advance(200ms);
    CHECK(presence.expire(clock.now()).empty());
    CHECK(presence.status("dev") == Status::online);
    // Silent again: asked again, and no answer within the window: offline.
    clock.advance(800ms);
    CHECK(presence.questions(clock.now()) == std::vector<std::string>{"dev"});
    clock.advance(299ms);
    CHECK(presence.expire(clock.now()).empty());
    clock.advance(1ms);
    CHECK(presence.expire(clock.now()) == std::vector<std::string>{"dev"});
    CHECK(presence.status("dev") == Status::offline);
    CHECK(presence.questions(clock.now()).empty());
    // Back: a DTU, and the next silence is asked about again.
    CHECK(presence.saw_dtu("dev", clock.now(), 3));
    clock.advance(1000ms);
    CHECK(presence.questions(clock.now()) == std::vector<std::string>{"dev"});
}

TEST_CASE("presence: 0 switches liveness off and applications use their own time") {
    Presence presence(0ms, 500ms);
    ManualClock clock;
    presence.set_kind("dev", Kind::adapter);
    presence.set_kind("app", Kind::application);
    presence.saw_dtu("dev", clock.now(), 1);
    presence.saw_dtu("app", clock.now(), 1);
    clock.advance(1h);
    CHECK(presence.expire(clock.now()) == std::vector<std::string>{"app"});
    CHECK(presence.status("dev") == Status::online);
}

TEST_CASE("presence: a reload's shorter liveness counts at once from each terminal's last DTU") {
    Presence presence(10s, 10s);
    ManualClock clock;
    presence.set_kind("dev", Kind::adapter);
    presence.saw_dtu("dev", clock.now(), 1);
    presence.saw_dtu("app", clock.now(), 1);
    clock.advance(2s);
    CHECK(presence.expire(clock.now()).empty());
    presence.set_liveness(1s, 10s);
    CHECK(presence.expire(clock.now()) == std::vector<std::string>{"dev"});
    // A kind with a shorter time: an application that turns out an adapter.
    presence.saw_dtu("dev", clock.now(), 2);
    presence.set_kind("app", Kind::adapter);
    CHECK(presence.expire(clock.now()) == std::vector<std::string>{"app"});
    // Questions switched on while a terminal is silent: it is asked first.
    presence.set_liveness(1s, 1s);
    clock.advance(1s);
    presence.set_answer_window(500ms);
    CHECK(presence.questions(clock.now()) == std::vector<std::string>{"dev"});
    CHECK(presence.expire(clock.now()).empty());
}

TEST_CASE("presence: a terminal waits in the tick's queue once, however many DTUs it sends") {
    // The tick looks at the terminals that fell due, not at every one: a DTU
    // moves the end of liveness later without queueing anything.
    Presence presence(1s, 1s);
    ManualClock clock;
    for (int i = 0; i < 1000; ++i) {
        presence.saw_dtu("a", clock.now(), i);
        presence.saw_dtu("b", clock.now(), i);
        clock.advance(10ms);
    }
    CHECK(presence.queued() == 2);
    CHECK(presence.expire(clock.now()).empty());  // their first ends passed: queued again from the last DTU
    CHECK(presence.queued() == 2);
    clock.advance(1s);
    const auto gone = presence.expire(clock.now());
    CHECK(gone.size() == 2);
    CHECK(presence.queued() == 0);
}

TEST_CASE("presence: an adapter stays an adapter") {
    Presence presence(0ms, 0ms);
    presence.set_kind("x", Kind::adapter);
    presence.set_kind("x", Kind::application);
    CHECK(presence.kind("x") == Kind::adapter);
}

// An adapter "dev" online, its first online period, and a registrar with the
// default rule and policy.
struct LiveAdapter {
    Presence presence{0ms, 0ms};
    ManualClock clock;
    Registrar registrar{rule(), {}};
    LiveAdapter() {
        presence.set_kind("dev", Kind::adapter);
        presence.set_state("dev", Status::online, clock.now(), 1);
    }
};

TEST_CASE("registrar: a second registration of a live adapter is refused 301 and a resend is not") {
    LiveAdapter live;
    auto& [presence, clock, registrar] = live;
    CHECK(registrar.decide(reg("dev", "r1"), presence, 1).status.ok);
    CHECK(registrar.decide(reg("dev", "r1"), presence, 1).status.ok);  // the same request again
    const auto second = registrar.decide(reg("dev", "r2"), presence, 2);
    CHECK_FALSE(second.status.ok);
    CHECK(second.status.error == 301);
    // offline, then a new connection: a new registration is fine
    presence.set_state("dev", Status::offline, clock.now(), 3);
    presence.set_state("dev", Status::online, clock.now(), 3);
    CHECK(registrar.decide(reg("dev", "r3"), presence, 3).status.ok);
}

TEST_CASE("registrar: a resend of a request answered moments ago in the same online period is told apart") {
    LiveAdapter live;
    auto& [presence, clock, registrar] = live;
    const auto period = presence.online_periods("dev");
    REQUIRE(registrar.decide(reg("dev", "r1"), presence, 1).status.ok);
    CHECK_FALSE(registrar.resent_while_answered("dev", "r1", period, clock.now(), 30s));  // not answered yet
    registrar.answered("dev", clock.now());
    clock.advance(29s);
    CHECK(registrar.resent_while_answered("dev", "r1", period, clock.now(), 30s));
    CHECK_FALSE(registrar.resent_while_answered("dev", "r2", period, clock.now(), 30s));      // another request
    CHECK_FALSE(registrar.resent_while_answered("dev", "r1", period + 1, clock.now(), 30s));  // a new connection
    CHECK_FALSE(registrar.resent_while_answered("other", "r1", period, clock.now(), 30s));
    CHECK_FALSE(registrar.resent_while_answered("dev", "", period, clock.now(), 30s));  // no @id: never a resend
    clock.advance(1s);
    CHECK_FALSE(registrar.resent_while_answered("dev", "r1", period, clock.now(), 30s));  // answered long ago
}

TEST_CASE("registrar: an application registering again replaces its registration") {
    Presence presence(0ms, 0ms);
    ManualClock clock;
    Registrar registrar(rule(), {});
    presence.set_kind("app", Kind::application);
    presence.saw_dtu("app", clock.now(), 1);
    CHECK(registrar.decide(reg("app", "a"), presence, 1).status.ok);
    CHECK(registrar.decide(reg("app", "b"), presence, 1).status.ok);
}

TEST_CASE("registrar: closed allowlist and credentials") {
    RegistrationPolicy p;
    p.open = false;
    p.terminals["mes"] = TerminalEntry{"application", "s3cret"};
    p.terminals["mill"] = TerminalEntry{"adapter", ""};
    Presence presence(0ms, 0ms);
    Registrar registrar(rule(p), p);
    CHECK(registrar.decide(reg("mill", "1"), presence, 1).status.ok);
    CHECK(registrar.decide(reg("stranger", "2"), presence, 1).status.error == 301);
    CHECK(registrar.decide(reg("mes", "3"), presence, 1).status.error == 301);
    CHECK(registrar.decide(reg("mes", "4", Json{{"password", "wrong"}}), presence, 1).status.error == 301);
    CHECK(registrar.decide(reg("mes", "5", Json{{"password", "s3cret"}}), presence, 1).status.ok);
    CHECK(registrar.decide(reg("bad/id", "6"), presence, 1).status.error == 414);
}

TEST_CASE("access: the application entry for the adapter wins over its star entry and the default") {
    AccessPolicy p;
    p.default_rights = access_read;
    p.applications["mes"]["*"] = access_read | access_set;
    p.applications["mes"]["mill-1"] = access_all;
    p.applications["viewer"]["mill-2"] = access_read;
    CHECK(rights_of(p, "stranger", "mill-1") == access_read);
    CHECK(rights_of(p, "mes", "mill-1") == access_all);
    CHECK(rights_of(p, "mes", "mill-9") == (access_read | access_set));
    CHECK(rights_of(p, "viewer", "mill-2") == access_read);
    CHECK(rights_of(p, "viewer", "mill-1") == access_none);  // listed: only what is listed
    CHECK(required_right(TopicKind::set_request) == access_set);
    CHECK(required_right(TopicKind::event_register_request) == access_read);
    CHECK(required_right(TopicKind::method_control_request) == access_method);
    CHECK_FALSE(required_right(TopicKind::query_response));
}

TEST_CASE("model cache: a new version needs a fetch and one fetch at a time") {
    ModelCache cache;
    ManualClock clock;
    CHECK(cache.announce("d", "1.0", clock.now()));
    cache.fetching("d", "f1", clock.now() + 1s);
    CHECK_FALSE(cache.announce("d", "1.0", clock.now()));  // under way
    CHECK(cache.is_fetch("d", "f1"));
    CHECK(cache.store("d", Json{{"id", "m"}}, 10));
    CHECK_FALSE(cache.announce("d", "1.0", clock.now()));  // have it
    CHECK(cache.announce("d", "1.1", clock.now()));
    CHECK(cache.find("d")->model_version == "1.0");
    cache.fetching("d", "f2", clock.now() + 1s);
    clock.advance(2s);
    cache.expire_fetches(clock.now());
    CHECK(cache.announce("d", "1.1", clock.now()));  // the overdue fetch is forgotten
    // A new fetch replaces the one under way: the old deadline ends nothing.
    cache.fetching("d", "f3", clock.now() + 1s);
    cache.fetching("d", "f4", clock.now() + 5s);
    clock.advance(2s);
    cache.expire_fetches(clock.now());
    CHECK(cache.is_fetch("d", "f4"));
    clock.advance(3s);
    cache.expire_fetches(clock.now());
    CHECK_FALSE(cache.is_fetch("d", "f4"));
}

TEST_CASE("pending forwards: answered by @id and kind or overdue or failed per adapter") {
    PendingForwards pending;
    ManualClock clock;
    Forwarded q;
    q.kind = TopicKind::query_request;
    q.dev = "d";
    q.ex = "app";
    q.msg_id = Json("q1");
    q.deadline = clock.now() + 1s;
    pending.add(q);
    Forwarded m = q;
    m.kind = TopicKind::method_call;
    m.msg_id = Json("m1");
    pending.add(m);
    Forwarded no_id = q;
    no_id.msg_id.reset();
    pending.add(no_id);  // not trackable
    CHECK(pending.size() == 2);
    CHECK_FALSE(pending.answered(TopicKind::set_response, "d", std::string("app"), "q1"));
    CHECK(pending.answered(TopicKind::method_status, "d", std::string("app"), "m1"));
    CHECK(pending.size() == 1);
    clock.advance(1s);
    CHECK(pending.take_expired(clock.now()).size() == 1);
    pending.add(q);
    CHECK(pending.take_for("other").empty());
    CHECK(pending.take_for("d").size() == 1);
}

TEST_CASE("pending announcements: due after the grace, in order, unless cancelled") {
    PendingAnnouncements held;
    ManualClock clock;
    held.hold("a", clock.now(), 30s);
    clock.advance(1s);
    held.hold("b", clock.now(), 30s);
    held.hold("a", clock.now(), 30s);  // already waiting: keeps its first time
    held.hold("c", clock.now(), 30s);
    CHECK(held.size() == 3);
    clock.advance(28s);
    CHECK(held.take_due(clock.now()).empty());
    clock.advance(1s);  // 30 s after a
    CHECK(held.take_due(clock.now()) == std::vector<std::string>{"a"});
    held.cancel("b");  // its own Notify/State came
    clock.advance(1s);
    CHECK(held.take_due(clock.now()) == std::vector<std::string>{"c"});
    CHECK(held.size() == 0);
    // Cancelled and held again: the later time counts, once.
    held.hold("d", clock.now(), 30s);
    held.cancel("d");
    clock.advance(10s);
    held.hold("d", clock.now(), 30s);
    clock.advance(20s);
    CHECK(held.take_due(clock.now()).empty());
    clock.advance(10s);
    CHECK(held.take_due(clock.now()) == std::vector<std::string>{"d"});
    CHECK(held.take_due(clock.now() + 1h).empty());
}

TEST_CASE("agent configuration: keys are read and typos refused") {
    const Json json = Json::parse(R"({
      "broker": {"url": "tcp://broker:1883", "mqtt_version": 4, "username": "nclink-agent"},
      "agent_id": "agent-a", "share_group": "plant", "state_dir": "/var/lib/nclink-agent",
      "request_timeout_ms": 900, "adapter_liveness_ms": 60000, "application_liveness_ms": 0,
      "registration": {"open": false, "max_id_length": 64, "id_pattern": "[a-z0-9-]+",
                       "terminals": {"mill-1": {"kind": "adapter"}, "mes": {"kind": "application", "password": "pw"}}},
      "access": {"default": ["read"], "applications": {"mes": {"*": "all"}, "viewer": {"mill-1": ["read"]}}},
      "acl": {"agent_user": "agents"}, "log_level": "debug", "max_in_flight": 250, "discovery_link": false
    })");
    auto c = agent_config_from_json(json);
    INFO((c.ok() ? std::string() : c.error().describe()));
    REQUIRE(c.ok());
    CHECK(c->broker_url == "tcp://broker:1883");
    CHECK(c->mqtt_version == 4);
    CHECK(c->share_group == "plant");
    CHECK(c->request_timeout == 900ms);
    CHECK(c->adapter_liveness == 60000ms);
    CHECK_FALSE(c->registration.open);
    CHECK(c->registration.terminals.at("mes").password == "pw");
    CHECK(c->access.default_rights == access_read);
    CHECK(c->access.applications.at("mes").at("*") == access_all);
    CHECK(c->acl_agent_user == "agents");
    CHECK(c->log_level == LogLevel::debug);
    CHECK(c->max_in_flight == 250);
    CHECK(agent_config_from_json(Json{{"max_in_flight", 0}})->max_in_flight == 1);
    CHECK(agent_config_from_json(Json::object())->max_in_flight == 1000);
    CHECK_FALSE(c->discovery_link);
    CHECK(agent_config_from_json(Json::object())->discovery_link);

    CHECK(agent_config_from_json(Json{{"request_timout_ms", 1}}).error().code == ErrorCode::keys_of_arguments);
    CHECK(agent_config_from_json(Json{{"access", {{"default", {"write"}}}}}).error().code == ErrorCode::value_type);
    CHECK(agent_config_from_json(Json{{"registration", {{"id_pattern", "(["}}}}).error().code == ErrorCode::value_type);
    CHECK(agent_config_from_json(Json{{"share_group", "a/b"}}).error().code == ErrorCode::value_type);
    CHECK_FALSE(load_agent_config("/nonexistent/agent.json").ok());
}

TEST_CASE("agent MQTT options: the broker section, a unique client id and the agent's in-flight window") {
    AgentConfig c;
    c.broker_url = "tcp://broker:1883";
    c.max_in_flight = 777;
    MqttOptions o = agent_mqtt_options(c, "1a2b");
    CHECK(o.broker_url == "tcp://broker:1883");
    CHECK(o.client_id == "nclink-agent-1a2b");
    CHECK(o.outbox.max_in_flight == 777);  // not the transport's default of 64
    c.client_id = "fixed";
    CHECK(agent_mqtt_options(c, "1a2b").client_id == "fixed");
}

TEST_CASE("mosquitto ACL: agents get everything and adapters only the requests they may receive") {
    AgentConfig c;
    c.access.default_rights = access_read;
    c.access.applications["mes"]["*"] = access_all;
    c.access.applications["viewer"]["mill-1"] = access_read;
    const std::string acl = mosquitto_acl(c);
    auto has = [&](const std::string& line) {
        INFO(line);
        CHECK(acl.find("\n" + line + "\n") != std::string::npos);
    };
    has("user nclink-agent\ntopic readwrite #");
    // mill-1 is named: explicit lines per listed application, the default for the rest
    has("user mill-1");
    has("topic read Set/Request/mill-1/mes");
    has("topic deny Set/Request/mill-1/viewer");
    has("topic read Query/Request/mill-1/viewer");
    has("topic read Query/Request/mill-1/+");
    // adapters not named: the default plus each application's "*" entry
    has("pattern read Query/Request/%u/+");
    has("pattern read Set/Request/%u/mes");
    has("pattern read Method/Call/%u/mes");
    has("pattern deny Query/Request/%u/viewer");
    // applications write requests under their own id only
    has("pattern write Set/Request/+/%u");
    has("pattern read Set/Response/+/%u");
    has("pattern write Register/Request");
    has("pattern read Register/Response/%u");
    // both spellings of the event/sampling registrations
    has("pattern write Reigster/Event/Request/+/%u");
    // the broker round-trip check every program runs at start, under its user name
    has("pattern readwrite nclink-rtt/%u/#");
    CHECK(acl.find("pattern read Set/Request/%u/+") == std::string::npos);
}

TEST_CASE("mosquitto ACL: a closed allowlist gives the default rights to listed applications only") {
    AgentConfig c;
    c.access.default_rights = access_read;
    c.access.applications["mes"]["*"] = access_all;
    c.access.applications["ghost"]["*"] = access_all;  // not on the allowlist: it cannot register
    c.registration.open = false;
    c.registration.terminals["mill-1"] = TerminalEntry{"adapter", ""};
    c.registration.terminals["mes"] = TerminalEntry{"application", ""};
    c.registration.terminals["viewer"] = TerminalEntry{"application", ""};
    const std::string acl = mosquitto_acl(c);
    auto has = [&](const std::string& line, bool expected = true) {
        INFO(line);
        CHECK((acl.find("\n" + line + "\n") != std::string::npos) == expected);
    };
    has("topic read Query/Request/mill-1/viewer");  // listed: the default rights, by name
    has("topic read Set/Request/mill-1/mes");
    has("topic deny Set/Request/mill-1/ghost");       // listed in access but not allowed to register
    has("topic read Query/Request/mill-1/+", false);  // nobody else
    has("pattern read Query/Request/%u/viewer");
    has("pattern read Query/Request/%u/+", false);
    has("topic read Probe/Query/Request/mill-1/nclink-agent");  // the agent's model fetches
    has("user viewer\ntopic read Sample/+/+");
    has("pattern read Sample/+/+", false);
}

namespace {

// The generated ACL as mosquitto reads it: the topic lines of each user, and
// the patterns (which apply to every user).
struct AclLines {
    std::map<std::string, std::set<std::string>> users;
    std::set<std::string> patterns;
    bool user_has(const std::string& user, const std::string& line) const {
        const auto it = users.find(user);
        return it != users.end() && it->second.count(line) != 0;
    }
};

AclLines parse_acl(const std::string& acl) {
    AclLines out;
    std::istringstream in(acl);
    std::string line, user;
    while (std::getline(in, line)) {
        if (line.rfind("user ", 0) == 0) user = line.substr(5);
        else if (line.rfind("topic ", 0) == 0) out.users[user].insert(line.substr(6));
        else if (line.rfind("pattern ", 0) == 0) out.patterns.insert(line.substr(8));
    }
    return out;
}

// Any line granting a read of `topic` (as mosquitto matches it) to `user`,
// by the user's topic lines or a pattern (%u replaced).
bool acl_lets_read(const AclLines& acl, const std::string& user, const std::string& topic) {
    auto grants = [&](const std::string& line, bool pattern) {
        std::string access, filter;
        std::istringstream words(line);
        words >> access >> filter;
        if (access != "read" && access != "readwrite") return false;
        if (pattern)
            for (std::size_t at; (at = filter.find("%u")) != std::string::npos;) filter.replace(at, 2, user);
        return topic_matches(filter, topic);
    };
    if (const auto it = acl.users.find(user); it != acl.users.end()) {
        for (const auto& l : it->second)
            if (l.rfind("deny ", 0) == 0 && topic_matches(l.substr(5), topic)) return false;
        for (const auto& l : it->second)
            if (grants(l, false)) return true;
    }
    for (const auto& l : acl.patterns)
        if (grants(l, true)) return true;
    return false;
}

}  // namespace

TEST_CASE("access: watch is a right of its own that all does not include") {
    CHECK(parse_rights(Json::array({"read", "watch"}), "x").value() == (access_read | access_watch));
    CHECK(parse_rights(Json("watch"), "x").value() == access_watch);
    CHECK((parse_rights(Json("all"), "x").value() & access_watch) == 0);
    CHECK(right_names(access_read | access_watch) == std::vector<std::string>{"read", "watch"});
    auto c = agent_config_from_json(Json::parse(R"({"access": {"applications": {"dash": {"mill-1": ["read", "watch"]}}}})"));
    REQUIRE(c.ok());
    CHECK(c->access.applications.at("dash").at("mill-1") == (access_read | access_watch));
}

TEST_CASE("mosquitto ACL: only watch lets an application read other applications' method runs and events") {
    AgentConfig c;
    c.access.default_rights = access_all;
    c.access.applications["mes"]["*"] = access_all;
    c.access.applications["dash"]["mill-1"] = access_read | access_watch;
    c.access.applications["ops"]["*"] = access_read | access_watch;
    c.registration.terminals["mill-2"] = TerminalEntry{"adapter", ""};
    const AclLines acl = parse_acl(mosquitto_acl(c));
    // the runs and events of application cam at mill-1
    const std::vector<std::string> others = {"Method/Status/mill-1/cam", "Method/Result/mill-1/cam", "Event/mill-1/cam"};
    for (const auto& topic : others) {
        INFO(topic);
        CHECK(acl_lets_read(acl, "dash", topic));            // watch on mill-1
        CHECK(acl_lets_read(acl, "ops", topic));             // watch everywhere
        CHECK_FALSE(acl_lets_read(acl, "mes", topic));       // all, but not watch
        CHECK_FALSE(acl_lets_read(acl, "stranger", topic));  // the default: all, not watch
    }
    CHECK(acl.user_has("dash", "read Method/Status/mill-1/+"));
    CHECK(acl.user_has("dash", "read Method/Result/mill-1/+"));
    CHECK(acl.user_has("dash", "read Event/mill-1/+"));
    CHECK(acl.user_has("ops", "read Event/+/+"));
    // dash may not watch mill-2 (named, no entry), ops may
    CHECK_FALSE(acl_lets_read(acl, "dash", "Event/mill-2/mes"));
    CHECK(acl_lets_read(acl, "ops", "Method/Result/mill-2/mes"));
    // everybody still reads its own answers, with or without watch
    CHECK(acl_lets_read(acl, "mes", "Method/Result/mill-1/mes"));
    CHECK(acl_lets_read(acl, "dash", "Event/mill-2/dash"));
    CHECK(acl_lets_read(acl, "stranger", "Method/Status/mill-2/stranger"));
}

TEST_CASE("mosquitto ACL: a star watch narrowed for one adapter is granted by name only") {
    AgentConfig c;
    c.access.default_rights = access_none;
    c.access.applications["ops"]["*"] = access_read | access_watch;
    c.access.applications["ops"]["mill-2"] = access_read;  // not this one
    c.registration.terminals["mill-1"] = TerminalEntry{"adapter", ""};
    c.registration.terminals["mill-2"] = TerminalEntry{"adapter", ""};
    const AclLines acl = parse_acl(mosquitto_acl(c));
    CHECK(acl_lets_read(acl, "ops", "Event/mill-1/mes"));
    CHECK_FALSE(acl_lets_read(acl, "ops", "Event/mill-2/mes"));
    CHECK_FALSE(acl_lets_read(acl, "ops", "Method/Status/mill-2/mes"));
    CHECK(acl_lets_read(acl, "ops", "Method/Status/mill-2/ops"));  // its own
}

TEST_CASE("mosquitto ACL: a default watch is a pattern only when no listed application lacks it") {
    AgentConfig c;
    c.access.default_rights = access_read | access_watch;
    SECTION("open, every listed application watches") {
        c.access.applications["ops"]["*"] = access_all | access_watch;
        const AclLines acl = parse_acl(mosquitto_acl(c));
        CHECK(acl_lets_read(acl, "stranger", "Method/Result/mill-1/mes"));
        CHECK(acl_lets_read(acl, "ops", "Event/mill-1/mes"));
    }
    SECTION("open, a listed application does not") {
        c.access.applications["viewer"]["*"] = access_read;
        const AclLines acl = parse_acl(mosquitto_acl(c));
        CHECK_FALSE(acl_lets_read(acl, "viewer", "Event/mill-1/mes"));
        CHECK_FALSE(acl_lets_read(acl, "stranger", "Event/mill-1/mes"));  // fails closed
        CHECK(acl_lets_read(acl, "viewer", "Event/mill-1/viewer"));
    }
    SECTION("closed: by name to the listed applications") {
        c.registration.open = false;
        c.registration.terminals["mill-1"] = TerminalEntry{"adapter", ""};
        c.registration.terminals["dash"] = TerminalEntry{"application", ""};
        const AclLines acl = parse_acl(mosquitto_acl(c));
        CHECK(acl_lets_read(acl, "dash", "Method/Status/mill-1/mes"));
        CHECK_FALSE(acl_lets_read(acl, "stranger", "Method/Status/mill-1/mes"));
    }
}

TEST_CASE("the agent's metrics section sets the HTTP limits of nclink-agent --metrics") {
    auto c = agent_config_from_json(Json::parse(R"({"metrics": {"http_max_connections_per_peer": 2, "http_keep_alive_ms": 50}})"));
    INFO((c.ok() ? "" : c.error().describe()));
    REQUIRE(c.ok());
    CHECK(c->metrics.max_connections_per_peer == 2);
    CHECK(c->metrics.keep_alive == std::chrono::milliseconds(50));
    CHECK(c->metrics.workers == 2);  // the rest keep their defaults
    auto typo = agent_config_from_json(Json::parse(R"({"metrics": {"http_max_conections": 2}})"));
    REQUIRE_FALSE(typo.ok());
    CHECK(typo.error().code == ErrorCode::keys_of_arguments);
    CHECK(typo.error().message.find("http_max_connections") != std::string::npos);  // the nearest key is named
}
