// The streaming Query request decoder against the tree decoder: wherever it
// answers, it answers exactly what decode<QueryRequest>(const Json&) gives;
// it answers for the requests applications really send; and what it leaves
// to the tree still gets the tree's refusal through decode<QueryRequest>(text).
#include "protocol/query_request_fast.hpp"
#include "support/payload_damage.hpp"

#include <nclink/dtu.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <string>
#include <string_view>
#include <vector>

using namespace nclink;
using nclink::test::damage;
using protocol_detail::fast_decode_query_request;

namespace {

// One decoder's answer against the tree decoder's.
void same_as_tree(const QueryRequest& fast, const std::string& payload) {
    const Json tree = Json::parse(payload, nullptr, false);
    INFO(payload);
    REQUIRE(!tree.is_discarded());
    const auto reference = decode<QueryRequest>(tree);
    REQUIRE(reference.ok());
    CHECK(fast.msg_id == reference->msg_id);
    if (fast.msg_id && reference->msg_id) CHECK(fast.msg_id->type() == reference->msg_id->type());
    CHECK(fast.guid == reference->guid);
    CHECK(fast.private_info == reference->private_info);
    REQUIRE(fast.ids.size() == reference->ids.size());
    for (std::size_t i = 0; i < fast.ids.size(); ++i) {
        CHECK(fast.ids[i].id == reference->ids[i].id);
        CHECK(fast.ids[i].params == reference->ids[i].params);
    }
}

// Both decoders on one payload, and the plain scan (the streaming decoder's
// first attempt) on its own. Returns whether the streaming decoder answered.
bool agrees(const std::string& payload) {
    if (const auto plain = protocol_detail::plain_decode_query_request(payload)) same_as_tree(*plain, payload);
    const auto fast = fast_decode_query_request(payload);
    if (!fast) return false;
    same_as_tree(*fast, payload);
    return true;
}

}  // namespace

TEST_CASE("the streaming Query decoder reads what applications send as the tree decoder does") {
    const char* payloads[] = {
        R"({"@id":"q1","guid":"dev-1","ids":[{"id":"pos"},{"id":"ovr"}]})",
        R"({"ids":[]})",
        R"({"@id":17,"ids":["010203","040506"]})",
        R"({"@id":-3,"ids":[{"id":"a"}]})",
        R"({"@id":18446744073709551615,"ids":[{"id":"a"}]})",
        R"({"@id":2.5,"ids":[{"id":"a"}]})",
        R"({"@id":null,"ids":[{"id":"a"}]})",
        R"({"@id":true,"ids":[{"id":"a"}]})",
        R"({"ids":[{"params":{"offset":2,"length":3},"id":"arr"}],"guid":"g"})",
        R"({"ids":[{"id":"x","params":{"keys":["a","b"],"deep":[[1,{"k":[null,false]}],{}],"k":1,"k":2}}]})",
        R"({"ids":[{"id":"x","params":7},{"id":"y","params":"text"},{"id":"z","params":null},{"id":"w","params":[]}]})",
        R"({"ids":[{"id":"x"}],"privateInfo":{"trace":["a",{"b":1.5e3}]}})",
        R"({"ids":[{"id":"x"}],"privateInfo":"plain"})",
        R"({"vendor":{"a":[1,2,{"b":[]}]},"extra":[1,[2]],"ids":[{"id":"x","note":{"n":1},"tags":[1]}],"more":"s"})",
        R"(  {"ids" : [ { "id" : "caf\u00e9 \"q\" \\ \n" } ] , "guid" : "\ud83d\ude00" }  )",
        "\xEF\xBB\xBF{\"ids\":[{\"id\":\"bom\"}]}",
    };
    for (const char* payload : payloads) {
        INFO(payload);
        CHECK(agrees(payload));
    }
}

TEST_CASE("the streaming Query decoder leaves every request the tree refuses or reads differently to the tree") {
    const char* payloads[] = {
        "",
        "   ",
        "[]",
        "\"ids\"",
        "{",
        R"({"ids":[{"id":"a"}]} trailing)",
        R"({"ids":[{"id":"a"}],})",
        R"({"guid":"g"})",             // ids missing: 102
        R"({"values":[{"id":"a"}]})",  // ids missing beside an unknown key: 413
        R"({"ids":{"id":"a"}})",       // not an array
        R"({"ids":"a"})",
        R"({"ids":[{"id":"a"}],"guid":5})",  // guid not a string
        R"({"ids":[{"id":"a"}],"guid":null})",
        R"({"@id":{"n":1},"ids":[]})",  // structured @id
        R"({"@id":[1],"ids":[]})",
        R"({"ids":[7]})",  // an entry neither string nor object
        R"({"ids":[null]})",
        R"({"ids":[["a"]]})",
        R"({"ids":[{"params":{}}]})",  // entry without id
        R"({"ids":[{"id":5}]})",       // id not a string
        R"({"ids":[{"id":{"a":1}}]})",
        R"({"ids":[{"id":"a","id":"b"}]})",  // a key the decoder reads, given twice
        R"({"ids":[{"id":"a","params":1,"params":2}]})",
        R"({"ids":[],"ids":[{"id":"a"}]})",
        R"({"@id":1,"@id":2,"ids":[]})",
        R"({"guid":"a","guid":"b","ids":[]})",
        R"({"privateInfo":1,"privateInfo":2,"ids":[]})",
        R"({"ids":[{"id":"a"}],"n":1e999})",  // number overflow
        R"({"ids":[{"id":"\ud800"}]})",       // lone surrogate
        "{\"ids\":[{\"id\":\"\xff\"}]}",      // invalid UTF-8
    };
    for (const char* payload : payloads) {
        INFO(payload);
        CHECK_FALSE(fast_decode_query_request(payload).has_value());
    }
    SECTION("nesting beyond the payload depth limit") {
        std::string deep = R"({"ids":[{"id":"a","params":)";
        for (int i = 0; i < 200; ++i) deep += '[';
        for (int i = 0; i < 200; ++i) deep += ']';
        deep += "}]}";
        CHECK_FALSE(fast_decode_query_request(deep).has_value());
        const auto refused = decode<QueryRequest>(deep);
        REQUIRE_FALSE(refused.ok());
        CHECK(refused.error().code == ErrorCode::syntax_error);
    }
    SECTION("through decode<QueryRequest>(text) the tree's refusal stands") {
        const auto missing = decode<QueryRequest>(R"({"guid":"g"})");
        REQUIRE_FALSE(missing.ok());
        CHECK(missing.error().code == ErrorCode::parameter_missing);
        const auto unknown = decode<QueryRequest>(R"({"values":[{"id":"a"}]})");
        REQUIRE_FALSE(unknown.ok());
        CHECK(unknown.error().code == ErrorCode::keys_of_arguments);
        const auto bad_json = decode<QueryRequest>("{");
        REQUIRE_FALSE(bad_json.ok());
        CHECK(bad_json.error().code == ErrorCode::syntax_error);
        const auto twice = decode<QueryRequest>(R"({"ids":[{"id":"a","id":"b"}]})");  // the tree keeps the last
        REQUIRE(twice.ok());
        CHECK(twice->ids.at(0).id == "b");
    }
}

// Generated requests, valid and broken: the streaming decoder never answers
// differently from the tree, and answers for every well-formed one it sees.
TEST_CASE("the streaming Query decoder agrees with the tree on generated requests") {
    std::mt19937 random(20261127);
    const auto pick = [&](int n) { return static_cast<int>(random() % static_cast<unsigned>(n)); };
    const auto free_json = [&](int depth, auto& self) -> std::string {
        switch (depth > 2 ? pick(5) : pick(7)) {
            case 0: return "null";
            case 1: return pick(2) ? "true" : "false";
            case 2: return std::to_string(static_cast<int>(random() % 2001) - 1000);
            case 3: return "1.25e2";
            case 4: return "\"s\\u00e9" + std::to_string(pick(9)) + "\"";
            case 5: {
                std::string s = "[";
                for (int i = 0, n = pick(3); i < n; ++i) s += (i ? "," : "") + self(depth + 1, self);
                return s + "]";
            }
            default: {
                std::string s = "{";
                for (int i = 0, n = pick(3); i < n; ++i)
                    s += std::string(i ? "," : "") + "\"k" + std::to_string(pick(3)) + "\":" + self(depth + 1, self);
                return s + "}";
            }
        }
    };
    int answered = 0, well_formed = 0;
    for (int round = 0; round < 2000; ++round) {
        const bool broken = pick(4) == 0;
        std::vector<std::string> members;
        if (pick(3)) members.push_back("\"@id\":" + (pick(2) ? "\"r" + std::to_string(round) + "\"" : std::to_string(round)));
        if (pick(2)) members.push_back("\"guid\":\"dev-" + std::to_string(pick(5)) + "\"");
        std::string ids = "\"ids\":[";
        for (int i = 0, n = pick(6); i < n; ++i) {
            if (i) ids += ",";
            if (pick(4) == 0) {
                ids += "\"bare" + std::to_string(i) + "\"";
                continue;
            }
            std::vector<std::string> entry{"\"id\":\"item" + std::to_string(pick(50)) + "\""};
            if (pick(2)) entry.push_back("\"params\":" + free_json(0, free_json));
            if (pick(5) == 0) entry.push_back("\"other\":" + free_json(0, free_json));
            std::shuffle(entry.begin(), entry.end(), random);
            ids += "{";
            for (std::size_t k = 0; k < entry.size(); ++k) ids += (k ? "," : "") + entry[k];
            ids += "}";
        }
        members.push_back(ids + "]");
        if (pick(4) == 0) members.push_back("\"privateInfo\":" + free_json(0, free_json));
        if (pick(4) == 0) members.push_back("\"vendor\":" + free_json(0, free_json));
        std::shuffle(members.begin(), members.end(), random);
        std::string payload = "{";
        for (std::size_t k = 0; k < members.size(); ++k) payload += (k ? "," : "") + members[k];
        payload += "}";
        if (broken) {
            damage(payload, random, "{}[]\":,x1");
        } else {
            ++well_formed;
        }
        if (agrees(payload)) ++answered;
    }
    // Every well-formed request was answered by the streaming decoder (the
    // generator gives no key twice), some broken ones too (still valid JSON).
    CHECK(answered >= well_formed);
}

TEST_CASE("the plain scan reads the plain requests applications send as the tree decoder does") {
    const char* payloads[] = {
        R"({"@id":"q1","guid":"dev-1","ids":[{"id":"pos"},{"id":"ovr"}]})",
        R"({"ids":[]})",
        R"({"ids":["010203","040506"],"guid":"g"})",
        R"({"ids":[{"id":""}],"@id":""})",
        " \t\r\n{ \"guid\" : \"g\" ,\n \"ids\" : [ { \"id\" : \"a b~\" } , \"c\" ] , \"@id\" : \"x\" } \n",
    };
    for (const char* payload : payloads) {
        INFO(payload);
        const auto plain = protocol_detail::plain_decode_query_request(payload);
        REQUIRE(plain.has_value());
        same_as_tree(*plain, payload);
    }
}

TEST_CASE("the plain scan leaves everything but the plain form to the SAX pass") {
    const char* payloads[] = {
        R"({"@id":17,"ids":[{"id":"a"}]})",  // a number @id
        R"({"@id":null,"ids":[{"id":"a"}]})",
        R"({"ids":[{"id":"a","params":{"keys":["k"]}}]})",  // params
        R"({"ids":[{"params":1,"id":"a"}]})",
        R"({"ids":[{"id":"a"}],"privateInfo":{}})",
        R"({"ids":[{"id":"a"}],"vendor":1})",  // a key it does not read
        R"({"ids":[{"id":"a\"b"}]})",          // an escape
        R"({"ids":[{"id":"caf\u00e9"}]})",
        "{\"ids\":[{\"id\":\"caf\xc3\xa9\"}]}",  // UTF-8
        "{\"ids\":[{\"id\":\"\x7f\"}]}",
        "{\"ids\":[{\"id\":\"tab\there\"}]}",  // a raw control byte
        R"({"ids":[{"id":"a"}],"ids":[]})",    // a key twice
        R"({"@id":"a","@id":"b","ids":[]})",
        R"({"ids":[{"id":"a","id":"b"}]})",
        R"({"ids":[{"id":"a"}]} x)",  // trailing bytes
        R"({"ids":[{"id":"a"}],})",
        R"({"ids":[{"id":"a"},]})",
        R"({"ids":[{"id":"a"})",
        R"({"ids":[{}]})",
        R"({"ids":[1]})",
        R"({"guid":"g"})",  // no ids
        R"({})",
        "\xEF\xBB\xBF{\"ids\":[]}",  // a BOM
        "",
    };
    for (const char* payload : payloads) {
        INFO(payload);
        CHECK_FALSE(protocol_detail::plain_decode_query_request(payload).has_value());
    }
}

// Plain requests with whitespace, then a byte dropped, doubled or replaced:
// wherever the plain scan still answers, the tree answers the same.
TEST_CASE("the plain scan agrees with the tree on generated and damaged plain requests") {
    std::mt19937 random(20261128);
    const auto pick = [&](int n) { return static_cast<int>(random() % static_cast<unsigned>(n)); };
    const auto space = [&] {
        return std::string(" \t\r\n").substr(static_cast<std::size_t>(pick(4)), static_cast<std::size_t>(pick(2)));
    };
    int answered = 0, intact = 0;
    for (int round = 0; round < 20000; ++round) {
        std::vector<std::string> members;
        if (pick(3)) members.push_back("\"@id\"" + space() + ":" + space() + "\"r" + std::to_string(round) + "\"");
        if (pick(2)) members.push_back("\"guid\":" + space() + "\"dev " + std::to_string(pick(5)) + "\"");
        std::string ids = "\"ids\":" + space() + "[";
        for (int i = 0, n = pick(8); i < n; ++i) {
            ids += (i ? "," : "") + space();
            ids += pick(4) == 0 ? "\"bare" + std::to_string(i) + "\""
                                : "{" + space() + "\"id\":\"i/" + std::to_string(pick(50)) + "\"" + space() + "}";
        }
        members.push_back(ids + space() + "]");
        std::shuffle(members.begin(), members.end(), random);
        std::string payload = space() + "{";
        for (std::size_t k = 0; k < members.size(); ++k) payload += (k ? "," : "") + space() + members[k];
        payload += "}" + space();
        if (pick(3) == 0) {
            damage(payload, random, "{}[]\":, \\x");
        } else {
            ++intact;
        }
        if (const auto plain = protocol_detail::plain_decode_query_request(payload)) {
            same_as_tree(*plain, payload);
            ++answered;
        }
    }
    CHECK(answered >= intact);
}
