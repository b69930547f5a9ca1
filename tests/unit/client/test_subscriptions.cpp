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
    REQUIRE(client->subscribe_samples("dev1", [&](const SampleDtu& s) { one.add(s.id); }, std::string("ch2")).ok());
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
