// Samples, state and version notifications delivered through the client.
#include "fake_adapter.hpp"

#include <atomic>
#include <chrono>
#include <mutex>

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::eventually;
using nclink::test::FakeAdapter;
using nclink::test::make_client;
using nclink::test::reply_to;

namespace {

template <class T>
struct Collected {
    std::mutex mutex;
    std::vector<T> items;
    void add(const T& t) {
        std::lock_guard<std::mutex> lock(mutex);
        items.push_back(t);
    }
    std::size_t size() {
        std::lock_guard<std::mutex> lock(mutex);
        return items.size();
    }
    std::vector<T> get() {
        std::lock_guard<std::mutex> lock(mutex);
        return items;
    }
};

Message sample(const std::string& dev, const std::string& channel, std::int64_t begin, std::vector<Json> data) {
    SampleDtu dtu;
    dtu.guid = dev;
    dtu.id = channel;
    dtu.begin_time = begin;
    dtu.data = std::move(data);
    return {topics::sample(dev, channel), encode(dtu), 0, false};
}

}  // namespace

TEST_CASE("sample DTUs of a device reach the handler decoded, in order") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", nullptr);
    auto client = make_client(broker, "app1");
    Collected<SampleDtu> got;
    auto sub = client->subscribe_samples("dev1", [&](const SampleDtu& s) { got.add(s); });
    REQUIRE(sub.ok());
    adapter.publish(sample("dev1", "ch1", 1000, {Json::array({1, 2}), Json::array({"a", nullptr})}));
    adapter.publish({"Sample/dev1/ch2", "garbage", 0, false});
    adapter.publish(sample("dev1", "ch2", 2000, {Json::array({3})}));
    adapter.publish(sample("dev2", "ch1", 3000, {Json::array({4})}));  // another device
    REQUIRE(eventually([&] { return got.size() == 2; }));
    REQUIRE(eventually([&] { return client->stats().malformed == 1; }));
    const auto samples = got.get();
    CHECK(samples[0].id == "ch1");
    CHECK(samples[0].guid == "dev1");
    CHECK(samples[0].begin_time == 1000);
    CHECK(samples[0].data.at(1) == Json::array({"a", nullptr}));
    CHECK(samples[1].id == "ch2");
    CHECK(client->stats().samples == 2);

    REQUIRE(client->unsubscribe(*sub).ok());
    CHECK_FALSE(client->unsubscribe(*sub).ok());
    adapter.publish(sample("dev1", "ch1", 4000, {Json::array({5})}));
    REQUIRE(eventually([&] { return broker.routed() >= 5; }));
    std::this_thread::sleep_for(50ms);
    CHECK(got.size() == 2);
}

TEST_CASE("a channel subscription sees only its channel and two handlers both see a shared filter") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", nullptr);
    auto client = make_client(broker, "app1");
    Collected<std::string> one, all_a, all_b;
    REQUIRE(client
                ->subscribe_samples(
                    "dev1", [&](const SampleDtu& s) { one.add(s.id); }, std::string("ch2"))
                .ok());
    auto a = client->subscribe_samples("dev1", [&](const SampleDtu& s) { all_a.add(s.id); });
    REQUIRE(client->subscribe_samples("dev1", [&](const SampleDtu& s) { all_b.add(s.id); }).ok());
    adapter.publish(sample("dev1", "ch1", 1, {Json::array({1})}));
    adapter.publish(sample("dev1", "ch2", 2, {Json::array({2})}));
    REQUIRE(eventually([&] { return all_a.size() == 2 && all_b.size() == 2 && one.size() == 1; }));
    CHECK(one.get() == std::vector<std::string>{"ch2"});
    // Removing one of two handlers of a filter keeps the broker subscription.
    REQUIRE(client->unsubscribe(*a).ok());
    adapter.publish(sample("dev1", "ch1", 3, {Json::array({3})}));
    REQUIRE(eventually([&] { return all_b.size() == 3; }));
    CHECK(all_a.size() == 2);
    CHECK_FALSE(client->subscribe_samples("dev/x", [](const SampleDtu&) {}).ok());
}

TEST_CASE("the retained state arrives on subscribe, then changes follow") {
    LoopbackBroker broker;
    Message will{topics::notify_state("dev1"), R"({"tid":"dev1","state":"offline"})", 1, true};
    FakeAdapter adapter(broker, "dev1", nullptr, {}, will);
    adapter.publish({topics::notify_state("dev1"), R"({"tid":"dev1","state":"online"})", 1, true});
    REQUIRE(eventually([&] { return broker.retained(topics::notify_state("dev1")).has_value(); }));

    auto client = make_client(broker, "app1");
    Collected<NotifyState> states;
    REQUIRE(client->subscribe_state("dev1", [&](const NotifyState& s) { states.add(s); }).ok());
    REQUIRE(eventually([&] { return states.size() == 1; }));
    CHECK(states.get()[0].state == "online");
    CHECK(states.get()[0].tid == "dev1");

    // Abnormal disconnect: the broker publishes the will. (drop_client
    // reconnects it; the fake does not announce itself again.)
    REQUIRE(broker.drop_client("adapter-dev1"));
    REQUIRE(eventually([&] { return states.size() == 2; }));
    CHECK(states.get()[1].state == "offline");

    // A second handler gets the current state too.
    Collected<NotifyState> late;
    REQUIRE(client->subscribe_state("dev1", [&](const NotifyState& s) { late.add(s); }).ok());
    REQUIRE(eventually([&] { return late.size() == 1; }));
    CHECK(late.get()[0].state == "offline");
}

TEST_CASE("version notifications reach the handler and a state without tid gets it from the topic") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", nullptr);
    auto client = make_client(broker, "app1");
    Collected<ProbeVersionRequest> versions;
    Collected<NotifyState> states;
    REQUIRE(client->subscribe_version("dev1", [&](const ProbeVersionRequest& v) { versions.add(v); }).ok());
    REQUIRE(client->subscribe_state("dev1", [&](const NotifyState& s) { states.add(s); }).ok());
    adapter.publish({topics::probe_version("dev1"), R"({"@id":"v1","guid":"dev1","version":"1.2.0"})", 1, false});
    adapter.publish({topics::notify_state("dev1"), R"({"state":"online"})", 1, false});
    REQUIRE(eventually([&] { return versions.size() == 1 && states.size() == 1; }));
    CHECK(versions.get()[0].version == "1.2.0");
    CHECK(states.get()[0].tid == "dev1");
    CHECK(client->stats().notifications == 2);
}

TEST_CASE("a handler may unsubscribe itself and make async requests") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
    auto client = make_client(broker, "app1");
    std::atomic<int> calls{0};
    std::atomic<bool> answered{false};
    std::atomic<SubscriptionId> id{0};
    std::atomic<bool> unsubscribed{false};
    // No Catch assertions here: they are not thread-safe.
    auto sub = client->subscribe_samples("dev1", [&](const SampleDtu&) {
        ++calls;
        unsubscribed = client->unsubscribe(id).ok();
        client->query_async("dev1", {QueryItem{"a", std::nullopt}}, [&](auto r) { answered = r.ok(); });
    });
    REQUIRE(sub.ok());
    id = *sub;
    adapter.publish(sample("dev1", "ch1", 1, {Json::array({1})}));
    adapter.publish(sample("dev1", "ch1", 2, {Json::array({2})}));
    REQUIRE(eventually([&] { return answered.load(); }));
    std::this_thread::sleep_for(30ms);
    CHECK(calls == 1);
    CHECK(unsubscribed);
}

namespace {

Message method_status(const std::string& dev, const std::string& ex, const std::string& call, const std::string& method,
                      const std::string& status, double progress) {
    return {topics::method_status(dev, ex),
            Json{{"@id", call}, {"guid", dev}, {"id", method}, {"status", status}, {"progress", progress}}.dump(), 1, false};
}

Message method_result(const std::string& dev, const std::string& ex, const std::string& call, const std::string& method,
                      const std::string& result) {
    return {topics::method_result(dev, ex),
            Json{{"@id", call}, {"guid", dev}, {"id", method}, {"result", result}, {"code", "OK"}, {"return", {{"n", 3}}}}.dump(),
            1, false};
}

Message event_dtu(const std::string& dev, const std::string& ex, const std::string& msg_id, const std::string& event_id,
                  const std::string& item, Json value) {
    return {
        topics::event(dev, ex),
        Json{{"@id", msg_id}, {"guid", dev}, {"id", event_id}, {"time", 1700000000000LL}, {"event", {{"id", item}, {"value", value}}}}
            .dump(),
        1, false};
}

}  // namespace

TEST_CASE("method runs of every caller at a device reach subscribe_method_runs decoded, naming caller and kind") {
    LoopbackBroker broker;
    // The adapter answers this client's own call with a status and the result.
    FakeAdapter adapter(broker, "dev1", [](const Message& request) -> std::vector<Message> {
        const auto topic = parse_topic(request.topic);
        if (!topic || topic->kind != TopicKind::method_call) return {};
        const Json call = Json::parse(request.payload);
        const std::string id = call["@id"].get<std::string>();
        return {method_status("dev1", *topic->ex, id, call["id"], "executing", 50),
                method_result("dev1", *topic->ex, id, call["id"], "finished")};
    });
    auto client = make_client(broker, "dash");
    Collected<MethodRun> runs;
    auto sub = client->subscribe_method_runs("dev1", [&](const MethodRun& r) { runs.add(r); });
    REQUIRE(sub.ok());
    CHECK_FALSE(client->subscribe_method_runs("dev/1", [](const MethodRun&) {}).ok());

    // Another application's call: its status and result, and the result again (a QoS 1 repeat).
    adapter.publish(method_status("dev1", "mes", "c-7", "G_HOME", "executing", 25));
    adapter.publish(method_result("dev1", "mes", "c-7", "G_HOME", "finished"));
    adapter.publish(method_result("dev1", "mes", "c-7", "G_HOME", "finished"));
    adapter.publish({topics::method_status("dev1", "mes"), "{not json", 1, false});
    adapter.publish({topics::method_result("dev1", "mes"), Json{{"@id", "c-8"}}.dump(), 1, false});  // no result
    adapter.publish(method_result("dev2", "mes", "c-9", "G_HOME", "finished"));                      // another device
    REQUIRE(eventually([&] { return runs.size() == 2 && client->stats().malformed == 2; }));
    auto got = runs.get();
    CHECK(got[0].kind == MethodRun::Kind::status);
    CHECK(got[0].dev == "dev1");
    CHECK(got[0].ex == "mes");
    REQUIRE(got[0].status);
    CHECK_FALSE(got[0].result);
    CHECK(got[0].status->id == "G_HOME");
    CHECK(got[0].status->status == "executing");
    CHECK(got[0].status->progress == 25);
    CHECK(got[0].status->msg_id == Json("c-7"));
    CHECK(got[1].kind == MethodRun::Kind::result);
    REQUIRE(got[1].result);
    CHECK(got[1].result->result == "finished");
    CHECK(got[1].result->return_value == Json{{"n", 3}});
    CHECK(to_string(got[1].kind) == "result");

    // This client's own call still completes (status to on_status, result
    // to done), and the watcher sees it too, with ex = this client.
    std::atomic<int> statuses{0};
    auto result = client->call_method("dev1", "G_STOP", nullptr, [&](const MethodStatus&) { ++statuses; });
    REQUIRE(result.ok());
    CHECK(result->result == "finished");
    CHECK(statuses == 1);
    REQUIRE(eventually([&] { return runs.size() == 4; }));
    got = runs.get();
    CHECK(got[2].ex == "dash");
    CHECK(got[2].kind == MethodRun::Kind::status);
    CHECK(got[3].ex == "dash");
    CHECK(got[3].result->id == "G_STOP");
    CHECK(client->stats().unmatched_responses == 0);

    REQUIRE(client->unsubscribe(*sub).ok());
    adapter.publish(method_result("dev1", "mes", "c-10", "G_HOME", "finished"));
    const auto routed = broker.routed();
    REQUIRE(eventually([&] { return broker.routed() >= routed; }));
    std::this_thread::sleep_for(50ms);
    CHECK(runs.size() == 4);
}

TEST_CASE("event DTUs of every registration at a device reach subscribe_events, own registrations still routed") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& request) -> std::vector<Message> {
        const auto topic = parse_topic(request.topic);
        if (!topic || topic->kind != TopicKind::event_register_request) return {};
        return {reply_to(request, {{"code", "OK"}, {"id", "ev-own"}}, "dev1")};
    });
    auto client = make_client(broker, "dash");
    Collected<WatchedEvent> watched;
    REQUIRE(client->subscribe_events("dev1", [&](const WatchedEvent& e) { watched.add(e); }).ok());
    Collected<std::string> own;
    Client::EventRegistration registration;
    registration.id = "spindle_speed";
    auto id = client->register_event("dev1", registration, [&](const EventData& e) { own.add(e.id); });
    REQUIRE(id.ok());
    CHECK(*id == "ev-own");

    adapter.publish(event_dtu("dev1", "mes", "m-1", "ev-3", "feed_override", 120));
    adapter.publish(event_dtu("dev1", "mes", "m-1", "ev-3", "feed_override", 120));  // a QoS 1 repeat
    adapter.publish({topics::event("dev1", "mes"), "[]", 1, false});
    adapter.publish(event_dtu("dev2", "mes", "m-2", "ev-4", "feed_override", 90));  // another device
    adapter.publish(event_dtu("dev1", "dash", "m-3", "ev-own", "spindle_speed", 8000));
    REQUIRE(eventually([&] { return watched.size() == 2 && own.size() == 1; }));
    REQUIRE(eventually([&] { return client->stats().malformed == 1; }));
    const auto got = watched.get();
    CHECK(got[0].dev == "dev1");
    CHECK(got[0].ex == "mes");
    CHECK(got[0].event.id == "ev-3");
    CHECK(got[0].event.event.id == "feed_override");
    CHECK(got[0].event.event.value == Json(120));
    CHECK(got[1].ex == "dash");
    CHECK(got[1].event.id == "ev-own");
    CHECK(own.get().front() == "ev-own");
    CHECK(client->stats().unmatched_responses == 0);  // other applications' events are not ours to route
}
