// sim -> NC-Link -> nclink-bridge -> MTConnect -> the MTConnect source driver
// -> NC-Link again: the second terminal ("the copy") must show the types,
// units and values of the first, follow changes, refuse Sets with 301, and
// recover from a restarted agent (new instanceId), a dropped connection and
// a `from` that fell out of the agent's buffer.
#include "support/model_items.hpp"
#include "bridge/bridge.hpp"
#include "mtconnect/agent_source.hpp"
#include "mtconnect/mtconnect_driver.hpp"
#include "mtconnect/probe_document.hpp"
#include "mtconnect/reverse_mapping.hpp"

#include "support/sim_mill_rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::eventually;

namespace {

const std::string kCopy = "mt-copy-01";

using nclink::test::model_items;

struct Rig : nclink::test::SimMillRig {
    explicit Rig(std::size_t buffer_size = 4096) {
        start();
        client = make_client("checker");
        bridge_config.broker_url = broker.url();
        bridge_config.http_port = 0;
        bridge_config.shdr_enabled = false;
        bridge_config.buffer_size = buffer_size;
        bridge_config.poll_interval = 200ms;
        bridge_config.ex_cid = "bridge-mt-itest";
        start_bridge();
        bridge_config.http_port = the_bridge->http_port();  // a restart comes back on the same port
    }
    ~Rig() override {
        if (copy) copy->stop(std::chrono::milliseconds(0));
        the_bridge.reset();
    }

    void start_bridge() {
        the_bridge = std::make_unique<bridge::Bridge>(bridge_config, Logger{});
        REQUIRE(the_bridge->start().ok());
        const mtconnect::AgentUrl url{"127.0.0.1", the_bridge->http_port(), ""};
        REQUIRE(eventually(
            [&] {
                auto r = mtconnect::agent_get(url, "/current", 2s);
                return r.ok() && r->find(">AVAILABLE</Availability>") != std::string::npos;
            },
            20s));
    }
    std::string agent_url() const { return "http://127.0.0.1:" + std::to_string(the_bridge->http_port()); }

    /// The copy: its model generated from the bridge's probe (what
    /// `nclink map --from-mtconnect` writes), its driver following the bridge.
    void start_copy(Json driver_config) {
        auto body = mtconnect::agent_get({"127.0.0.1", the_bridge->http_port(), ""}, "/probe", 5s);
        REQUIRE(body.ok());
        auto probe = mtconnect::read_probe(body.value());
        REQUIRE(probe.ok());
        mtconnect::ReverseOptions o;
        o.device = nclink::test::kSimMillDevice;
        auto reversed = mtconnect::reverse_map(probe.value(), o);
        REQUIRE(reversed.ok());
        generated = reversed->model;
        std::filesystem::create_directories(scratch.path);
        const auto file = scratch.path / "mt-copy.json";
        std::ofstream(file) << generated.dump(2);
        AdapterConfig c;
        c.broker_url = broker.url();
        c.model_path = file.string();
        c.dev_uuid = kCopy;  // the probe's uuid is the sim's, which is on this broker already
        c.register_timeout = 500ms;
        c.driver_config = std::move(driver_config);
        mt = std::make_shared<mtconnect::MtConnectDriver>();
        copy = nclink::test::started_adapter(c, mt);
    }

    /// Query of one item of the copy: its value, or null when it did not answer OK.
    Json copy_value(const std::string& id) {
        auto results = client->query(kCopy, {QueryItem{id, std::nullopt}});
        if (!results.ok() || !results->at(0).status.ok) return nullptr;
        return (*results->at(0).values)[0];
    }

    bridge::BridgeConfig bridge_config;
    std::unique_ptr<bridge::Bridge> the_bridge;
    std::shared_ptr<mtconnect::MtConnectDriver> mt;
    std::unique_ptr<Adapter> copy;
    Json generated;
};

// The bridge serves every terminal it finds, the copy too: the driver names
// the device it follows (else, after a restart, the first of the probe's
// devices could be the copy itself).
Json fast_agent(const Rig& rig) {
    return Json{{"agent", rig.agent_url()},
                {"device", nclink::test::kSimMillDevice},
                {"interval_ms", 100},
                {"retry_ms", 100},
                {"timeout_ms", 2000}};
}

}  // namespace

TEST_CASE("round trip: the copy has the sim's types, units and values, follows changes and refuses Sets") {
    Rig rig;
    rig.start_copy(fast_agent(rig));

    // Types and units: every data item of the sim that is an MTConnect DataItem.
    const LoadResult sim = load_model_file(rig.config.model_path);
    REQUIRE(sim.ok());
    const auto original = model_items(model_to_json(*sim.model));
    const auto copied = model_items(rig.generated);
    auto mapping = mtconnect_mapping(*sim.model);
    REQUIRE(mapping.ok());
    int compared = 0;
    for (const MtDataItem& mt : mapping->items()) {
        if (mt.target != MtTarget::data_item && mt.target != MtTarget::fallback) continue;
        INFO(mt.item_id);
        REQUIRE(copied.count(mt.item_id));
        CHECK(copied.at(mt.item_id)["type"] == original.at(mt.item_id)["type"]);
        CHECK(copied.at(mt.item_id).value("units", "") == original.at(mt.item_id).value("units", ""));
        ++compared;
    }
    CHECK(compared > 30);

    // Values nothing changes meanwhile: equal on both terminals.
    for (const char* id : {"spindle_override", "feed_override", "work_mode", "emergency_stop", "door_closed", "tool_number",
                           "machine_category", "spindle_max_speed", "cnc_version", "parameters"}) {
        INFO(id);
        const Json want = rig.query_one(id);
        Json got;
        CHECK(eventually(
            [&] {
                got = rig.copy_value(id);
                return got == want;
            },
            10s));
        CHECK(got == want);
    }
    // A number in a converted unit (mm/min, sent as MILLIMETER/SECOND): a number again.
    CHECK(eventually([&] { return rig.copy_value("x_speed").is_number(); }, 10s));

    // The copy's sample channel (from the probe's sampleRates) publishes
    // what it observes.
    std::size_t column = 0;
    std::string channel;
    for (const auto& c : rig.generated["devices"][0]["configs"])
        if (c["type"] == "SAMPLE_CHANNEL")
            for (std::size_t i = 0; i < c["ids"].size(); ++i)
                if (c["ids"][i]["id"] == "spindle_override") {
                    channel = c["id"].get<std::string>();
                    column = i;
                }
    REQUIRE_FALSE(channel.empty());
    std::mutex seen_mutex;
    bool sampled_87 = false;
    auto subscribed = rig.client->subscribe_samples(kCopy, [&](const SampleDtu& dtu) {
        if (dtu.id != channel || dtu.data.size() <= column) return;
        std::lock_guard lock(seen_mutex);
        for (const auto& v : dtu.data[column]) sampled_87 = sampled_87 || v == Json(87);
    });
    REQUIRE(subscribed.ok());

    // A change on the sim reaches the copy through /sample.
    rig.set_one("spindle_override", Json{{"value", 87}});
    CHECK(eventually([&] { return rig.copy_value("spindle_override") == Json(87); }, 10s));
    CHECK(eventually(
        [&] {
            std::lock_guard lock(seen_mutex);
            return sampled_87;
        },
        10s));
    const Json tools = Json::parse(R"([{"id":"T9","len":12.5}])");
    rig.set_one("tools", Json{{"value", tools}});
    CHECK(eventually([&] { return rig.copy_value("tools") == tools; }, 10s));

    // MTConnect is read-only: a Set on the copy is answered 301.
    auto set = rig.client->set(kCopy, {SetItem{"spindle_override", Json{{"value", 50}}, std::nullopt, std::nullopt}});
    REQUIRE(set.ok());
    CHECK_FALSE(set->at(0).status.ok);
    CHECK(set->at(0).status.error == std::optional<int>(301));

    const auto stats = rig.mt->stats();
    CHECK(stats.currents >= 1);
    CHECK(stats.samples >= 1);
    CHECK(stats.restarts == 0);
}

TEST_CASE("the copy recovers from a dropped agent and from its restart with a new instanceId") {
    Rig rig;
    rig.start_copy(fast_agent(rig));
    REQUIRE(eventually([&] { return rig.copy_value("spindle_override") == rig.query_one("spindle_override"); }, 10s));
    const auto before = rig.mt->stats();

    // The agent goes away: the copy's machine link drops, its items answer 202.
    const std::time_t stopped_at = std::time(nullptr);
    rig.the_bridge.reset();
    CHECK(eventually([&] { return rig.mt->link().state == MachineLink::disconnected; }, 10s));
    CHECK(rig.copy_value("spindle_override").is_null());

    // It comes back on the same port as a new instance (instanceId is its
    // start second: wait for the next one so the ids differ).
    while (std::time(nullptr) <= stopped_at) std::this_thread::sleep_for(50ms);
    rig.set_one("spindle_override", Json{{"value", 73}});
    rig.start_bridge();
    std::string seen;
    const bool recovered = eventually(
        [&] {
            const Json v = rig.copy_value("spindle_override");
            const auto st = rig.mt->stats();
            seen = "value " + v.dump() + ", link '" + rig.mt->link().reason + "', restarts " + std::to_string(st.restarts) +
                   ", failures " + std::to_string(st.failures) + ", currents " + std::to_string(st.currents) + ", samples " +
                   std::to_string(st.samples);
            return v == Json(73);
        },
        20s);
    if (!recovered) {
        auto cur = mtconnect::agent_get({"127.0.0.1", rig.the_bridge->http_port(), ""}, "/current", 2s);
        const std::string body = cur.ok() ? cur.value() : cur.error().message;
        const auto at = body.find(nclink::test::kSimMillDevice + ".spindle_override\"");
        seen += "; bridge: " + (at == std::string::npos ? body.substr(0, 300) : body.substr(at, 200));
        seen += "; sim: " + rig.query_one("spindle_override").dump();
    }
    INFO(seen);
    CHECK(recovered);
    CHECK(rig.mt->link().state == MachineLink::connected);
    const auto after = rig.mt->stats();
    CHECK(after.restarts > before.restarts);
    CHECK(after.probes > before.probes);  // the probe was read again
    CHECK(after.failures > before.failures);
}

TEST_CASE("a sample `from` that fell out of the agent's buffer: /current again, values still current") {
    Rig rig(256);  // a small buffer the 1 ms axis channel overruns between two polls
    rig.start_copy(Json{{"agent", rig.agent_url()},
                        {"device", nclink::test::kSimMillDevice},
                        {"interval_ms", 1500},
                        {"count", 10},
                        {"retry_ms", 100}});
    CHECK(eventually([&] { return rig.mt->stats().out_of_range > 0; }, 30s));
    rig.set_one("spindle_override", Json{{"value", 64}});
    CHECK(eventually([&] { return rig.copy_value("spindle_override") == Json(64); }, 20s));
}
