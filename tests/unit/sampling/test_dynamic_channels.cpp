// Dynamic sampling (8.2.17-8.2.21) through a whole adapter on the loopback
// broker: Register/Sample and Unregister/Sample requests on the wire, the
// answers of table 19, data on Sample/{dev}/{ex}/{channel}, release of a
// gone application's channels.
#include "support/adapter_fixture.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::test;

namespace {

constexpr const char* kDev = "test-dev";

struct DynamicFixture : AdapterFixture {
    explicit DynamicFixture(AdapterConfig extra = {}) : AdapterFixture(std::move(extra)) {}
    // Stop with fake time moving: the engine's two threads share one
    // PollingSleeper whose single wake flag one of them can consume for the
    // other, which then sleeps until the ManualClock reaches its deadline.
    ~DynamicFixture() {
        std::atomic<bool> stopped{false};
        std::thread ticker([&] {
            while (!stopped) {
                clock->advance(std::chrono::milliseconds(20));
                std::this_thread::sleep_for(std::chrono::milliseconds(1));
            }
        });
        if (adapter) adapter->stop();
        stopped = true;
        ticker.join();
    }

    Json register_sampling(const Json& ids, double sample_ms, double upload_ms, const std::string& ex = "app",
                           const Json& extra = Json::object()) {
        Json request{{"@id", "r" + std::to_string(++counter)},
                     {"guid", kDev},
                     {"sampleInterval", sample_ms},
                     {"uploadInterval", upload_ms},
                     {"ids", ids}};
        for (auto it = extra.begin(); it != extra.end(); ++it) request[it.key()] = it.value();
        return app->request(topics::sample_register_request(kDev, ex), topics::sample_register_response(kDev, ex), request);
    }
    Json unregister_sampling(const std::string& channel, const std::string& ex = "app") {
        return app->request(topics::sample_unregister_request(kDev, ex), topics::sample_unregister_response(kDev, ex),
                            Json{{"@id", "u" + std::to_string(++counter)}, {"guid", kDev}, {"id", channel}});
    }
    Json dynamic_stats() { return adapter->stats().features.at("sampling").at("dynamic"); }
    /// Moves fake time on until a DTU arrives on `topic` (the engine polls the clock).
    Json wait_sample(const std::string& topic, std::size_t n = 1) {
        REQUIRE(eventually([&] {
            clock->advance(std::chrono::milliseconds(10));
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            return app->on(topic).size() >= n;
        }));
        return Json::parse(app->on(topic)[n - 1].payload);
    }
};

Json ids(std::initializer_list<const char*> list) {
    Json out = Json::array();
    for (const char* id : list) out.push_back(Json{{"id", id}});
    return out;
}

void check_ng(const Json& reply, ErrorCode code) {
    INFO(reply.dump());
    CHECK(reply["code"] == "NG");
    CHECK(reply["error"] == to_int(code));
    CHECK(reply["reason"] == std::string(reason(code)));
    CHECK(reply["guid"] == kDev);
}

}  // namespace

TEST_CASE("dynamic channel is registered answered in both spellings and publishes on its topic") {
    DynamicFixture f;
    const Json reply = f.register_sampling(ids({"pos", "ovr"}), 10, 50);
    INFO(reply.dump());
    REQUIRE(reply["code"] == "OK");
    CHECK(reply["guid"] == kDev);
    CHECK(reply["@id"] == "r1");
    const std::string channel = reply["id"].get<std::string>();
    CHECK(channel.size() <= 16);
    // The standard's misprinted response topic gets the same answer (docs/wire.md).
    REQUIRE(eventually([&] { return !f.app->on("Reigster/Sample/Response/test-dev/app").empty(); }));
    CHECK(Json::parse(f.app->on("Reigster/Sample/Response/test-dev/app")[0].payload) == reply);

    // Fake time moves on whether or not the sampling thread has run: under a
    // loaded emulator (qemu) a tick can come due while an older one waits,
    // and that overrun's row is null by design (docs/sampling.md). The first
    // DTU whose rows were all read shows the driver's values.
    const auto all_read = [](const Json& d) {
        for (const auto& row : d["data"])
            for (const auto& v : row["data"])
                if (v.is_null()) return false;
        return true;
    };
    Json dtu;
    for (std::size_t n = 1; n <= 50; ++n)
        if (all_read(dtu = f.wait_sample(topics::dynamic_sample(kDev, "app", channel), n))) break;
    CHECK(dtu["guid"] == kDev);
    CHECK(dtu["id"] == channel);
    REQUIRE(dtu["data"].size() == 2);
    CHECK(dtu["data"][0]["data"][0] == 12.5);
    CHECK(dtu["data"][1]["data"][0] == 100);

    const Json stats = f.dynamic_stats();
    CHECK(stats["channels"] == 1);
    CHECK(stats["owners"][channel] == "app");
    CHECK(stats["registered"] == 1);
}

TEST_CASE("dynamic channel ids are unique and never reused") {
    DynamicFixture f;
    const std::string a = f.register_sampling(ids({"pos"}), 10, 10)["id"];
    const std::string b = f.register_sampling(ids({"pos"}), 10, 10)["id"];
    CHECK(a != b);
    REQUIRE(f.unregister_sampling(a)["code"] == "OK");
    const std::string c = f.register_sampling(ids({"pos"}), 10, 10)["id"];
    CHECK(c != a);
    CHECK(c != b);
    CHECK(c != "ch1");
}

TEST_CASE("dynamic registration refuses unknown ids configs and empty ids") {
    DynamicFixture f;
    check_ng(f.register_sampling(ids({"pos", "nope"}), 10, 10), ErrorCode::node_not_exists);
    check_ng(f.register_sampling(ids({"feed_ovr_cfg"}), 10, 10), ErrorCode::node_not_exists);  // configs are never sampled
    check_ng(f.register_sampling(ids({"ch1"}), 10, 10), ErrorCode::node_not_exists);           // a channel is no data item
    check_ng(f.register_sampling(Json::array(), 10, 10), ErrorCode::parameter_missing);
    CHECK(f.dynamic_stats()["channels"] == 0);
    CHECK(f.dynamic_stats()["refused"] == 4);
}

TEST_CASE("dynamic registration refuses intervals that cannot work with 411") {
    DynamicFixture f;
    check_ng(f.register_sampling(ids({"pos"}), 0, 10), ErrorCode::attribute_error);
    check_ng(f.register_sampling(ids({"pos"}), -5, 10), ErrorCode::attribute_error);
    check_ng(f.register_sampling(ids({"pos"}), 10, 0), ErrorCode::attribute_error);
    check_ng(f.register_sampling(ids({"pos"}), 20, 10), ErrorCode::attribute_error);  // upload < sample
    CHECK(f.register_sampling(ids({"pos"}), 20, 20)["code"] == "OK");                 // equal is fine
    CHECK(f.dynamic_stats()["channels"] == 1);
}

TEST_CASE("dynamic registration answers malformed requests with the codec's code") {
    DynamicFixture f;
    const std::string reply_topic = topics::sample_register_response(kDev, "app");
    auto send_raw = [&](const std::string& payload) {
        const std::size_t before = f.app->on(reply_topic).size();
        f.app->send(topics::sample_register_request(kDev, "app"), payload);
        return f.app->wait(reply_topic, before + 1);
    };
    check_ng(send_raw("{not json"), ErrorCode::syntax_error);
    check_ng(send_raw(R"({"@id":"m1","guid":"test-dev","sampleInterval":10,"uploadInterval":10})"), ErrorCode::parameter_missing);
    const Json wrong_type =
        send_raw(R"({"@id":"m2","guid":"test-dev","sampleInterval":"fast","uploadInterval":10,"ids":[{"id":"pos"}]})");
    check_ng(wrong_type, ErrorCode::value_type);
    CHECK(wrong_type["@id"] == "m2");
}

TEST_CASE("dynamic registration without an application id in the topic is refused with 414") {
    DynamicFixture f;
    const Json reply =
        f.app->request(topics::sample_register_request(kDev), topics::sample_register_response(kDev),
                       Json{{"@id", "x1"}, {"guid", kDev}, {"sampleInterval", 10}, {"uploadInterval", 10}, {"ids", ids({"pos"})}});
    check_ng(reply, ErrorCode::unsupported_terminal_id);
    CHECK(reply["@id"] == "x1");
}

TEST_CASE("dynamic registration answers 415 beyond max_dynamic_channels") {
    AdapterConfig config;
    config.sampling.max_dynamic_channels = 2;
    DynamicFixture f(config);
    const std::string a = f.register_sampling(ids({"pos"}), 10, 10)["id"];
    REQUIRE(f.register_sampling(ids({"pos"}), 10, 10, "other")["code"] == "OK");
    check_ng(f.register_sampling(ids({"pos"}), 10, 10), ErrorCode::insufficient_dynamic_sampling);
    REQUIRE(f.unregister_sampling(a)["code"] == "OK");
    CHECK(f.register_sampling(ids({"pos"}), 10, 10)["code"] == "OK");
}

TEST_CASE("dynamic unregistration refuses unknown model and foreign channels") {
    DynamicFixture f;
    const std::string mine = f.register_sampling(ids({"pos"}), 10, 10)["id"];
    check_ng(f.unregister_sampling("dyn999"), ErrorCode::node_not_exists);
    check_ng(f.unregister_sampling("ch1"), ErrorCode::permission_denied);  // a model channel
    check_ng(f.unregister_sampling(mine, "intruder"), ErrorCode::permission_denied);
    // Without an ex_cid nobody can prove ownership.
    const Json anonymous = f.app->request(topics::sample_unregister_request(kDev), topics::sample_unregister_response(kDev),
                                          Json{{"@id", "a1"}, {"guid", kDev}, {"id", mine}});
    check_ng(anonymous, ErrorCode::permission_denied);
    CHECK(f.dynamic_stats()["channels"] == 1);
    // Also answered on the misprinted topic.
    REQUIRE(eventually([&] { return !f.app->on("Unreigster/Sample/Response/test-dev/app").empty(); }));

    const Json ok = f.unregister_sampling(mine);
    CHECK(ok["code"] == "OK");
    CHECK(ok["guid"] == kDev);
    CHECK(f.dynamic_stats()["channels"] == 0);
    check_ng(f.unregister_sampling(mine), ErrorCode::node_not_exists);  // only once
}

TEST_CASE("dynamic channel stops publishing after unregistration") {
    DynamicFixture f;
    const std::string channel = f.register_sampling(ids({"pos"}), 10, 20)["id"];
    const std::string topic = topics::dynamic_sample(kDev, "app", channel);
    f.wait_sample(topic);
    REQUIRE(f.unregister_sampling(channel)["code"] == "OK");
    // The rows sampled before the removal still go out; then nothing.
    REQUIRE(eventually([&] {
        const auto list = f.adapter->stats().features.at("sampling").at("channels");
        for (const auto& c : list)
            if (c["id"] == channel) return false;
        return true;
    }));
    // The last DTU left the uploader when the channel left the statistics;
    // the loopback broker may still be delivering it: wait until the count
    // holds still, then move time on.
    std::size_t after = f.app->on(topic).size();
    REQUIRE(eventually([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        const std::size_t now = f.app->on(topic).size();
        const bool still = now == after;
        after = now;
        return still;
    }));
    for (int i = 0; i < 20; ++i) {
        f.clock->advance(std::chrono::milliseconds(10));
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    CHECK(f.app->on(topic).size() == after);
}

TEST_CASE("dynamic channels of an application that goes offline are released") {
    DynamicFixture f;
    const std::string a1 = f.register_sampling(ids({"pos"}), 10, 10, "app")["id"];
    const std::string a2 = f.register_sampling(ids({"ovr"}), 10, 10, "app")["id"];
    const std::string b1 = f.register_sampling(ids({"pos"}), 10, 10, "other")["id"];
    f.app->send(topics::notify_state("app"), R"({"tid":"app","state":"offline"})");
    REQUIRE(eventually([&] { return f.dynamic_stats()["channels"] == 1; }));
    const Json stats = f.dynamic_stats();
    CHECK(stats["owners"].contains(b1));
    CHECK(stats["released"] == 2);
    check_ng(f.unregister_sampling(a1), ErrorCode::node_not_exists);
}

TEST_CASE("dynamic channels of a silent application are released after the lease") {
    AdapterConfig config;
    config.application_lease = std::chrono::milliseconds(1000);
    DynamicFixture f(config);
    f.register_sampling(ids({"pos"}), 10, 10, "quiet");
    f.register_sampling(ids({"pos"}), 10, 10, "chatty");
    REQUIRE(f.dynamic_stats()["channels"] == 2);
    for (int i = 0; i < 8; ++i) {
        f.clock->advance(std::chrono::milliseconds(250));
        // "chatty" keeps sending DTUs (any request renews the lease).
        f.query(Json::array({"pos"}), "chatty");
    }
    REQUIRE(eventually([&] { return f.dynamic_stats()["channels"] == 1; }));
    CHECK(f.dynamic_stats()["owners"].begin().value() == "chatty");
}

TEST_CASE("dynamic channel Sample DTUs default to QoS 1 and may ask for QoS 0 through privateInfo") {
    DynamicFixture f;
    const Json reply = f.register_sampling(ids({"pos"}), 10, 10, "app", Json{{"privateInfo", {{"qos", 0}}}});
    REQUIRE(reply["code"] == "OK");
    const std::string topic = topics::dynamic_sample(kDev, "app", reply["id"].get<std::string>());
    f.wait_sample(topic);
    CHECK(f.app->on(topic)[0].qos == 0);  // the loopback delivers min(publish, subscription) QoS
    const Json plain = f.register_sampling(ids({"pos"}), 10, 10);
    const std::string plain_topic = topics::dynamic_sample(kDev, "app", plain["id"].get<std::string>());
    f.wait_sample(plain_topic);
    CHECK(f.app->on(plain_topic)[0].qos == 1);  // sampling.qos, default 1
}
