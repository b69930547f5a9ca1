// encode<QueryResponse>, written without the Json tree, against the text
// to_json().dump() gives: the same bytes, for hand-picked and generated answers,
// but for doubles nlohmann writes with more digits than they need.
#include <nclink/dtu.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace nclink;

namespace {

std::string reference(const QueryResponse& dtu) { return to_json(dtu).dump(-1, ' ', false, Json::error_handler_t::replace); }

QueryResult ok(std::string id, Json values) {
    QueryResult r;
    r.id = std::move(id);
    r.values = std::move(values);
    return r;
}

QueryResult failed(std::string id, ErrorCode code, std::string message = {}) {
    QueryResult r;
    r.id = std::move(id);
    r.status = ResponseStatus(make_error(code, message));
    if (!message.empty()) r.private_info = Json{{"message", message}};
    return r;
}

}  // namespace

TEST_CASE("a Query answer's text is the bytes to_json().dump() gives") {
    QueryResponse dtu;
    dtu.msg_id = Json("q1");
    dtu.guid = "dev-1";
    SECTION("no items") {}
    SECTION("values of every JSON type, params echoed") {
        dtu.values.push_back(ok("pos", Json::array({12.5})));
        dtu.values.push_back(ok("count", Json::array({-3, 18446744073709551615ULL})));
        dtu.values.push_back(ok("flags", Json::array({true, false, nullptr})));
        dtu.values.push_back(ok("tools", Json::array({Json{{"z", 1}, {"a", Json::array({1e300, 1e-7, 0.1})}}})));
        QueryResult with_params = ok("list", Json::array({"a", "b"}));
        with_params.params = Json{{"indexes", Json::array({0, 1})}, {"keys", nullptr}};
        dtu.values.push_back(with_params);
    }
    SECTION("failures: table-19 codes, a vendor code with its words, the driver's message") {
        dtu.values.push_back(failed("ghost", ErrorCode::node_not_exists));
        dtu.values.push_back(failed("spindle", ErrorCode::timeout, "driver did not answer within 1000 ms"));
        QueryResult vendor;
        vendor.id = "load";
        vendor.status = ResponseStatus(make_error(static_cast<ErrorCode>(-7), "spindle drive fault \"E7\""));
        vendor.private_info = Json{{"message", "spindle drive fault \"E7\""}};
        dtu.values.push_back(vendor);
    }
    SECTION("strings that need escaping or UTF-8 checks: ids, guid, reasons, values") {
        dtu.guid = "dev\"1\\\n";
        dtu.values.push_back(ok("quote\"back\\slash", Json::array({"tab\there"})));
        dtu.values.push_back(ok("control\x01\x1f", Json::array({"\x7f"})));
        dtu.values.push_back(ok("\xe4\xb8\xad\xe6\x96\x87", Json::array({"\xe4\xb8\xad"})));  // UTF-8
        dtu.values.push_back(ok("bad\xff\xfeutf8", Json::array({"bad\xc3"})));                  // replaced
        dtu.values.push_back(ok("", Json::array()));
    }
    SECTION("a refusal as a whole: top-level status, no @id, no guid, privateInfo") {
        dtu.msg_id.reset();
        dtu.guid.clear();
        dtu.status = ResponseStatus(make_error(ErrorCode::syntax_error));
        dtu.private_info = Json{{"message", "not JSON"}};
    }
    SECTION("a numeric @id and an OK top-level status") {
        dtu.msg_id = Json(42);
        dtu.status = ResponseStatus::success();
        dtu.values.push_back(ok("pos", Json::array({1})));
    }
    CHECK(encode(dtu) == reference(dtu));
}

TEST_CASE("generated Query answers encode to the same bytes as to_json().dump()") {
    std::mt19937 rng(20261127);
    const auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
    const std::string alphabet = "ab_Z09\"\\\n\x01\x7f\xc3\xa9\xff ";
    const auto text = [&] {
        std::string s;
        for (int i = pick(8); i > 0; --i) s += alphabet[static_cast<std::size_t>(pick(static_cast<int>(alphabet.size())))];
        return s;
    };
    const auto value = [&] {
        switch (pick(6)) {
            case 0: return Json(pick(2000) - 1000);
            case 1: return Json(std::ldexp(static_cast<double>(rng()), pick(80) - 40));
            case 2: return Json(text());
            case 3: return Json(pick(2) == 1);
            case 4: return Json(nullptr);
            default: return Json{{text(), pick(10)}, {"k", Json::array({text(), 0.5})}};
        }
    };
    const ErrorCode codes[] = {ErrorCode::node_not_exists, ErrorCode::timeout, ErrorCode::unavailable,
                               ErrorCode::out_of_range, static_cast<ErrorCode>(-12)};
    for (int round = 0; round < 300; ++round) {
        QueryResponse dtu;
        if (pick(5) != 0) dtu.msg_id = pick(2) ? Json(text()) : Json(pick(100000));
        dtu.guid = pick(6) ? text() : std::string();
        if (pick(10) == 0) dtu.status = ResponseStatus(make_error(codes[pick(5)], text()));
        if (pick(10) == 0) dtu.private_info = Json{{"message", text()}};
        for (int i = pick(12); i > 0; --i) {
            QueryResult r;
            r.id = text();
            if (pick(4) == 0) {
                r.status = ResponseStatus(make_error(codes[pick(5)], text()));
                if (pick(2)) r.private_info = Json{{"message", text()}};
            } else {
                Json values = Json::array();
                for (int v = pick(4); v > 0; --v) values.push_back(value());
                r.values = std::move(values);
            }
            if (pick(3) == 0) r.params = Json{{"indexes", Json::array({pick(5)})}};
            dtu.values.push_back(std::move(r));
        }
        INFO("round " << round);
        REQUIRE(encode(dtu) == reference(dtu));
    }
}

namespace {

// The text of the one value of a one-item answer.
std::string number_text(const std::string& answer) {
    const auto start = answer.find("\"values\":[", answer.find("\"id\":")) + 10;
    return answer.substr(start, answer.find(']', start) - start);
}

QueryResponse one_value(double value) {
    QueryResponse dtu;
    dtu.values.push_back(ok("v", Json::array({value})));
    return dtu;
}

}  // namespace

TEST_CASE("a double in a Query answer gets its shortest digits where nlohmann's are longer") {
    // nlohmann's grisu2 writes these with 17 digits; both texts read back to
    // the same double, the answer's is the shortest.
    for (const double value : {460.47851, -135.484178, 1595247.068539, -91.372757}) {
        const QueryResponse dtu = one_value(value);
        const std::string text = encode(dtu);
        const std::string longer = number_text(reference(dtu));
        INFO(longer);
        REQUIRE(longer.size() > 12);
        CHECK(number_text(text).size() < longer.size());
        CHECK(Json::parse(number_text(text)).get<double>() == value);
        CHECK(Json::parse(text) == Json::parse(reference(dtu)));
    }
    CHECK(number_text(encode(one_value(460.47851))) == "460.47851");
}

TEST_CASE("every double of a Query answer reads back exactly, in nlohmann's notation, never longer than it") {
    std::mt19937_64 rng(20261128);
    std::vector<double> values = {414.0,  -0.0,   0.0,     1e15,     999999999999999.0, 1e14,  0.0001,   0.00012,
                                  1e-5,   0.5,    -0.25,   1e-7,     4294967295.5,      -4294967296.5, 4294967296.25,
                                  1e300,  -1e-300, 123.456, 0.001,   -0.0009999,        1e16,  2.5e15};
    for (int i = 0; i < 200000; ++i) {
        // Decimals with 0..7 fraction digits over many magnitudes, and raw bit patterns.
        const auto decimals = static_cast<std::size_t>(rng() % 8);
        std::string text = std::to_string((rng() % 10000000000ULL) >> (rng() % 34));
        if (decimals > 0) {
            const std::string fraction = std::to_string(rng() % static_cast<std::uint64_t>(std::pow(10.0, decimals)));
            text += "." + std::string(decimals - fraction.size(), '0') + fraction;
        }
        double value = std::stod(text);
        if (rng() & 1) value = -value;
        values.push_back(value);
        std::uint64_t bits = rng();
        double raw;
        std::memcpy(&raw, &bits, sizeof raw);
        if (std::isfinite(raw)) values.push_back(raw);
    }
    for (const double value : values) {
        const QueryResponse dtu = one_value(value);
        const std::string ours = number_text(encode(dtu));
        const std::string theirs = number_text(reference(dtu));
        INFO(theirs);
        if (ours != theirs) {
            REQUIRE(ours.size() < theirs.size());
            REQUIRE(ours.find_first_of("eE") == std::string::npos);
        }
        const double back = Json::parse(ours).get<double>();
        REQUIRE((back == value && std::signbit(back) == std::signbit(value)));
    }
}
