// The fidelity checks of the tester (checks_fidelity.hpp), each fed the
// answer of an adapter that makes the mistake and of one that does not.
#include "conform/checks.hpp"
#include "conform/checks_fidelity.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::conform;

namespace {

bool mentions(const Problems& problems, const std::string& text) {
    for (const auto& p : problems)
        if (p.find(text) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST_CASE("fidelity: an NG reason is the table-19 string of its error") {
    CHECK(check_table19_reason(Json{{"code", "NG"}, {"reason", "Node not exists"}, {"error", 401}}).empty());
    CHECK(check_table19_reason(Json{{"code", "NG"}, {"reason", " unavailable"}, {"error", 202}}).empty());  // 8.2.12's spacing
    CHECK(check_table19_reason(Json{{"code", "NG"}, {"reason", "my own"}, {"error", -3}}).empty());         // user code
    CHECK(check_table19_reason(Json{{"code", "NG"}, {"reason", "DEV_UNREACHABLE"}, {"error", 301}}).empty());
    CHECK(mentions(check_table19_reason(Json{{"code", "NG"}, {"reason", "/devices: fatal: missing"}, {"error", 412}}),
                   "but error 412 is \"syntax error\""));
    CHECK(mentions(check_table19_reason(Json{{"code", "NG"}, {"reason", "bad model"}}), "not a reason of table 19"));
    CHECK(mentions(check_table19_reason(Json{{"code", "NG"}, {"reason", "x"}, {"error", 999}}), "not a code of table 19"));
    // check_status_keys includes it, so every answer the tester reads is judged.
    CHECK(mentions(check_status_keys(Json{{"code", "NG"}, {"reason", "bad model"}, {"error", 412}}), "table 20"));
}

TEST_CASE("fidelity: refused registrations carry id") {
    const Json refused{{"@id", "r"}, {"guid", "d"}, {"code", "NG"}, {"reason", "Node not exists"}, {"error", 401}};
    CHECK(mentions(check_event_register_response(refused, Json("r"), "d"), "\"id\" is missing (table 49"));
    CHECK(mentions(check_sample_register_response(refused, Json("r"), "d"), "\"id\" is missing (table 39"));
    Json with_id = refused;
    with_id["id"] = "";
    CHECK(check_event_register_response(with_id, Json("r"), "d").empty());
    CHECK(check_sample_register_response(with_id, Json("r"), "d").empty());
}

TEST_CASE("fidelity: values are judged against chapter 7") {
    const LoadResult loaded = parse_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0","devices":[
      {"id":"d","type":"MACHINE","guid":"d","version":"1.0.0","dataItems":[
        {"id":"mode","type":"SPINDLE_MODE"},{"id":"pos","type":"POSITION"}]}]})");
    REQUIRE(loaded.ok());
    const ValueRules rules(*loaded.model);
    CHECK(check_value_rule(rules, "mode", Json("stop")).empty());
    CHECK(mentions(check_value_rule(rules, "mode", Json("spinning")), "table 15"));
    CHECK(mentions(check_value_rule(rules, "pos", Json("12")), "breaks chapter 7"));
    CHECK(check_value_rule(rules, "pos", Json(nullptr)).empty());
}

TEST_CASE("fidelity: appendix A forms are not refused as malformed") {
    CHECK(check_form_understood(Json{{"id", "l"}, {"code", "OK"}, {"values", Json::array({1})}}, "f").empty());
    CHECK(check_form_understood(Json{{"id", "l"}, {"code", "NG"}, {"reason", "Value type error"}, {"error", 405}}, "f").empty());
    CHECK(mentions(check_form_understood(Json{{"id", "l"}, {"code", "NG"}, {"reason", "keys of arguments error"}, {"error", 413}},
                                         "get_attribute"),
                   "get_attribute is refused as malformed"));
    CHECK_FALSE(check_form_understood(Json{{"code", "NG"}, {"reason", "syntax error"}}, "f").empty());
}

TEST_CASE("fidelity: the version round trip") {
    CHECK(check_version_round_trip("1.0", "1.0", "").empty());
    CHECK(check_version_round_trip("", "1.0.1", "1.0.1").empty());
    CHECK(mentions(check_version_round_trip("", "1.0.0", "1.0"), "the model comes back changed"));
    CHECK(mentions(check_version_round_trip("1.0.0", "1.0", ""), "Probe/Version announces \"1.0.0\""));
}

TEST_CASE("fidelity: Set results echo what was done, not the value") {
    const Json params{{"index", 0}, {"offset", 5}, {"length", 10}, {"value", 16}};
    CHECK(
        check_set_echo(Json{{"id", "l"}, {"code", "OK"}, {"params", {{"index", 0}, {"offset", 5}, {"length", 10}}}}, params).empty());
    CHECK(mentions(check_set_echo(Json{{"id", "l"}, {"code", "OK"}}, params), "does not echo \"offset\""));
    CHECK(mentions(check_set_echo(Json{{"id", "l"}, {"code", "OK"}, {"params", params}}, params), "echoes \"value\""));
    CHECK(check_set_echo(Json{{"id", "s"}, {"code", "OK"}}, Json{{"value", 12.5}}).empty());  // 8.2.14 example 1
}
