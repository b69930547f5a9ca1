#include "values_test_util.hpp"

using namespace nclink;
using namespace values_test;

namespace {
// Applies a set and fails the test on error.
void s(const char* params, Json& current, DataKind kind) {
    INFO(params);
    auto result = apply_set(Json::parse(params), current, kind, true);
    if (!result) FAIL(result.error().describe());
}
// Applies a set that must fail, checks the value is untouched, returns the code.
ErrorCode s_fails(const char* params, const Json& current, DataKind kind, bool setable = true) {
    INFO(params);
    Json copy = current;
    auto result = apply_set(Json::parse(params), copy, kind, setable);
    CHECK(copy == current);
    const auto code = code_of(result);
    CHECK(reason(code) != "Success");
    return code;
}
}  // namespace

TEST_CASE("single items: whole set, examples 8.2.13-1") {
    Json a = 1.0;
    Json b = 2.0;
    s(R"({"value": 12.5})", a, DataKind::single);
    s(R"({"operation": "set_value", "value": 22.3})", b, DataKind::single);
    CHECK(a == 12.5);
    CHECK(b == 22.3);
    s(R"({"values": 7})", a, DataKind::single);  // `values` as a plain value
    CHECK(a == 7);
    s(R"({"values": [8]})", a, DataKind::single);  // one value for one target
    CHECK(a == 8);
    Json unknown;  // null accepts any type
    s(R"({"value": "now a string"})", unknown, DataKind::single);
    CHECK(unknown == "now a string");
    Json arr = Json::parse("[1, 2]");
    s(R"({"value": [3, 4, 5]})", arr, DataKind::single);
    CHECK(arr == Json::parse("[3, 4, 5]"));
}

TEST_CASE("dict set_value / add / delete, examples 8.2.13-2") {
    Json dict = example_dict();
    s(R"({"operation": "set_value", "key": "k1", "value": 2})", dict, DataKind::dict);
    CHECK(dict["k1"] == 2);
    s(R"({"key": "k2", "value": "other"})", dict, DataKind::dict);
    CHECK(dict["k2"] == "other");
    s(R"({"operation": "add", "key": "AAA", "value": "111"})", dict, DataKind::dict);
    CHECK(dict["AAA"] == "111");
    s(R"({"operation": "delete", "key": "AAA"})", dict, DataKind::dict);
    CHECK_FALSE(dict.contains("AAA"));
    // Several keys: one value each (example 8.2.14-2's "set_values"), or one for all.
    s(R"({"operation": "set_values", "keys": ["k1", "k2"], "values": [5, "five"]})", dict, DataKind::dict);
    CHECK(dict["k1"] == 5);
    CHECK(dict["k2"] == "five");
    s(R"({"keys": ["k1", "k1"], "value": 6})", dict, DataKind::dict);
    CHECK(dict["k1"] == 6);
    s(R"({"operation": "add", "keys": ["x", "y"], "values": [1, null]})", dict, DataKind::dict);
    CHECK(dict["x"] == 1);
    CHECK(dict["y"].is_null());
    s(R"({"operation": "delete", "keys": ["x", "y", "x"]})", dict, DataKind::dict);
    CHECK(dict == Json::parse(R"({"k1": 6, "k2": "five", "k3": [1, 2, 3, 4]})"));
    // Whole dict.
    s(R"({"value": {"only": true}})", dict, DataKind::dict);
    CHECK(dict == Json::parse(R"({"only": true})"));
    Json unknown;
    s(R"({"value": {}})", unknown, DataKind::dict);
    CHECK(unknown == Json::object());
}

TEST_CASE("list set_value / add / delete") {
    Json list = example_list();
    s(R"({"index": 1, "value": 21})", list, DataKind::list);
    CHECK(list[1] == 21);
    s(R"({"operation": "set_value", "index": "5", "value": "s"})", list, DataKind::list);
    CHECK(list[5] == "s");
    s(R"({"indexes": ["1-3", 9], "values": [1, 2, 3, 4]})", list, DataKind::list);
    CHECK(list == Json::parse(R"([100.234, 1, 2, 3, 50, "s", [1.1, 2.2, 3.3], 8, 9, 4])"));
    s(R"({"indexes": ["7-9"], "value": 0})", list, DataKind::list);  // one value for all
    CHECK(list == Json::parse(R"([100.234, 1, 2, 3, 50, "s", [1.1, 2.2, 3.3], 0, 0, 0])"));
    s(R"({"index": ["0"], "value": 1})", list, DataKind::list);  // `index` as array, example 8.2.14-3
    CHECK(list[0] == 1);

    Json l = Json::parse("[1, 2, 3]");
    s(R"({"operation": "add", "index": 0, "value": 0})", l, DataKind::list);
    CHECK(l == Json::parse("[0, 1, 2, 3]"));
    s(R"({"operation": "add", "index": 2, "value": "mid"})", l, DataKind::list);
    CHECK(l == Json::parse(R"([0, 1, "mid", 2, 3])"));
    s(R"({"operation": "add", "index": 5, "value": [9]})", l, DataKind::list);  // index == length appends
    CHECK(l == Json::parse(R"([0, 1, "mid", 2, 3, [9]])"));
    s(R"({"operation": "delete", "index": 2})", l, DataKind::list);
    CHECK(l == Json::parse(R"([0, 1, 2, 3, [9]])"));
    // Indexes name elements before the delete; overlaps delete once.
    s(R"({"operation": "delete", "indexes": ["0-1", "1", 4]})", l, DataKind::list);
    CHECK(l == Json::parse("[2, 3]"));
    // Whole list.
    s(R"({"value": ["a"]})", l, DataKind::list);
    CHECK(l == Json::parse(R"(["a"])"));
}

TEST_CASE("set is all-or-nothing") {
    const Json dict = example_dict();
    // The second key is missing: the first is not changed either.
    CHECK(s_fails(R"({"keys": ["k1", "nope"], "values": [1, 2]})", dict, DataKind::dict) == ErrorCode::key_error);
    // The second value has the wrong type.
    CHECK(s_fails(R"({"keys": ["k1", "k2"], "values": [1, 2]})", dict, DataKind::dict) == ErrorCode::value_type);
    CHECK(s_fails(R"({"operation": "add", "keys": ["new", "k1"], "values": [1, 2]})", dict, DataKind::dict) == ErrorCode::key_error);
    CHECK(s_fails(R"({"operation": "add", "keys": ["new", "new"], "values": [1, 2]})", dict, DataKind::dict) ==
          ErrorCode::key_error);
    CHECK(s_fails(R"({"operation": "delete", "keys": ["k1", "nope"]})", dict, DataKind::dict) == ErrorCode::key_error);
    const Json list = example_list();
    CHECK(s_fails(R"({"indexes": ["0-2"], "values": [1, 2, "three"]})", list, DataKind::list) == ErrorCode::value_type);
    CHECK(s_fails(R"({"indexes": ["8-10"], "value": 1})", list, DataKind::list) == ErrorCode::out_of_range);
    CHECK(s_fails(R"({"operation": "delete", "indexes": [0, 10]})", list, DataKind::list) == ErrorCode::out_of_range);
    CHECK(s_fails(R"({"indexes": [5, 1], "offset": 0, "length": 1, "value": "x"})", list, DataKind::list) == ErrorCode::value_type);
}

TEST_CASE("set errors") {
    const Json single = 1;
    const Json dict = example_dict();
    const Json list = example_list();
    // 101
    CHECK(s_fails(R"({"index": 10, "value": 1})", list, DataKind::list) == ErrorCode::out_of_range);
    CHECK(s_fails(R"({"operation": "add", "index": 11, "value": 1})", list, DataKind::list) == ErrorCode::out_of_range);
    CHECK(s_fails(R"({"operation": "delete", "index": 10})", list, DataKind::list) == ErrorCode::out_of_range);
    CHECK(s_fails(R"({"index": -2, "value": 1})", list, DataKind::list) == ErrorCode::out_of_range);
    // 102: nothing to write
    CHECK(s_fails("null", single, DataKind::single) == ErrorCode::parameter_missing);
    CHECK(s_fails("{}", single, DataKind::single) == ErrorCode::parameter_missing);
    CHECK(s_fails(R"({"operation": "set_value"})", single, DataKind::single) == ErrorCode::parameter_missing);
    CHECK(s_fails(R"({"operation": "add", "key": "n"})", dict, DataKind::dict) == ErrorCode::parameter_missing);
    CHECK(s_fails(R"({"operation": "add", "index": 0})", list, DataKind::list) == ErrorCode::parameter_missing);
    CHECK(s_fails(R"({"indexes": ["0-3"], "values": [1, 2]})", list, DataKind::list) == ErrorCode::parameter_missing);
    CHECK(s_fails(R"({"values": []})", single, DataKind::single) == ErrorCode::parameter_missing);
    // 202: element access on an unknown value
    CHECK(s_fails(R"({"key": "k1", "value": 1})", Json(), DataKind::dict) == ErrorCode::unavailable);
    CHECK(s_fails(R"({"operation": "add", "index": 0, "value": 1})", Json(), DataKind::list) == ErrorCode::unavailable);
    // 301: not setable, checked before anything else
    CHECK(s_fails(R"({"value": 2})", single, DataKind::single, false) == ErrorCode::permission_denied);
    CHECK(s_fails(R"({"bogus": 2})", single, DataKind::single, false) == ErrorCode::permission_denied);
    // 402 / 403
    CHECK(s_fails(R"({"operation": "delete"})", list, DataKind::list) == ErrorCode::no_index);
    CHECK(s_fails(R"({"operation": "add", "value": 1})", list, DataKind::list) == ErrorCode::no_index);
    CHECK(s_fails(R"({"offset": 1, "value": 1})", list, DataKind::list) == ErrorCode::no_index);
    CHECK(s_fails(R"({"indexes": [], "value": 1})", list, DataKind::list) == ErrorCode::no_index);
    CHECK(s_fails(R"({"operation": "delete"})", dict, DataKind::dict) == ErrorCode::no_key);
    CHECK(s_fails(R"({"operation": "add", "value": 1})", dict, DataKind::dict) == ErrorCode::no_key);
    CHECK(s_fails(R"({"keys": [], "value": 1})", dict, DataKind::dict) == ErrorCode::no_key);
    // 405: types
    CHECK(s_fails(R"({"value": "one"})", single, DataKind::single) == ErrorCode::value_type);
    CHECK(s_fails(R"({"value": null})", single, DataKind::single) == ErrorCode::value_type);
    CHECK(s_fails(R"({"key": "k1", "value": "x"})", dict, DataKind::dict) == ErrorCode::value_type);
    CHECK(s_fails(R"({"key": "k3", "value": {"a": 1}})", dict, DataKind::dict) == ErrorCode::value_type);
    CHECK(s_fails(R"({"index": 5, "value": 5})", list, DataKind::list) == ErrorCode::value_type);
    CHECK(s_fails(R"({"index": "abc", "value": 5})", list, DataKind::list) == ErrorCode::value_type);
    CHECK(s_fails(R"({"key": 1, "value": 5})", dict, DataKind::dict) == ErrorCode::value_type);
    CHECK(s_fails(R"({"value": [1]})", dict, DataKind::dict) == ErrorCode::value_type);
    CHECK(s_fails(R"({"value": {"a": 1}})", list, DataKind::list) == ErrorCode::value_type);
    CHECK(s_fails(R"({"operation": ["add"], "value": 1})", single, DataKind::single) == ErrorCode::value_type);
    CHECK(s_fails(R"({"index": 0, "offset": "x", "value": 1})", list, DataKind::list) == ErrorCode::value_type);
    // 409: more than the operation takes
    CHECK(s_fails(R"({"key": "a", "value": 2})", single, DataKind::single) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"index": 0, "value": 2})", single, DataKind::single) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"offset": 1, "value": 2})", single, DataKind::single) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"length": 1, "value": 2})", single, DataKind::single) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"index": 0, "value": 2})", dict, DataKind::dict) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"key": "k1", "offset": 0, "value": 2})", dict, DataKind::dict) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"key": "k1", "value": 2})", list, DataKind::list) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"operation": "delete", "key": "k1", "value": 2})", dict, DataKind::dict) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"operation": "add", "index": 0, "offset": 1, "value": 2})", list, DataKind::list) ==
          ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"operation": "add", "indexes": ["0-1"], "value": 2})", list, DataKind::list) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"value": 1, "values": [1]})", single, DataKind::single) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"values": [1, 2]})", single, DataKind::single) == ErrorCode::arguments_nimiety);
    CHECK(s_fails(R"({"index": 0, "indexes": [1], "value": 1})", list, DataKind::list) == ErrorCode::arguments_nimiety);
    // 410
    CHECK(s_fails(R"({"key": "nope", "value": 1})", dict, DataKind::dict) == ErrorCode::key_error);
    CHECK(s_fails(R"({"operation": "add", "key": "k1", "value": 1})", dict, DataKind::dict) == ErrorCode::key_error);
    CHECK(s_fails(R"({"operation": "delete", "key": "nope"})", dict, DataKind::dict) == ErrorCode::key_error);
    // 411: add/delete on a single value
    CHECK(s_fails(R"({"operation": "add", "value": 1})", single, DataKind::single) == ErrorCode::attribute_error);
    CHECK(s_fails(R"({"operation": "delete"})", single, DataKind::single) == ErrorCode::attribute_error);
    // 412
    CHECK(s_fails(R"([{"value": 1}])", single, DataKind::single) == ErrorCode::syntax_error);
    CHECK(s_fails(R"(12.5)", single, DataKind::single) == ErrorCode::syntax_error);
    CHECK(s_fails(R"({"indexes": ["8-5"], "value": 1})", list, DataKind::list) == ErrorCode::syntax_error);
    // 413
    CHECK(s_fails(R"({"operation": "replace", "value": 1})", single, DataKind::single) == ErrorCode::keys_of_arguments);
    CHECK(s_fails(R"({"operation": "get_value"})", single, DataKind::single) == ErrorCode::keys_of_arguments);
    CHECK(s_fails(R"({"value": 1, "type": "number"})", single, DataKind::single) == ErrorCode::keys_of_arguments);
}

TEST_CASE("parse_set gives drivers a typed request") {
    const auto parsed = parse_set(
        Json::parse(R"({"operation": "set_value", "index": 0, "offset": 5, "length": 10, "value": 16})"), DataKind::list);
    REQUIRE(parsed.ok());
    CHECK(parsed->operation == SetOperation::set_value);
    CHECK(parsed->indexes == std::vector<IndexRange>{{0, 0}});
    CHECK(parsed->offset == std::optional<std::size_t>{5});
    CHECK(parsed->length == std::optional<std::size_t>{10});
    CHECK(parsed->target_count() == 1);
    CHECK(parsed->value_for(0) == 16);
    CHECK(to_string(parsed->operation) == "set_value");

    const auto del = parse_set(Json::parse(R"({"operation": "delete", "keys": ["a", "b"]})"), DataKind::dict);
    REQUIRE(del.ok());
    CHECK(del->operation == SetOperation::remove);
    CHECK(to_string(del->operation) == "delete");
    CHECK(del->keys == std::vector<std::string>{"a", "b"});
    CHECK(del->values.empty());

    const auto many = parse_set(Json::parse(R"({"indexes": ["0", "4-6"], "values": [1, 2, 3, 4]})"), DataKind::list);
    REQUIRE(many.ok());
    CHECK(many->target_count() == 4);
    CHECK(many->value_for(3) == 4);
}

TEST_CASE("apply re-checks hand-built requests") {
    Json dict = example_dict();
    SetParams request;
    request.keys = {"k1"};
    CHECK(code_of(apply(request, dict, DataKind::dict, true)) == ErrorCode::parameter_missing);
    request.values = {Json(1), Json(2)};
    CHECK(code_of(apply(request, dict, DataKind::dict, true)) == ErrorCode::arguments_nimiety);
    request.values = {Json(1)};
    CHECK(code_of(apply(request, dict, DataKind::dict, false)) == ErrorCode::permission_denied);
    CHECK(code_of(apply(request, dict, DataKind::single, true)) == ErrorCode::arguments_nimiety);
    REQUIRE(apply(request, dict, DataKind::dict, true).ok());
    CHECK(dict["k1"] == 1);
    request.operation = SetOperation::add;
    request.keys.clear();
    CHECK(code_of(apply(request, dict, DataKind::single, true)) == ErrorCode::attribute_error);
    CHECK(code_of(apply(request, dict, DataKind::dict, true)) == ErrorCode::no_key);
}
