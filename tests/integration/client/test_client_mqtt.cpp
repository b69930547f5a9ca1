// The client and the `nclink` device commands over a real mosquitto, against
// a scripted adapter: mirror topics over TCP, retained state, timeouts, exit codes.
#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/topics.hpp>

#include "support/cli.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cstdio>
#include <mutex>
#include <thread>

using namespace nclink;
using nclink::test::cli_built;
using nclink::test::run_cli;
using Run = nclink::test::CliRun;
using namespace std::chrono_literals;
using nclink::test::eventually;
using nclink::test::MosquittoBroker;

namespace {

// Answers Query with "v-<id>" (NG 401 for ids starting with "no"), Set with
// OK, Probe with a one-channel model, and publishes a retained online state.
class ScriptedAdapter {
public:
    ScriptedAdapter(const MosquittoBroker& broker, std::string dev) : dev_(std::move(dev)) {
        MqttOptions o;
        o.broker_url = broker.url();
        o.client_id = "adapter-" + dev_;
        o.last_will = Message{topics::notify_state(dev_), Json{{"tid", dev_}, {"state", "offline"}}.dump(), 1, true};
        auto made = make_mqtt_transport(std::move(o));
        REQUIRE(made.ok());
        transport_ = std::move(made).value();
        transport_->set_message_handler([this](const Message& m) { answer(m); });
        REQUIRE(transport_->subscribe(topics::adapter_subscriptions(dev_), 1).ok());
        REQUIRE(transport_->start().ok());
        REQUIRE(eventually([&] { return transport_->state() == LinkState::connected; }));
        REQUIRE(transport_->publish({topics::notify_state(dev_), Json{{"tid", dev_}, {"state", "online"}}.dump(), 1, true}).ok());
        REQUIRE(transport_->flush(5s));
    }
    ~ScriptedAdapter() { transport_->stop(500ms); }

    void publish_sample(std::int64_t begin) {
        SampleDtu s;
        s.guid = dev_;
        s.id = "ch1";
        s.begin_time = begin;
        s.data = {Json::array({1, 2}), Json::array({"a", nullptr})};
        (void)transport_->publish({topics::sample(dev_, "ch1"), encode(s), 0, false});
    }

private:
    void answer(const Message& m) {
        const auto topic = parse_topic(m.topic);
        const auto reply = response_topic(m.topic);
        if (!topic || !reply) return;
        const Json req = Json::parse(m.payload, nullptr, false);
        if (!req.is_object()) return;
        Json body{{"@id", req.value("@id", Json())}, {"guid", dev_}};
        if (topic->kind == TopicKind::query_request) {
            body["values"] = Json::array();
            for (const auto& item : req["ids"]) {
                const std::string id = item["id"].get<std::string>();
                if (id.rfind("no", 0) == 0)
                    body["values"].push_back({{"id", id}, {"code", "NG"}, {"reason", "Node not exists"}, {"error", 401}});
                else body["values"].push_back({{"id", id}, {"code", "OK"}, {"values", {"v-" + id}}});
            }
        } else if (topic->kind == TopicKind::set_request) {
            body["results"] = Json::array();
            for (const auto& item : req["values"]) body["results"].push_back({{"id", item["id"]}, {"code", "OK"}});
        } else if (topic->kind == TopicKind::probe_query_request) {
            body["code"] = "OK";
            body["probe"] = {
                {"id", "root"},
                {"type", "NC_LINK_ROOT"},
                {"version", "1.0.0"},
                {"devices",
                 {{{"id", "m"},
                   {"type", "MACHINE"},
                   {"guid", dev_},
                   {"configs",
                    {{{"id", "ch1"},
                      {"type", "SAMPLE_CHANNEL"},
                      {"sampleInterval", 10},
                      {"uploadInterval", 100},
                      {"ids", {{{"id", "pos"}}, {{"id", "mode"}}}}}}},
                   {"dataItems",
                    {{{"id", "pos"}, {"type", "POSITION"}, {"setable", true}}, {{"id", "mode"}, {"type", "WORK_MODE"}}}}}}}};
        } else {
            return;
        }
        (void)transport_->publish({*reply, body.dump(), 1, false});
    }

    std::string dev_;
    std::unique_ptr<Transport> transport_;
};

std::unique_ptr<Client> connect(const MosquittoBroker& broker, const std::string& ex) {
    MqttOptions mqtt;
    mqtt.broker_url = broker.url();
    ClientOptions o;
    o.ex_cid = ex;
    o.default_timeout = 300ms;
    auto client = Client::create(std::move(mqtt), o);
    REQUIRE(client.ok());
    auto outcome = (*client)->connect(10s);
    REQUIRE(outcome.ok());
    CHECK(outcome->kind == RegisterOutcome::Kind::no_answer);  // no agent on a bare broker
    return std::move(client).value();
}

}  // namespace

TEST_CASE("query, set, probe and state through mosquitto") {
    MosquittoBroker broker;
    ScriptedAdapter adapter(broker, "dev1");
    auto client = connect(broker, "app1");
    // The client's 300 ms default is for the answers that never come (the
    // registration without an agent, the silent device below); the answers
    // that do come get room for a loaded machine (one failed under TSan with
    // the suite running two tests at once).
    RequestOptions patient;
    patient.timeout = 10s;

    auto query = client->query("dev1", {{"a", std::nullopt}, {"nope", std::nullopt}}, patient);
    REQUIRE(query.ok());
    REQUIRE(query->size() == 2);
    CHECK(*(*query)[0].values == Json::array({"v-a"}));
    CHECK((*query)[1].status.error == 401);
    auto set = client->set("dev1", {SetItem{"a", Json{{"value", 1}}, std::nullopt, std::nullopt}}, patient);
    REQUIRE(set.ok());
    CHECK((*set)[0].status.ok);
    auto model = client->probe("dev1", patient);
    REQUIRE(model.ok());
    CHECK((*model)["id"] == "root");

    std::mutex mutex;
    std::vector<std::string> states;
    REQUIRE(client
                ->subscribe_state("dev1",
                                  [&](const NotifyState& s) {
                                      std::lock_guard<std::mutex> lock(mutex);
                                      states.push_back(s.state);
                                  })
                .ok());
    REQUIRE(eventually([&] {
        std::lock_guard<std::mutex> lock(mutex);
        return !states.empty();
    }));
    CHECK(states.front() == "online");

    std::atomic<int> samples{0};
    REQUIRE(client->subscribe_samples("dev1", [&](const SampleDtu&) { ++samples; }).ok());
    // The subscription reaches the broker asynchronously: publish until one arrives.
    REQUIRE(eventually([&] {
        adapter.publish_sample(1000);
        std::this_thread::sleep_for(20ms);
        return samples > 0;
    }));

    auto silent = client->query("nobody", {{"a", std::nullopt}});
    REQUIRE_FALSE(silent.ok());
    CHECK(silent.error().code == ErrorCode::timeout);
}

TEST_CASE("the nclink device commands: output and exit codes") {
    if (!cli_built()) {
        WARN("bin/nclink not built (target nclink_cli); skipping");
        return;
    }
    MosquittoBroker broker;
    ScriptedAdapter adapter(broker, "dev1");
    const std::string common =
        "--broker " + broker.url() + " --device dev1 --timeout 10000 ";  // generous: CI runs tests in parallel on 2 cores

    auto q = run_cli("query " + common + "a nope");
    CHECK(q.status == 1);
    CHECK(q.out == "a = \"v-a\"\nnope: NG 401 Node not exists\n");
    auto ok = run_cli("query " + common + "--json a");
    CHECK(ok.status == 0);
    CHECK(Json::parse(ok.out)[0]["values"] == Json::array({"v-a"}));
    auto s = run_cli("set " + common + "'a=5' 'b:{\"value\":\"x\"}'");
    CHECK(s.status == 0);
    CHECK(s.out == "a: OK\nb: OK\n");
    auto p = run_cli("probe " + common);
    CHECK(p.status == 0);
    CHECK(p.out.find("channel ch1  sample every 10 ms, upload every 100 ms  [pos, mode]") != std::string::npos);
    CHECK(p.out.find("item pos  POSITION  setable") != std::string::npos);
    CHECK(p.out.find("item mode  WORK_MODE") != std::string::npos);
    auto st = run_cli("state " + common);
    CHECK(st.status == 0);
    CHECK(st.out == "dev1: online\n");
    {
        std::atomic<bool> done{false};
        std::thread publisher([&] {
            // A new beginTime each time: the client drops a repeated Sample
            // DTU as a duplicate delivery (docs/delivery.md).
            for (std::int64_t k = 0; !done; ++k) {
                adapter.publish_sample(1700000000123 + 1000 * k);
                std::this_thread::sleep_for(20ms);
            }
        });
        auto w = run_cli("watch " + common + "--count 2");
        done = true;
        publisher.join();
        CHECK(w.status == 0);
        CHECK(w.out.find("pos") != std::string::npos);
        CHECK(w.out.find("mode") != std::string::npos);
        // beginTime 1700000000123 (22:13:20.123Z) + k s: the hour holds for
        // k < 2800, whatever the tool's start-up costs on a loaded machine.
        CHECK(w.out.find("2023-11-14T22:") != std::string::npos);
        CHECK(w.out.find(".123Z") != std::string::npos);
        CHECK(w.out.find("\"a\"") != std::string::npos);  // latest non-null value of "mode"
    }
    auto silent = run_cli("query --broker " + broker.url() + " --device nobody --timeout 200 a");
    CHECK(silent.status == 1);
    CHECK(run_cli("query " + common).status == 2);  // no ID
    CHECK(run_cli("query --device dev1 --bogus a").status == 2);
    CHECK(run_cli("state --broker " + broker.url()).status == 2);  // no --device
}
