#include "values_test_util.hpp"

#include <atomic>
#include <string>
#include <thread>
#include <vector>

using namespace nclink;
using namespace values_test;

TEST_CASE("ValueStore registers items and answers query/set") {
    ValueStore store;
    REQUIRE(store.add("010203", DataKind::single, false, Json(12.5)).ok());
    REQUIRE(store.add("011213", DataKind::dict, true, example_dict()).ok());
    REQUIRE(store.add("012223", DataKind::list, true, example_list()).ok());
    REQUIRE(store.add("later", DataKind::list, true, Json()).ok());
    CHECK(store.size() == 4);
    CHECK(store.contains("011213"));
    CHECK_FALSE(store.contains("nope"));
    CHECK(store.ids() == std::vector<std::string>{"010203", "011213", "012223", "later"});

    CHECK(code_of(store.add("010203", DataKind::single, true, Json(1))) == ErrorCode::key_error);
    CHECK(code_of(store.add("bad", DataKind::dict, true, Json::array())) == ErrorCode::value_type);
    CHECK(code_of(store.add("bad", DataKind::list, true, Json(1))) == ErrorCode::value_type);

    CHECK(*store.query("010203", Json()) == Json::parse("[12.5]"));
    CHECK(*store.query("012223", Json::parse(R"({"operation": "get_value", "indexes": ["0", "4-7"]})")) ==
          Json::parse(R"([100.234, 50, "str_v_6", [1.1, 2.2, 3.3], 8])"));
    CHECK(code_of(store.query("nope", Json())) == ErrorCode::node_not_exists);
    CHECK(reason(ErrorCode::node_not_exists) == "Node not exists");
    CHECK(code_of(store.query("later", Json::parse(R"({"operation": "get_length"})"))) == ErrorCode::unavailable);

    CHECK(code_of(store.set("010203", Json::parse(R"({"value": 1})"))) == ErrorCode::permission_denied);
    CHECK(code_of(store.set("nope", Json::parse(R"({"value": 1})"))) == ErrorCode::node_not_exists);
    REQUIRE(store.set("011213", Json::parse(R"({"operation": "add", "key": "AAA", "value": "111"})")).ok());
    CHECK(*store.query("011213", Json::parse(R"({"operation": "get_keys"})")) == Json::parse(R"(["AAA", "k1", "k2", "k3"])"));
    CHECK(code_of(store.set("011213", Json::parse(R"({"keys": ["k1", "zz"], "values": [1, 2]})"))) == ErrorCode::key_error);
    CHECK((*store.get("011213"))["k1"] == 1234);  // untouched

    // put: SDK-side writes ignore setable but keep the kind.
    REQUIRE(store.put("010203", Json(99)).ok());
    CHECK(*store.get("010203") == 99);
    CHECK(code_of(store.put("011213", Json(1))) == ErrorCode::value_type);
    CHECK(code_of(store.put("nope", Json(1))) == ErrorCode::node_not_exists);
    CHECK(code_of(store.get("nope")) == ErrorCode::node_not_exists);
}

TEST_CASE("ValueStore snapshot and load") {
    ValueStore store;
    REQUIRE(store.add("a", DataKind::single, true, Json(1)).ok());
    REQUIRE(store.add("d", DataKind::dict, true, Json::object()).ok());
    const Json snap = store.snapshot();
    CHECK(snap == Json::parse(R"({"a": 1, "d": {}})"));

    ValueStore other;
    REQUIRE(other.add("a", DataKind::single, false, Json()).ok());
    REQUIRE(other.add("d", DataKind::dict, false, Json()).ok());
    const auto loaded = other.load(Json::parse(R"({"a": 5, "d": {"x": 1}, "gone": 3})"));
    REQUIRE(loaded.ok());
    CHECK(*loaded == 2);  // "gone" is skipped
    CHECK(other.snapshot() == Json::parse(R"({"a": 5, "d": {"x": 1}})"));

    // All-or-nothing: a value that does not fit its kind restores nothing.
    CHECK(code_of(other.load(Json::parse(R"({"a": 6, "d": [1]})"))) == ErrorCode::value_type);
    CHECK(*other.get("a") == 5);
    CHECK(code_of(other.load(Json::array())) == ErrorCode::syntax_error);
}

TEST_CASE("ValueStore is safe to use from several threads") {
    ValueStore store;
    REQUIRE(store.add("counters", DataKind::dict, true, Json::object()).ok());
    REQUIRE(store.add("regs", DataKind::list, true, Json::parse("[0, 0, 0, 0]")).ok());
    constexpr int kThreads = 4;
    constexpr int kRounds = 200;
    std::atomic<int> failures{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&store, &failures, t] {
            for (int i = 0; i < kRounds; ++i) {
                // Writers: each thread adds its own keys and flips its own bit.
                const Json add = {{"operation", "add"}, {"key", std::to_string(t) + "-" + std::to_string(i)}, {"value", i}};
                if (!store.set("counters", add).ok()) ++failures;
                const Json bit = {{"index", t}, {"offset", i % 64}, {"value", 1}};
                if (!store.set("regs", bit).ok()) ++failures;
                // Readers: queries and snapshots interleaved with the writes.
                auto keys = store.query("counters", Json{{"operation", "get_keys"}});
                if (!keys.ok() || keys->empty()) ++failures;
                auto length = store.query("regs", Json{{"operation", "get_length"}});
                if (!length.ok() || *length != Json::array({4})) ++failures;
                if (!store.snapshot().is_object()) ++failures;
            }
        });
    }
    for (auto& thread : threads) thread.join();
    CHECK(failures == 0);
    CHECK(store.query("counters", Json{{"operation", "get_keys"}})->size() == kThreads * kRounds);
    // Every thread set bits 0..63 of its own register: all ones.
    const Json regs = *store.get("regs");
    for (int t = 0; t < kThreads; ++t) CHECK(regs[static_cast<std::size_t>(t)] == -1);
}
