// MessageRouter on its own (client/message_router.hpp): the client's
// receive side without a dispatch thread, fed Messages directly.
#include "client/message_router.hpp"
#include "client/responders.hpp"

#include <nclink/dtu.hpp>
#include <nclink/testing/loopback_transport.hpp>

#include <catch2/catch.hpp>

#include <optional>
#include <string>
#include <vector>

using namespace nclink;
using namespace nclink::client_detail;

namespace {

struct Rig {
    LoopbackBroker broker;
    ClientLink link{make_loopback_transport(broker, LoopbackOptions{})};
    ClientCounters counters;
    PendingRequests pending;
    EventRoutes event_routes;
    std::vector<std::string> instances;  // note_instance calls, "dev payload"
    MessageRouter router{MessageRouter::Parts{"app1", Logger{}, counters, link, pending, event_routes,
                                              [this](const std::string& dev, const std::string&) { instances.push_back(dev); }},
                         16};

    /// A pending Query with id `id` to `dev`; its outcome lands in `outcome`.
    void expect_query(const std::string& id, const std::string& dev, std::optional<Result<std::vector<QueryResult>>>& outcome) {
        auto responder = query_responder([&outcome](Result<std::vector<QueryResult>> r) { outcome = std::move(r); });
        REQUIRE(pending.add(PendingRequest{id, TopicKind::query_response, Clock::now() + std::chrono::hours(1), responder, dev}));
    }
};

Message query_response(const std::string& dev, const std::string& id) {
    QueryResponse dtu;
    dtu.msg_id = Json(id);
    dtu.guid = dev;
    QueryResult result;
    result.id = "speed";
    result.status = ResponseStatus{};
    result.values = Json::array({1500});
    dtu.values.push_back(result);
    return {topics::query_response(dev, "app1"), encode(dtu), 1, false};
}

Message sample(const std::string& dev, std::int64_t begin) {
    SampleDtu dtu;
    dtu.guid = dev;
    dtu.id = "ch1";
    dtu.begin_time = begin;
    dtu.data = {Json::array({1})};
    return {topics::sample(dev, "ch1"), encode(dtu), 1, false};
}

}  // namespace

TEST_CASE("router: a response completes the pending request with its @id, once") {
    Rig rig;
    std::optional<Result<std::vector<QueryResult>>> outcome;
    rig.expect_query("q1", "dev1", outcome);
    rig.router.route(query_response("dev1", "other"));  // nobody waits for it
    CHECK_FALSE(outcome);
    CHECK(rig.counters.unmatched == 1);
    rig.router.route(query_response("dev1", "q1"));
    REQUIRE(outcome);
    REQUIRE(outcome->ok());
    CHECK(outcome->value().at(0).values == Json::array({1500}));
    CHECK(rig.counters.responses == 1);
    rig.router.route(query_response("dev1", "q1"));  // a QoS 1 repeat: the request is gone
    CHECK(rig.counters.responses == 1);
    CHECK(rig.counters.unmatched == 2);
}

TEST_CASE("router: a response of the wrong kind or without @id is not taken for the request") {
    Rig rig;
    std::optional<Result<std::vector<QueryResult>>> outcome;
    rig.expect_query("q1", "dev1", outcome);
    Message wrong = query_response("dev1", "q1");
    wrong.topic = topics::set_response("dev1", "app1");
    rig.router.route(wrong);
    CHECK_FALSE(outcome);
    CHECK(rig.counters.unmatched == 1);
    rig.router.route({topics::query_response("dev1", "app1"), R"({"guid":"dev1"})", 1, false});
    CHECK(rig.counters.malformed == 1);
    rig.router.route({"not/an/nclink/topic", "{}", 1, false});
    CHECK(rig.counters.unmatched == 2);
    CHECK_FALSE(outcome);
    CHECK(rig.pending.size() == 1);
}

TEST_CASE("router: a repeated Sample DTU reaches its subscription once") {
    Rig rig;
    std::vector<std::int64_t> begins;
    REQUIRE(rig.link.subscribe(topics::sample("dev1", "+"),
                               SampleHandler([&](const SampleDtu& s) { begins.push_back(s.begin_time); })));
    rig.router.route(sample("dev1", 100));
    rig.router.route(sample("dev1", 100));  // the adapter sent it again after a reconnect
    rig.router.route(sample("dev1", 200));
    rig.router.route(sample("dev2", 100));  // no subscription matches
    CHECK(begins == std::vector<std::int64_t>{100, 200});
    CHECK(rig.counters.samples == 2);
    CHECK(rig.counters.duplicates == 1);
}

TEST_CASE("router: the last Notify/State per terminal is known until a cleared retained state") {
    Rig rig;
    std::vector<std::string> states;
    REQUIRE(rig.link.subscribe(topics::notify_state("+"), StateHandler([&](const NotifyState& n) { states.push_back(n.state); })));
    CHECK_FALSE(rig.router.known_state("dev1"));
    NotifyState offline;
    offline.tid = "dev1";
    offline.state = "offline";
    rig.router.route({topics::notify_state("dev1"), encode(offline), 1, true});
    CHECK(rig.router.known_state("dev1") == std::optional<std::string>("offline"));
    CHECK_FALSE(rig.router.known_state("dev2"));
    rig.router.route({topics::notify_state("dev1"), "", 1, true});  // the retained state cleared
    CHECK_FALSE(rig.router.known_state("dev1"));
    rig.router.route({topics::notify_state("dev1"), "{not json", 1, true});
    CHECK(rig.counters.malformed == 1);
    CHECK(states == std::vector<std::string>{"offline"});
}
