// The plain-form Set request scan against the tree decoder: wherever it
// answers, it answers exactly what decode<SetRequest>(const Json&) gives,
// down to the Json type of every number (an unsigned 42 and a signed 42 are
// equal to nlohmann's == but not on the wire back); it answers for the
// requests applications really send; and what it leaves to the tree still
// gets the tree's answer through decode<SetRequest>(text).
#include "protocol/set_request_fast.hpp"
#include "support/payload_damage.hpp"

#include <nclink/dtu.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <string_view>
#include <vector>

using namespace nclink;
using nclink::test::damage;
using protocol_detail::plain_decode_set_request;

namespace {

// Equal and of the same types all the way down (-0.0 keeps its sign).
bool identical(const Json& a, const Json& b) {
    if (a.type() != b.type()) return false;
    if (a.is_object()) {
        if (a.size() != b.size()) return false;
        for (const auto& [key, value] : a.items())
            if (!b.contains(key) || !identical(value, b.at(key))) return false;
        return true;
    }
    if (a.is_array()) {
        if (a.size() != b.size()) return false;
        for (std::size_t i = 0; i < a.size(); ++i)
            if (!identical(a[i], b[i])) return false;
        return true;
    }
    if (a.is_number_float()) return a == b && std::signbit(a.get<double>()) == std::signbit(b.get<double>());
    return a == b;
}

bool identical(const std::optional<Json>& a, const std::optional<Json>& b) {
    return a.has_value() == b.has_value() && (!a || identical(*a, *b));
}

void same_as_tree(const SetRequest& plain, const std::string& payload) {
    const Json tree = Json::parse(payload, nullptr, false);
    INFO(payload);
    REQUIRE(!tree.is_discarded());
    const auto reference = decode<SetRequest>(tree);
    REQUIRE(reference.ok());
    CHECK(identical(plain.msg_id, reference->msg_id));
    CHECK(plain.guid == reference->guid);
    CHECK(identical(plain.private_info, reference->private_info));
    REQUIRE(plain.values.size() == reference->values.size());
    for (std::size_t i = 0; i < plain.values.size(); ++i) {
        CHECK(plain.values[i].id == reference->values[i].id);
        CHECK(identical(plain.values[i].params, reference->values[i].params));
        CHECK(identical(plain.values[i].offset, reference->values[i].offset));
        CHECK(identical(plain.values[i].length, reference->values[i].length));
    }
}

// Whether the scan answered; where it did, it agreed with the tree.
bool agrees(const std::string& payload) {
    const auto plain = plain_decode_set_request(payload);
    if (!plain) return false;
    same_as_tree(*plain, payload);
    return true;
}

std::string set_of(const std::string& value) {
    return R"({"@id":"s1","guid":"dev","values":[{"id":"ovr","params":{"value":)" + value + "}}]}";
}

}  // namespace

TEST_CASE("the plain Set scan reads the Sets applications send as the tree decoder does") {
    const char* payloads[] = {
        R"({"@id":"s1","guid":"dev-1","values":[{"id":"feed_ovr_cfg","params":{"value":42}}]})",
        R"({"values":[{"params":{"value":-7},"id":"a"},{"id":"b","params":{"value":"on"}}],"guid":"g"})",
        R"({"values":[]})",
        R"({"values":[{"id":"a"}]})",  // no params: 102 per item from the values module
        R"({"values":[{"id":"a","params":{}}]})",
        R"({"values":[{"id":"a","params":{"index":2,"value":true}}]})",
        R"({"values":[{"id":"a","params":{"value":null}},{"id":"b","params":{"value":false}}]})",
        R"({"values":[{"id":"a","params":{"value":1.5}},{"id":"b","params":{"value":-0.0}},{"id":"c","params":{"value":-0}}]})",
        R"({"values":[{"id":"a","params":{"value":1e5}},{"id":"b","params":{"value":2.5E-3}},{"id":"c","params":{"value":-3e+2}}]})",
        R"({"values":[{"id":"a","params":{"value":0}},{"id":"b","params":{"value":999999999999999999}},{"id":"c","params":{"value":-999999999999999999}}]})",
        R"({"values":[{"id":"a","params":{"value":0.1}},{"id":"b","params":{"value":5e-324}},{"id":"c","params":{"value":1.7976931348623157e308}}]})",
        " \t\r\n{ \"guid\" : \"g\" ,\n \"values\" : [ { \"id\" : \"a b~\" , \"params\" : { \"value\" : 3 } } ] , \"@id\" : \"x\" "
        "} \n",
    };
    for (const char* payload : payloads) {
        INFO(payload);
        CHECK(agrees(payload));
    }
}

TEST_CASE("the plain Set scan leaves everything but the plain form to the tree, which answers as before") {
    const char* payloads[] = {
        R"({"@id":17,"values":[{"id":"a","params":{"value":1}}]})",  // a number @id
        R"({"values":[{"id":"a","params":{"value":[1,2]}}]})",       // a structure in params
        R"({"values":[{"id":"a","params":{"values":{"k":1}}}]})",
        R"({"values":[{"id":"a","params":7}]})",                                  // params not an object
        R"({"values":[{"id":"a","params":{"value":1},"offset":2,"length":1}]})",  // offset/length beside params
        R"({"values":[{"id":"a","params":{"value":1}}],"privateInfo":{}})",
        R"({"values":[{"id":"a","params":{"value":1},"other":1}]})",  // a key it does not read
        R"({"values":[{"id":"a","params":{"value":1}}],"vendor":1})",
        R"({"values":[{"id":"a","params":{"value":"a\"b"}}]})",                  // an escape
        "{\"values\":[{\"id\":\"a\",\"params\":{\"value\":\"caf\xc3\xa9\"}}]}",  // UTF-8
        R"({"values":[{"id":"a","params":{"value":1,"value":2}}]})",             // a key twice
        R"({"values":[{"id":"a","id":"b","params":{"value":1}}]})",
        R"({"values":[],"values":[]})",
        R"({"values":[{"id":"a","params":{"value":1}}]} x)",  // trailing bytes
        R"({"values":[{"id":"a","params":{"value":1,}}]})",
        R"({"values":[{"params":{"value":1}}]})",  // no id
        R"({"values":[{"id":5,"params":{"value":1}}]})",
        R"({"values":[{"id":"a","params":{"value":01}}]})",  // not JSON numbers
        R"({"values":[{"id":"a","params":{"value":+1}}]})",
        R"({"values":[{"id":"a","params":{"value":1.}}]})",
        R"({"values":[{"id":"a","params":{"value":.5}}]})",
        R"({"values":[{"id":"a","params":{"value":1e}}]})",
        R"({"values":[{"id":"a","params":{"value":-}}]})",
        R"({"values":[{"id":"a","params":{"value":tru}}]})",
        R"({"values":[{"id":"a","params":{"value":nulls}}]})",
        R"({"values":[{"id":"a","params":{"value":1234567890123456789}}]})",  // beyond 18 digits: the tree's rules
        R"({"values":[{"id":"a","params":{"value":-18446744073709551616}}]})",
        R"({"values":[{"id":"a","params":{"value":1e999}}]})",  // out of range
        R"({"values":[{"id":"a","params":{"value":1e-400}}]})",
        R"({"guid":"g"})",  // no values
        R"({"ids":[{"id":"a"}]})",
        R"({})",
        "",
    };
    for (const char* payload : payloads) {
        INFO(payload);
        CHECK_FALSE(plain_decode_set_request(payload).has_value());
        // decode<SetRequest>(text) gives exactly the tree's answer.
        const Json tree = Json::parse(payload, nullptr, false);
        const auto through_text = decode<SetRequest>(std::string_view(payload));
        if (tree.is_discarded()) {
            REQUIRE_FALSE(through_text.ok());
            CHECK(through_text.error().code == ErrorCode::syntax_error);
            continue;
        }
        const auto reference = decode<SetRequest>(tree);
        REQUIRE(through_text.ok() == reference.ok());
        if (!reference.ok()) {
            CHECK(through_text.error().code == reference.error().code);
            CHECK(through_text.error().message == reference.error().message);
        } else {
            CHECK(through_text->values.size() == reference->values.size());
        }
    }
    SECTION("table-19 answers through decode<SetRequest>(text)") {
        const auto missing = decode<SetRequest>(R"({"guid":"g"})");
        REQUIRE_FALSE(missing.ok());
        CHECK(missing.error().code == ErrorCode::parameter_missing);
        const auto unknown = decode<SetRequest>(R"({"ids":[{"id":"a"}]})");
        REQUIRE_FALSE(unknown.ok());
        CHECK(unknown.error().code == ErrorCode::keys_of_arguments);
        const auto twice =
            decode<SetRequest>(R"({"values":[{"id":"a","params":{"value":1,"value":2}}]})");  // the tree keeps the last
        REQUIRE(twice.ok());
        CHECK(twice->values.at(0).params->at("value") == 2);
    }
}

// Numbers of every JSON shape, printed as applications print them: wherever
// the scan answers, it made the same number of the same type as the parser.
TEST_CASE("the plain Set scan reads numbers exactly as nlohmann's parser does") {
    std::mt19937_64 random(20261129);
    int answered = 0;
    for (int round = 0; round < 20000; ++round) {
        std::string text;
        char buffer[64];
        switch (random() % 6) {
            case 0: text = std::to_string(static_cast<std::int64_t>(random()) >> (random() % 64)); break;
            case 1: text = std::to_string(random() >> (random() % 64)); break;
            case 2: {
                double v = 0;
                std::uint64_t bits = random();
                std::memcpy(&v, &bits, sizeof v);
                if (!std::isfinite(v)) continue;
                std::snprintf(buffer, sizeof buffer, "%.17g", v);
                text = buffer;
                break;
            }
            case 3:
                std::snprintf(buffer, sizeof buffer, "%.*f", static_cast<int>(random() % 7),
                              static_cast<double>(static_cast<std::int64_t>(random() % 2000001) - 1000000) / 997.0);
                text = buffer;
                break;
            case 4:
                std::snprintf(buffer, sizeof buffer, "%.*e", static_cast<int>(random() % 17),
                              static_cast<double>(static_cast<std::int64_t>(random() % 2001) - 1000) *
                                  std::pow(10.0, static_cast<double>(static_cast<int>(random() % 600) - 300)));
                text = buffer;
                break;
            default: text = random() % 2 ? "-0" : "0.0"; break;
        }
        if (agrees(set_of(text))) ++answered;
    }
    CHECK(answered > 15000);  // all but the > 18-digit integers and the extremes
}

// Plain Sets with whitespace, then a byte dropped, doubled or replaced:
// wherever the scan still answers, the tree answers the same.
TEST_CASE("the plain Set scan agrees with the tree on generated and damaged requests") {
    std::mt19937 random(20261129);
    const auto pick = [&](int n) { return static_cast<int>(random() % static_cast<unsigned>(n)); };
    const auto space = [&] {
        return std::string(" \t\r\n").substr(static_cast<std::size_t>(pick(4)), static_cast<std::size_t>(pick(2)));
    };
    const char* scalars[] = {"42", "-7", "0", "1.5", "-0.25e3", "true", "false", "null", "\"on\"", "\"\"", "1E2"};
    int answered = 0, intact = 0;
    for (int round = 0; round < 20000; ++round) {
        std::vector<std::string> members;
        if (pick(3)) members.push_back("\"@id\"" + space() + ":" + space() + "\"r" + std::to_string(round) + "\"");
        if (pick(2)) members.push_back("\"guid\":" + space() + "\"dev " + std::to_string(pick(5)) + "\"");
        std::string values = "\"values\":" + space() + "[";
        for (int i = 0, n = pick(5); i < n; ++i) {
            std::vector<std::string> entry{"\"id\"" + space() + ":\"i/" + std::to_string(pick(50)) + "\""};
            if (pick(6)) {
                std::vector<std::string> params;
                if (pick(5)) params.push_back("\"value\":" + space() + scalars[pick(11)]);
                if (pick(4) == 0) params.push_back("\"index\":" + std::to_string(pick(9)));
                std::shuffle(params.begin(), params.end(), random);
                std::string p = "\"params\":" + space() + "{";
                for (std::size_t k = 0; k < params.size(); ++k) p += (k ? "," : "") + space() + params[k];
                entry.push_back(p + space() + "}");
            }
            std::shuffle(entry.begin(), entry.end(), random);
            values += (i ? "," : "") + space() + "{";
            for (std::size_t k = 0; k < entry.size(); ++k) values += (k ? "," : "") + space() + entry[k];
            values += space() + "}";
        }
        members.push_back(values + space() + "]");
        std::shuffle(members.begin(), members.end(), random);
        std::string payload = space() + "{";
        for (std::size_t k = 0; k < members.size(); ++k) payload += (k ? "," : "") + space() + members[k];
        payload += "}" + space();
        if (pick(3) == 0) {
            damage(payload, random, "{}[]\":, \\x1.e-");
        } else {
            ++intact;
        }
        if (agrees(payload)) ++answered;
    }
    CHECK(answered >= intact);
}
