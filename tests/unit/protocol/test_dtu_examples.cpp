// Every example DTU of chapter 8 round-trips through its typed struct.
#include "chapter8_examples.hpp"
#include "dtu_dispatch.hpp"

#include <nclink/dtu.hpp>

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>

using namespace nclink;
using chapter8::kExamples;

TEST_CASE("chapter 8 examples: decode -> encode -> decode is stable and matches the example") {
    for (const auto& example : kExamples) {
        INFO(example.name);
        const Json expected = Json::parse(example.json);
        auto first = chapter8::reencode(example.dtu, example.json);
        REQUIRE(first.ok());
        // Decoding our own encoding gives the same DTU again.
        auto second = chapter8::reencode(example.dtu, first->dump());
        REQUIRE(second.ok());
        CHECK(*second == *first);
        // Decoding from an already-parsed Json gives the same as from text.
        auto from_json = chapter8::reencode(example.dtu, expected);
        REQUIRE(from_json.ok());
        CHECK(*from_json == *first);
        if (example.complete) CHECK(*first == expected);
    }
}

TEST_CASE("chapter 8 examples: the fuzz corpus holds the same texts") {
    const auto dir = std::filesystem::path(__FILE__).parent_path() / ".." / ".." / "fuzz" / "corpus" / "dtu";
    REQUIRE(std::filesystem::is_directory(dir));
    for (const auto& example : kExamples) {
        INFO(example.name);
        std::ifstream in(dir / (std::string(example.name) + ".json"));
        REQUIRE(in.good());
        const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        CHECK(Json::parse(text) == Json::parse(example.json));
    }
}

TEST_CASE("typed fields of the examples decode as the standard means them") {
    SECTION("query request 8.2.11 example 3b") {
        auto q = decode_query_request(kExamples[17].json);
        REQUIRE(q.ok());
        CHECK(q->msg_id == Json("some_mid_x6"));
        CHECK(q->guid == "dev_uuid");
        REQUIRE(q->ids.size() == 1);
        CHECK(q->ids[0].id == "012223");
        CHECK((*q->ids[0].params)["indexes"] == Json::array({"0", "5-8"}));
    }
    SECTION("query response 8.2.12 example 1") {
        auto r = decode_query_response(kExamples[18].json);
        REQUIRE(r.ok());
        REQUIRE(r->values.size() == 2);
        CHECK(r->values[0].status.ok);
        CHECK(*r->values[0].values == Json::parse(R"([2, "str1", [1, 2, 3], 100.23])"));
        CHECK_FALSE(r->values[1].status.ok);
        CHECK(r->values[1].status.error_code() == ErrorCode::unavailable);
        CHECK_FALSE(r->status.has_value());
    }
    SECTION("sample 8.2.15") {
        auto s = decode_sample(R"({"id":"cn1","guid":"d","beginTime":"1535642875900","data":[{"data":[1,null]}]})");
        REQUIRE(s.ok());
        CHECK(s->begin_time == 1535642875900);
        REQUIRE(s->data.size() == 1);
        CHECK(s->data[0] == Json::parse("[1,null]"));
        CHECK(encode(*s) == R"({"beginTime":"1535642875900","data":[{"data":[1,null]}],"guid":"d","id":"cn1"})");
    }
    SECTION("event register 8.2.27") {
        auto e = decode_event_register_request(kExamples[44].json);
        REQUIRE(e.ok());
        CHECK(e->id == "010302");
        REQUIRE(e->filters);
        CHECK(e->filters->size() == 2);
        CHECK(e->trigger_type == "always");
        CHECK_FALSE(e->key);
        CHECK_FALSE(e->index);
    }
    SECTION("event data 8.2.31") {
        auto e = decode_event_data(kExamples[48].json);
        REQUIRE(e.ok());
        CHECK(e->time == 19202912);
        CHECK(e->event.index == 1);
        CHECK(e->event.value == 5);
        CHECK(e->event.old_value == Json(10));
    }
    SECTION("DEV_UNREACHABLE 8.3.4") {
        auto d = decode_dev_unreachable(kExamples[49].json);
        REQUIRE(d.ok());
        CHECK(d->status.reason == std::string(dev_unreachable_reason));
        DevUnreachable built;
        built.msg_id = Json("some_mid_123");
        built.dev_uuid = "dev_uuid_2";
        built.cli_uuid = "ex_cid";
        CHECK(to_json(built) == Json::parse(kExamples[49].json));
    }
}

TEST_CASE("examples are indexed as the typed-field test assumes") {
    CHECK(kExamples[17].name == "8.2.11_ex3b_query_request");
    CHECK(kExamples[18].name == "8.2.12_ex1_query_response");
    CHECK(kExamples[44].name == "8.2.27_event_register_request");
    CHECK(kExamples[48].name == "8.2.31_event_data");
    CHECK(kExamples[49].name == "8.3.4_dev_unreachable");
}
