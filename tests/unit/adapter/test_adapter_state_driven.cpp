// The state-machine table drives the adapter: what goes out, and in which order,
// follows the row of (state, event). A scripted transport lets the test take
// the link down and refuse publishes while requests still arrive, which a
// real broker cannot arrange.
#include "support/adapter_fixture.hpp"

#include <deque>
#include <fstream>

using namespace nclink;
using namespace nclink::test;

namespace {

/// Records what is published; the test decides the link state and whether
/// publishes succeed, and delivers requests straight to the adapter.
class ScriptedTransport final : public Transport {
public:
    struct Shared {
        std::mutex mutex;
        std::vector<Message> sent;
        bool refuse = false;
        LinkState link = LinkState::disconnected;
        MessageHandler on_message;
        LinkStateHandler on_state;
    };
    explicit ScriptedTransport(std::shared_ptr<Shared> shared) : s_(std::move(shared)) {}

    void set_message_handler(MessageHandler h) override { s_->on_message = std::move(h); }
    void set_state_handler(LinkStateHandler h) override { s_->on_state = std::move(h); }
    Result<void> start() override { return ok_result(); }
    void stop(std::chrono::milliseconds) override {}
    Result<void> publish(Message m) override {
        std::lock_guard<std::mutex> lock(s_->mutex);
        if (s_->refuse) return make_error(ErrorCode::unavailable, "refused by the test");
        s_->sent.push_back(std::move(m));
        return ok_result();
    }
    Result<void> subscribe(std::vector<std::string>, int) override { return ok_result(); }
    Result<void> unsubscribe(std::vector<std::string>) override { return ok_result(); }
    LinkState state() const override {
        std::lock_guard<std::mutex> lock(s_->mutex);
        return s_->link;
    }
    TransportStats stats() const override { return {}; }
    bool flush(std::chrono::milliseconds) override { return true; }

private:
    std::shared_ptr<Shared> s_;
};

struct Driven {
    Driven() {
        config.model_path = test_model_path();
        config.persistence_dir = scratch_dir("adapter-driven");
        config.register_timeout = std::chrono::milliseconds(60000);
        adapter = std::make_unique<Adapter>(config, driver);
        adapter->use_transport(std::make_unique<ScriptedTransport>(link));
        REQUIRE(adapter->start().ok());
    }
    ~Driven() {
        adapter->stop(std::chrono::milliseconds(0));
        std::error_code ec;
        std::filesystem::remove_all(config.persistence_dir, ec);
    }
    void set_link(LinkState state) {
        {
            std::lock_guard<std::mutex> lock(link->mutex);
            link->link = state;
        }
        link->on_state(state, "test");
    }
    void refuse(bool on) {
        std::lock_guard<std::mutex> lock(link->mutex);
        link->refuse = on;
    }
    void query(const std::string& id) {
        link->on_message(Message{"Query/Request/test-dev/app",
                                 Json{{"@id", id}, {"guid", "test-dev"}, {"ids", Json::array({Json{{"id", "pos"}}})}}.dump(), 1,
                                 false});
    }
    std::vector<std::string> topics() {
        std::lock_guard<std::mutex> lock(link->mutex);
        std::vector<std::string> out;
        for (const auto& m : link->sent) out.push_back(m.topic);
        return out;
    }
    std::size_t count(const std::string& topic) {
        std::size_t n = 0;
        for (const auto& t : topics()) n += t == topic;
        return n;
    }
    std::ptrdiff_t first(const std::string& topic) {
        const auto all = topics();
        for (std::size_t i = 0; i < all.size(); ++i)
            if (all[i] == topic) return static_cast<std::ptrdiff_t>(i);
        return -1;
    }

    AdapterConfig config;
    std::shared_ptr<FakeDriver> driver = std::make_shared<FakeDriver>();
    std::shared_ptr<ScriptedTransport::Shared> link = std::make_shared<ScriptedTransport::Shared>();
    std::unique_ptr<Adapter> adapter;
};

const std::string kResponse = "Query/Response/test-dev/app";

}  // namespace

TEST_CASE("adapter driven: before the first connection responses are kept, then sent after the announcement (79, 81, 8.3.6)") {
    Driven d;
    CHECK(d.adapter->state() == AdapterState::disconnected);
    d.query("q1");
    // Handled, and kept: nothing reaches the link while it is down.
    REQUIRE(eventually([&] { return d.adapter->stats().requests >= 1; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    CHECK(d.count(kResponse) == 0);
    d.set_link(LinkState::connected);
    CHECK(d.adapter->state() == AdapterState::normal);
    REQUIRE(eventually([&] { return d.count(kResponse) == 1; }));
    // The row's order: online state, registration, version, then what was kept.
    const auto online = d.first("Notify/State/test-dev"), reg = d.first("Register/Request"),
               version = d.first("Probe/Version/test-dev"), response = d.first(kResponse);
    REQUIRE(online >= 0);
    CHECK(online < reg);
    CHECK(reg < version);
    CHECK(version < response);
}

TEST_CASE("adapter driven: normal answers at once (69), a lost link keeps answers until it is back (70, 79, 81)") {
    Driven d;
    d.set_link(LinkState::connected);
    d.query("q1");
    REQUIRE(eventually([&] { return d.count(kResponse) == 1; }));
    CHECK(d.adapter->state() == AdapterState::normal);

    d.set_link(LinkState::disconnected);
    CHECK(d.adapter->state() == AdapterState::disconnected);
    CHECK(d.adapter->stats().state == AdapterState::disconnected);
    CHECK(to_json(d.adapter->stats())["state"] == "disconnected");
    d.query("q2");
    REQUIRE(eventually([&] { return d.adapter->stats().requests >= 2; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    CHECK(d.count(kResponse) == 1);
    const auto registrations = d.count("Register/Request");
    d.set_link(LinkState::connected);
    REQUIRE(eventually([&] { return d.count(kResponse) == 2; }));
    CHECK(d.count("Register/Request") == registrations + 1);  // registers again on reconnection (8.3.6)
}

TEST_CASE("adapter driven: a response the link refuses moves to request state and is tried again (69, 74, retry)") {
    Driven d;
    d.set_link(LinkState::connected);
    d.refuse(true);
    d.query("q1");
    REQUIRE(eventually([&] { return d.adapter->state() == AdapterState::request; }));
    d.query("q2");  // 74: handled in the request state, refused again, kept
    REQUIRE(eventually([&] { return d.adapter->stats().requests >= 2; }));
    CHECK(d.adapter->state() == AdapterState::request);
    d.refuse(false);
    // The housekeeping tick retries while connected; both go, in order, and
    // the adapter is normal again.
    REQUIRE(eventually([&] { return d.count(kResponse) == 2; }));
    REQUIRE(eventually([&] { return d.adapter->state() == AdapterState::normal; }));
}

TEST_CASE("adapter driven: request state and a lost link keep the responses, reconnection sends them (75, 76)") {
    Driven d;
    d.set_link(LinkState::connected);
    d.refuse(true);
    d.query("q1");
    REQUIRE(eventually([&] { return d.adapter->state() == AdapterState::request; }));
    d.set_link(LinkState::disconnected);
    CHECK(d.adapter->state() == AdapterState::disconnected);
    d.refuse(false);
    std::this_thread::sleep_for(std::chrono::milliseconds(150));  // housekeeping does not retry while down
    CHECK(d.count(kResponse) == 0);
    d.set_link(LinkState::connected);
    REQUIRE(eventually([&] { return d.count(kResponse) == 1; }));
    CHECK(d.adapter->state() == AdapterState::normal);
}

TEST_CASE("adapter driven: a model change announces Probe/Version when connected, on reconnection when not") {
    Driven d;
    d.set_link(LinkState::connected);
    const auto versions = d.count("Probe/Version/test-dev");
    Json model = Json::parse(std::ifstream(test_model_path()));
    model["devices"][0]["version"] = "1.0.1";
    REQUIRE(d.adapter->replace_model(model.dump()).ok());
    CHECK(d.count("Probe/Version/test-dev") == versions + 1);

    d.set_link(LinkState::disconnected);
    model["devices"][0]["version"] = "1.0.2";
    REQUIRE(d.adapter->replace_model(model.dump()).ok());
    CHECK(d.count("Probe/Version/test-dev") == versions + 1);  // nothing while down
    d.set_link(LinkState::connected);
    CHECK(d.count("Probe/Version/test-dev") == versions + 2);
    std::lock_guard<std::mutex> lock(d.link->mutex);
    std::string last;
    for (const auto& m : d.link->sent)
        if (m.topic == "Probe/Version/test-dev") last = m.payload;
    CHECK(Json::parse(last)["version"] == "1.0.2");
}
