// The C helpers for plugins (driver_plugin_helpers.h): what they write is
// JSON a real parser reads back, what they read is what JSON says.
#include <nclink/driver_plugin_helpers.h>
#include <nclink/json.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

using nclink::Json;

TEST_CASE("the C JSON writer escapes strings and writes numbers, booleans and nesting as JSON") {
    char buf[512];
    nclink_json_writer w;
    nclink_json_init(&w, buf, sizeof buf);
    nclink_json_begin_object(&w);
    nclink_json_key(&w, "text");
    nclink_json_string(&w, "quote \" backslash \\ newline \n tab \t bell \x07 é");
    nclink_json_key(&w, "list");
    nclink_json_begin_array(&w);
    nclink_json_int(&w, -42);
    nclink_json_uint(&w, 18446744073709551615ull);
    nclink_json_double(&w, 0.1);
    nclink_json_double(&w, 1e300);
    nclink_json_double(&w, std::nan(""));
    nclink_json_double(&w, std::numeric_limits<double>::infinity());
    nclink_json_bool(&w, 1);
    nclink_json_bool(&w, 0);
    nclink_json_null(&w);
    nclink_json_begin_object(&w);
    nclink_json_end_object(&w);
    nclink_json_end_array(&w);
    nclink_json_end_object(&w);
    REQUIRE(nclink_json_ok(&w));
    const std::string text(buf, w.length);
    INFO(text);
    const Json parsed = Json::parse(text);
    CHECK(parsed["text"] == "quote \" backslash \\ newline \n tab \t bell \x07 é");
    const Json& list = parsed["list"];
    CHECK(list[0] == -42);
    CHECK(list[1].get<std::uint64_t>() == 18446744073709551615ull);
    CHECK(list[2] == 0.1);
    CHECK(text.find("0.1,") != std::string::npos);  // shortest form, not 0.10000000000000001
    CHECK(list[3] == 1e300);
    CHECK(list[4].is_null());
    CHECK(list[5].is_null());
    CHECK(list[6] == true);
    CHECK(list[7] == false);
    CHECK(list[8].is_null());
    CHECK(list[9] == Json::object());
}

TEST_CASE("the C JSON writer reports a buffer too small and an unbalanced text") {
    char small[8];
    nclink_json_writer w;
    nclink_json_init(&w, small, sizeof small);
    nclink_json_string(&w, "far too long for eight bytes");
    CHECK_FALSE(nclink_json_ok(&w));
    CHECK(w.overflow);
    char buf[32];
    nclink_json_init(&w, buf, sizeof buf);
    nclink_json_begin_array(&w);
    nclink_json_int(&w, 1);
    CHECK_FALSE(nclink_json_ok(&w));  // still open
    nclink_json_end_array(&w);
    CHECK(nclink_json_ok(&w));
    CHECK(std::string(buf) == "[1]");
}

TEST_CASE("the C JSON readers take numbers, booleans and strings and refuse other types") {
    int b = -1;
    CHECK(nclink_json_read_bool(" true ", &b));
    CHECK(b == 1);
    CHECK(nclink_json_read_bool("false", &b));
    CHECK(b == 0);
    CHECK_FALSE(nclink_json_read_bool("truex", &b));
    CHECK_FALSE(nclink_json_read_bool("1", &b));

    int64_t i = 0;
    CHECK(nclink_json_read_int("-9007199254740993", &i));
    CHECK(i == -9007199254740993LL);
    CHECK_FALSE(nclink_json_read_int("1.5", &i));
    CHECK_FALSE(nclink_json_read_int("99999999999999999999", &i));  // does not fit
    CHECK_FALSE(nclink_json_read_int("\"7\"", &i));

    double d = 0;
    CHECK(nclink_json_read_double("2.5e3", &d));
    CHECK(d == 2500.0);
    CHECK(nclink_json_read_double("7", &d));
    CHECK_FALSE(nclink_json_read_double("null", &d));

    char out[64];
    size_t length = 0;
    CHECK(nclink_json_read_string(R"("a\"b\\c\nd\u00e9\ud83d\ude00")", out, sizeof out, &length));
    CHECK(std::string(out, length) == "a\"b\\c\nd\xc3\xa9\xf0\x9f\x98\x80");
    CHECK_FALSE(nclink_json_read_string("\"unterminated", out, sizeof out, &length));
    CHECK_FALSE(nclink_json_read_string("\"too long for four\"", out, 4, &length));
    CHECK_FALSE(nclink_json_read_string("12", out, sizeof out, &length));
}

TEST_CASE("nclink_json_member finds a key of an object past nested values") {
    const char* params = R"({"skip": {"value": [1, {"x": "}"}]}, "s": "a,\"b\"", "value" : 80 , "last": true})";
    const char* value = nclink_json_member(params, "value");
    REQUIRE(value != nullptr);
    int64_t v = 0;
    CHECK(nclink_json_read_int(value, &v));
    CHECK(v == 80);
    int last = 0;
    REQUIRE(nclink_json_member(params, "last") != nullptr);
    CHECK(nclink_json_read_bool(nclink_json_member(params, "last"), &last));
    CHECK(last == 1);
    CHECK(nclink_json_member(params, "missing") == nullptr);
    CHECK(nclink_json_member("[1,2]", "value") == nullptr);
    CHECK(nclink_json_member("{\"value\"", "value") == nullptr);
    CHECK(nclink_json_member("{}", "value") == nullptr);
    CHECK(nclink_json_member("null", "value") == nullptr);
}
