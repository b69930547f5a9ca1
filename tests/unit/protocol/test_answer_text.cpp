// encode<QueryResponse> and encode<SetResponse>, written without the Json
// tree, against the text to_json().dump() gives: the same bytes, for
// hand-picked and generated answers, but for doubles nlohmann writes with
// other digits than the shortest.
// QueryAnswerText::add_value, the handler's way to write a driver's value,
// against add() of the same entry.
#include "protocol/query_answer_text.hpp"

#include <nclink/dtu.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace nclink;

namespace {

template <class Dtu>
std::string reference(const Dtu& dtu) {
    return to_json(dtu).dump(-1, ' ', false, Json::error_handler_t::replace);
}

// True when `ours` is `theirs` byte for byte but for numbers outside
// strings, where it may have other digits for the same double, never more.
bool same_but_shortest_numbers(const std::string& ours, const std::string& theirs) {
    const auto number_end = [](const std::string& s, std::size_t at) { return s.find_first_not_of("-+.0123456789eE", at); };
    bool in_string = false;
    std::size_t i = 0, j = 0;
    while (i < ours.size() && j < theirs.size()) {
        const char c = ours[i];
        const bool starts_number = !in_string && (c == '-' || (c >= '0' && c <= '9'));
        if (!starts_number) {
            if (c != theirs[j]) return false;
            if (in_string && c == '\\') {
                if (i + 1 >= ours.size() || j + 1 >= theirs.size() || ours[i + 1] != theirs[j + 1]) return false;
                i += 2;
                j += 2;
                continue;
            }
            if (c == '"') in_string = !in_string;
            ++i;
            ++j;
            continue;
        }
        const std::size_t ours_end = number_end(ours, i), theirs_end = number_end(theirs, j);
        const std::string a = ours.substr(i, ours_end - i), b = theirs.substr(j, theirs_end - j);
        if (a != b && (a.size() > b.size() || Json::parse(a) != Json::parse(b) ||
                       (a.find('e') == std::string::npos) != (b.find('e') == std::string::npos)))
            return false;
        i = ours_end;
        j = theirs_end;
    }
    return i == ours.size() && j == theirs.size();
}

QueryResult ok(std::string id, Json values) {
    QueryResult r;
    r.id = std::move(id);
    r.values = std::move(values);
    return r;
}

template <class Entry = QueryResult>
Entry failed(std::string id, ErrorCode code, std::string message = {}) {
    Entry r;
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
        dtu.values.push_back(ok("bad\xff\xfeutf8", Json::array({"bad\xc3"})));                // replaced
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

namespace {

// Random pieces of answers: texts over an alphabet of bytes that need
// escaping, a UTF-8 check or nothing; failures; the head all answers share.
struct Generator {
    explicit Generator(unsigned seed) : rng(seed) {}
    int pick(int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); }
    std::string text() {
        static const std::string alphabet = "ab_Z09\"\\\n\x01\x7f\xc3\xa9\xff ";
        std::string s;
        for (int i = pick(8); i > 0; --i) s += alphabet[static_cast<std::size_t>(pick(static_cast<int>(alphabet.size())))];
        return s;
    }
    double any_double() { return std::ldexp(static_cast<double>(rng()), pick(80) - 40); }
    ResponseStatus failure() {
        static const ErrorCode codes[] = {ErrorCode::node_not_exists,   ErrorCode::timeout,      ErrorCode::unavailable,
                                          ErrorCode::permission_denied, ErrorCode::out_of_range, static_cast<ErrorCode>(-12)};
        return ResponseStatus(make_error(codes[pick(6)], text()));
    }
    /// A failed entry, with the vendor's words half the time.
    template <class Entry>
    void fail(Entry& entry) {
        entry.status = failure();
        if (pick(2)) entry.private_info = Json{{"message", text()}};
    }
    template <class Response>
    void head(Response& dtu) {
        if (pick(5) != 0) dtu.msg_id = pick(2) ? Json(text()) : Json(pick(100000));
        dtu.guid = pick(6) ? text() : std::string();
        if (pick(10) == 0) dtu.status = failure();
        if (pick(10) == 0) dtu.private_info = Json{{"message", text()}};
    }

    std::mt19937 rng;
};

}  // namespace

TEST_CASE("generated Query answers encode to the same bytes as to_json().dump()") {
    Generator g(20261127);
    const auto value = [&] {
        switch (g.pick(6)) {
            case 0: return Json(g.pick(2000) - 1000);
            case 1: return Json(g.any_double());
            case 2: return Json(g.text());
            case 3: return Json(g.pick(2) == 1);
            case 4: return Json(nullptr);
            default: return Json{{g.text(), g.pick(10)}, {"k", Json::array({g.text(), 0.5})}};
        }
    };
    for (int round = 0; round < 300; ++round) {
        QueryResponse dtu;
        g.head(dtu);
        for (int i = g.pick(12); i > 0; --i) {
            QueryResult r;
            r.id = g.text();
            if (g.pick(4) == 0) {
                g.fail(r);
            } else {
                Json values = Json::array();
                for (int v = g.pick(4); v > 0; --v) values.push_back(value());
                r.values = std::move(values);
            }
            if (g.pick(3) == 0) r.params = Json{{"indexes", Json::array({g.pick(5)})}};
            dtu.values.push_back(std::move(r));
        }
        INFO("round " << round);
        const std::string ours = encode(dtu), theirs = reference(dtu);
        INFO(ours);
        REQUIRE(same_but_shortest_numbers(ours, theirs));
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

TEST_CASE("the shortest digits of a double in exponent form are nlohmann's notation") {
    // grisu2 writes 17 digits where 16 read back; the answer has the 16.
    CHECK(number_text(encode(one_value(4.916157685096776e+17))) == "4.916157685096776e+17");
    CHECK(number_text(reference(one_value(4.916157685096776e+17))) == "4.9161576850967757e+17");
    CHECK(number_text(encode(one_value(1e300))) == "1e+300");
    CHECK(number_text(encode(one_value(-2.5e-7))) == "-2.5e-07");
    CHECK(number_text(encode(one_value(1e15))) == "1e+15");
    CHECK(number_text(encode(one_value(123456789012345.6))) == "123456789012345.6");
    CHECK(number_text(encode(one_value(0.000123456789012))) == "0.000123456789012");
    CHECK(number_text(encode(one_value(std::nan("")))) == "null");
}

TEST_CASE("every double of a Query answer reads back exactly, in nlohmann's notation, never longer than it") {
    std::mt19937_64 rng(20261128);
    std::vector<double> values = {
        414.0, -0.0,       0.0,  1e15,         999999999999999.0, 1e14,          0.0001, 0.00012, 1e-5,
        0.5,   -0.25,      1e-7, 4294967295.5, -4294967296.5,     4294967296.25, 1e300,  -1e-300, 123.456,
        0.001, -0.0009999, 1e16, 2.5e15};
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
            // Other digits (grisu2's were not the shortest, or not the
            // nearest of the shortest), never more, in the same notation.
            REQUIRE(ours.size() <= theirs.size());
            REQUIRE((ours.find('e') == std::string::npos) == (theirs.find('e') == std::string::npos));
            REQUIRE(ours.find('.') == theirs.find('.'));
        }
        const double back = Json::parse(ours).get<double>();
        REQUIRE((back == value && std::signbit(back) == std::signbit(value)));
    }
}

TEST_CASE("a driver value written with add_value is the entry add() writes") {
    std::mt19937_64 rng(20261128);
    const Json params_examples[] = {Json(nullptr), Json::object(), Json{{"operation", "get_value"}}};
    for (int i = 0; i < 2000; ++i) {
        Json value;
        switch (rng() % 5) {
            case 0: value = static_cast<double>(static_cast<std::int64_t>(rng() % 2000000) - 1000000) / 1000.0; break;
            case 1: value = static_cast<std::int64_t>(rng() % 100000) - 50000; break;
            case 2: value = "mode " + std::to_string(rng() % 7); break;
            case 3: value = Json::array({1.5, "a\"b", nullptr}); break;
            default: value = Json{{"tool", static_cast<int>(rng() % 40)}, {"wear", 0.25}}; break;
        }
        std::optional<Json> params;
        if (rng() % 2) params = params_examples[rng() % 3];
        QueryResponse head;
        head.msg_id = Json("q" + std::to_string(i));
        head.guid = "dev-1";
        QueryResult entry;
        entry.id = i % 3 ? "pos" : "id \"quoted\"";
        entry.params = params;
        entry.values = Json::array({value});
        protocol_detail::QueryAnswerText by_value(head), by_entry(head);
        by_value.add_value(entry.id, params, value);
        by_entry.add(entry);
        by_value.add(entry);  // mixed with add() in one answer
        by_entry.add(entry);
        REQUIRE(by_value.finish() == by_entry.finish());
    }
}

TEST_CASE("a Set answer's text is the bytes to_json().dump() gives") {
    SetResponse dtu;
    dtu.msg_id = Json("s1");
    dtu.guid = "dev-1";
    SECTION("no items") {}
    SECTION("OK, params echoed, failures with vendor words") {
        SetResult plain;
        plain.id = "ovr";
        dtu.results.push_back(plain);
        SetResult echoed;
        echoed.id = "tools";
        echoed.params = Json{{"operation", "set_value"}, {"index", 1}, {"offset", 0.5}};
        dtu.results.push_back(echoed);
        dtu.results.push_back(failed<SetResult>("maker", ErrorCode::permission_denied));
        dtu.results.push_back(failed<SetResult>("spindle \"S1\"", static_cast<ErrorCode>(-7), "drive fault \xff"));
    }
    SECTION("a refusal as a whole: top-level status, no @id, no guid, privateInfo") {
        dtu.msg_id.reset();
        dtu.guid.clear();
        dtu.status = ResponseStatus(make_error(ErrorCode::timeout, "driver busy"));
        dtu.private_info = Json{{"message", "driver busy for 1000 ms: not written"}};
    }
    CHECK(encode(dtu) == reference(dtu));
}

TEST_CASE("generated Set answers encode to the same bytes as to_json().dump()") {
    Generator g(20261129);
    for (int round = 0; round < 300; ++round) {
        SetResponse dtu;
        g.head(dtu);
        for (int i = g.pick(12); i > 0; --i) {
            SetResult r;
            r.id = g.text();
            if (g.pick(3) == 0) g.fail(r);
            if (g.pick(3) == 0)
                r.params = Json{{"operation", g.text()}, {"index", g.pick(5)}, {"offset", g.any_double()}, {"ok", g.pick(2) == 1}};
            dtu.results.push_back(std::move(r));
        }
        INFO("round " << round);
        const std::string ours = encode(dtu), theirs = reference(dtu);
        INFO(ours);
        REQUIRE(same_but_shortest_numbers(ours, theirs));
    }
}
