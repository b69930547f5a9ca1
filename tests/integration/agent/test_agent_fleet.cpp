// A plant powering up: a thousand terminals come online at once, each
// registering (8.2.1) and announcing a model version (8.2.5) but never
// answering the agent's model fetch (8.2.7) and never retrying. The agent
// must register them all and keep answering Discovery (8.2.3) with every one
// of them online.
//
// With mosquitto's default settings exactly 339 were registered: the burst
// is three QoS 1 messages per terminal to the agent, mosquitto keeps at most
// max_queued_messages (default 1000) plus 20 in flight per subscriber and
// drops the rest, and 1020 / 3 = 340 (docs/scaling.md). The broker here has
// exactly the settings nclink ships (tools/mosquitto/nclink.conf), nothing
// larger.
#include <nclink/agent.hpp>
#include <nclink/client.hpp>
#include <nclink/dtu.hpp>
#include <nclink/topics.hpp>

#include "support/mosquitto_broker.hpp"
#include "support/mqtt_fleet.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

FleetClient silent_terminal(const std::string& tid) {
    FleetClient c;
    c.client_id = tid;
    c.subscriptions = {topics::register_response(tid), topics::probe_query_request(tid) + "/#", topics::probe_query_request(tid)};
    RegisterRequest reg;
    reg.msg_id = Json(tid + "-reg");
    reg.cli_uuid = tid;
    ProbeVersionRequest version;
    version.msg_id = Json(tid + "-ver");
    version.version = "1.0";
    NotifyState online;
    online.tid = tid;
    online.state = "online";
    NotifyState offline = online;
    offline.state = "offline";
    c.on_connect = {Message{topics::notify_state(tid), encode(online), 1, true},
                    Message{topics::register_request(), encode(reg), 1, false},
                    Message{topics::probe_version(tid), encode(version), 1, false}};
    c.will = Message{topics::notify_state(tid), encode(offline), 1, true};
    return c;
}

bool got_registered(const MqttFleet& fleet, const std::string& tid) {
    for (const auto& m : fleet.received(tid))
        if (m.topic == topics::register_response(tid)) {
            const auto response = decode<RegisterResponse>(m.payload);
            return response && response->status.ok;
        }
    return false;
}

}  // namespace

TEST_CASE("agent: 1000 terminals coming online at once are all registered and listed by Discovery") {
    constexpr int kTerminals = 1000;
    MosquittoOptions plant;
    plant.large_queues = false;  // the shipped settings alone must carry it
    MosquittoBroker broker(plant);
    AgentConfig config;
    config.broker_url = broker.url();
    config.client_id = "agent-fleet";
    config.request_timeout = 2000ms;
    Agent agent(config);
    REQUIRE(agent.start().ok());
    REQUIRE(eventually([&] { return agent.stats().transport.connects >= 1; }));
    std::this_thread::sleep_for(200ms);  // SUBACKs come asynchronously

    MqttFleet fleet(broker.port());
    std::vector<std::string> ids;
    for (int i = 0; i < kTerminals; ++i) {
        ids.push_back(fmt::format("fleet-{:04d}", i));
        fleet.add(silent_terminal(ids.back()));
    }
    REQUIRE(eventually([&] { return fleet.connected() == kTerminals; }, 120s));
    const bool all_registered = eventually(
        [&] {
            for (const auto& tid : ids)
                if (!got_registered(fleet, tid)) return false;
            return true;
        },
        180s);
    std::size_t registered = 0;
    for (const auto& tid : ids) registered += got_registered(fleet, tid) ? 1 : 0;
    INFO("terminals answered Register/Response OK: " << registered << ", agent stats: registrations " << agent.stats().registrations
                                                     << ", published " << agent.stats().transport.published << ", buffered "
                                                     << agent.stats().transport.buffered << ", in flight "
                                                     << agent.stats().transport.in_flight);
    REQUIRE(all_registered);

    auto app = started_client(broker.url(), "fleet-app", 30s);
    std::set<std::string> online;
    REQUIRE(eventually(
        [&] {
            auto list = app->discover();
            if (!list) return false;
            online.clear();
            for (const auto& entry : *list)
                if (entry.status == "online") online.insert(entry.guid);
            return online.size() == static_cast<std::size_t>(kTerminals);
        },
        120s));
    CHECK(online.count("fleet-0000") == 1);
    CHECK(online.count("fleet-0999") == 1);
}
