#include "values_test_util.hpp"

using namespace nclink;
using namespace values_test;

namespace {
Json q(const char* params, const Json& current, DataKind kind) {
    auto result = evaluate_query(Json::parse(params), current, kind);
    INFO(params);
    if (!result) FAIL(result.error().describe());
    return *result;
}
}  // namespace

TEST_CASE("whole-item query answers (value) for every kind") {
    // Example 8.2.12-1: a single item holding an array.
    const Json single = Json::parse(R"([2, "str1", [1, 2, 3], 100.23])");
    CHECK(q("null", single, DataKind::single) == Json::array({single}));
    CHECK(q("{}", Json(12.5), DataKind::single) == Json::parse("[12.5]"));
    CHECK(q(R"({"operation": "get_value"})", Json("x"), DataKind::single) == Json::parse(R"(["x"])"));
    CHECK(q(R"({"operation": null})", Json(1), DataKind::single) == Json::parse("[1]"));
    CHECK(q("{}", example_dict(), DataKind::dict) == Json::array({example_dict()}));
    CHECK(q(R"({"operation": "get_value"})", example_dict(), DataKind::dict) == Json::array({example_dict()}));
    CHECK(q("null", example_list(), DataKind::list) == Json::array({example_list()}));
    // Unknown current value: the whole item is [null] (the adapter decides
    // whether that is "Unavailable").
    CHECK(q("{}", Json(), DataKind::single) == Json::parse("[null]"));
    const auto parsed = parse_query(Json(), DataKind::list);
    REQUIRE(parsed.ok());
    CHECK(parsed->whole_item());
}

TEST_CASE("evaluate consuming the value answers as evaluate reading it") {
    const Json list = example_list();
    for (const char* params : {"null", "{}", R"({"operation":"get_value","indexes":[0,2]})", R"({"operation":"get_length"})",
                               R"({"operation":"get_attributes","indexes":"0-1"})", R"({"indexes":[99]})"}) {
        INFO(params);
        const auto parsed = parse_query(Json::parse(params), DataKind::list);
        REQUIRE(parsed.ok());
        const auto reading = evaluate(*parsed, list, DataKind::list);
        Json taken = list;
        const auto consuming = evaluate(*parsed, std::move(taken), DataKind::list);
        REQUIRE(reading.ok() == consuming.ok());
        if (reading.ok()) CHECK(*reading == *consuming);
        else CHECK(reading.error().code == consuming.error().code);
    }
    // The whole item is taken over, not copied: the source is left moved-from (null).
    Json big = Json::array({1, 2, 3});
    const auto whole = evaluate(*parse_query(Json(), DataKind::list), std::move(big), DataKind::list);
    REQUIRE(whole.ok());
    CHECK(*whole == Json::parse("[[1,2,3]]"));
    CHECK(big.is_null());
}

TEST_CASE("dict queries of examples 8.2.11-2 / 8.2.12-2") {
    const Json dict = example_dict();
    CHECK(q(R"({"operation": "get_keys"})", dict, DataKind::dict) == Json::parse(R"(["k1","k2","k3"])"));
    CHECK(q(R"({"operation": "get_attributes", "keys": ["k1", "k2"]})", dict, DataKind::dict) ==
          Json::parse(R"(["number","string"])"));
    CHECK(q(R"({"operation": "get_value", "keys": ["k1", "k2", "k3"]})", dict, DataKind::dict) ==
          Json::parse(R"([1234, "kv_string", [1, 2, 3, 4]])"));
    // Request order, repeats, `key` spelling, case of the operation name.
    CHECK(q(R"({"operation": "get_value", "keys": ["k3", "k1", "k3"]})", dict, DataKind::dict) ==
          Json::parse(R"([[1, 2, 3, 4], 1234, [1, 2, 3, 4]])"));
    CHECK(q(R"({"operation": "GET_VALUE", "key": "k2"})", dict, DataKind::dict) == Json::parse(R"(["kv_string"])"));
    CHECK(q(R"({"keys": "k1"})", dict, DataKind::dict) == Json::parse("[1234]"));
    CHECK(q(R"({"operation": "get_attributes", "keys": ["k3"]})", dict, DataKind::dict) == Json::parse(R"(["array"])"));
    CHECK(q(R"({"operation": "get_keys"})", Json::object(), DataKind::dict) == Json::array());
}

TEST_CASE("list queries of examples 8.2.11-3 / 8.2.12-3") {
    const Json list = example_list();
    CHECK(q(R"({"operation": "get_length"})", list, DataKind::list) == Json::parse("[10]"));
    CHECK(q(R"({"operation": "get_value", "indexes": ["0", "4-7"]})", list, DataKind::list) ==
          Json::parse(R"([100.234, 50, "str_v_6", [1.1, 2.2, 3.3], 8])"));
    CHECK(q(R"({"operation": "get_value", "indexes": ["0", "5-8"]})", list, DataKind::list) ==
          Json::parse(R"([100.234, "str_v_6", [1.1, 2.2, 3.3], 8, 9])"));
}

TEST_CASE("list index forms: numbers, mixed, overlapping, single-element ranges") {
    const Json list = example_list();
    CHECK(q(R"({"operation": "get_value", "indexes": [1, "2", "3-3"]})", list, DataKind::list) == Json::parse("[20, 30, 40]"));
    CHECK(q(R"({"operation": "get_value", "indexes": ["7-9", "8-9", 0]})", list, DataKind::list) ==
          Json::parse("[8, 9, 10, 9, 10, 100.234]"));
    CHECK(q(R"({"operation": "get_value", "index": 9})", list, DataKind::list) == Json::parse("[10]"));
    CHECK(q(R"({"operation": "get_value", "index": "9"})", list, DataKind::list) == Json::parse("[10]"));
    CHECK(q(R"({"indexes": "1-2"})", list, DataKind::list) == Json::parse("[20, 30]"));
    CHECK(q(R"({"operation": "get_attributes", "indexes": ["0", "5-6", 9]})", list, DataKind::list) ==
          Json::parse(R"(["number", "string", "array", "number"])"));
    CHECK(q(R"({"operation": "get_attributes", "indexes": [0, 1, 2, 3]})", Json::parse(R"([true, null, {}, -1])"),
            DataKind::list) == Json::parse(R"(["boolean", "null", "object", "number"])"));
}

TEST_CASE("query errors") {
    const Json list = example_list();
    const Json dict = example_dict();
    auto code = [](const char* params, const Json& current, DataKind kind) {
        INFO(params);
        return code_of(evaluate_query(Json::parse(params), current, kind));
    };
    // 101: beyond the list.
    CHECK(code(R"({"operation": "get_value", "indexes": ["0", "8-10"]})", list, DataKind::list) == ErrorCode::out_of_range);
    CHECK(code(R"({"operation": "get_value", "indexes": [-1]})", list, DataKind::list) == ErrorCode::out_of_range);
    // 202: element access on an unknown value.
    CHECK(code(R"({"operation": "get_length"})", Json(), DataKind::list) == ErrorCode::unavailable);
    CHECK(code(R"({"operation": "get_keys"})", Json(), DataKind::dict) == ErrorCode::unavailable);
    CHECK(code(R"({"operation": "get_value", "keys": ["k1"]})", Json(), DataKind::dict) == ErrorCode::unavailable);
    // 402 / 403: get_attributes without selectors; empty selector arrays.
    CHECK(code(R"({"operation": "get_attributes"})", list, DataKind::list) == ErrorCode::no_index);
    CHECK(code(R"({"operation": "get_value", "indexes": []})", list, DataKind::list) == ErrorCode::no_index);
    CHECK(code(R"({"operation": "get_attributes"})", dict, DataKind::dict) == ErrorCode::no_key);
    CHECK(code(R"({"operation": "get_value", "keys": []})", dict, DataKind::dict) == ErrorCode::no_key);
    // 405: wrong types.
    CHECK(code(R"({"operation": "get_value", "indexes": ["abc"]})", list, DataKind::list) == ErrorCode::value_type);
    CHECK(code(R"({"operation": "get_value", "keys": [1]})", dict, DataKind::dict) == ErrorCode::value_type);
    CHECK(code(R"({"operation": "get_value", "keys": {"k1": 1}})", dict, DataKind::dict) == ErrorCode::value_type);
    CHECK(code(R"({"operation": 3})", dict, DataKind::dict) == ErrorCode::value_type);
    // 406 / 407 / 408: operations the kind lacks.
    CHECK(code(R"({"operation": "get_length"})", dict, DataKind::dict) == ErrorCode::unsupported_get_length);
    CHECK(code(R"({"operation": "get_length"})", Json(1), DataKind::single) == ErrorCode::unsupported_get_length);
    CHECK(code(R"({"operation": "get_attributes"})", Json(1), DataKind::single) == ErrorCode::unsupported_get_attributes);
    CHECK(code(R"({"operation": "get_keys"})", list, DataKind::list) == ErrorCode::unsupported_get_keys);
    CHECK(code(R"({"operation": "get_keys"})", Json(1), DataKind::single) == ErrorCode::unsupported_get_keys);
    // 409: parameters the item/operation does not take.
    CHECK(code(R"({"keys": ["a"]})", Json(1), DataKind::single) == ErrorCode::arguments_nimiety);
    CHECK(code(R"({"indexes": ["0"]})", Json(1), DataKind::single) == ErrorCode::arguments_nimiety);
    CHECK(code(R"({"indexes": ["0"]})", dict, DataKind::dict) == ErrorCode::arguments_nimiety);
    CHECK(code(R"({"keys": ["k1"]})", list, DataKind::list) == ErrorCode::arguments_nimiety);
    CHECK(code(R"({"operation": "get_keys", "keys": ["k1"]})", dict, DataKind::dict) == ErrorCode::arguments_nimiety);
    CHECK(code(R"({"operation": "get_length", "indexes": [0]})", list, DataKind::list) == ErrorCode::arguments_nimiety);
    CHECK(code(R"({"key": "k1", "keys": ["k2"]})", dict, DataKind::dict) == ErrorCode::arguments_nimiety);
    // 410: key not in the dict.
    CHECK(code(R"({"operation": "get_value", "keys": ["k1", "nope"]})", dict, DataKind::dict) == ErrorCode::key_error);
    CHECK(code(R"({"operation": "get_attributes", "keys": ["nope"]})", dict, DataKind::dict) == ErrorCode::key_error);
    // 412: params not an object, malformed ranges.
    CHECK(code(R"("get_keys")", dict, DataKind::dict) == ErrorCode::syntax_error);
    CHECK(code(R"([1])", list, DataKind::list) == ErrorCode::syntax_error);
    CHECK(code(R"({"indexes": ["8-5"]})", list, DataKind::list) == ErrorCode::syntax_error);
    CHECK(code(R"({"indexes": ["5-"]})", list, DataKind::list) == ErrorCode::syntax_error);
    // 413: unknown operation or parameter name (Set parameters included).
    CHECK(code(R"({"operation": "get_everything"})", dict, DataKind::dict) == ErrorCode::keys_of_arguments);
    CHECK(code(R"({"operation": "set_value"})", dict, DataKind::dict) == ErrorCode::keys_of_arguments);
    CHECK(code(R"({"filter": 1})", dict, DataKind::dict) == ErrorCode::keys_of_arguments);
    CHECK(code(R"({"value": 1})", Json(1), DataKind::single) == ErrorCode::keys_of_arguments);
}

TEST_CASE("evaluate re-checks hand-built requests") {
    QueryParams request;
    request.operation = QueryOperation::get_value;
    request.indexes = {{0, 1}};
    CHECK(code_of(evaluate(request, example_dict(), DataKind::dict)) == ErrorCode::arguments_nimiety);
    CHECK(code_of(evaluate(request, Json::array({1}), DataKind::list)) == ErrorCode::out_of_range);
    CHECK(*evaluate(request, Json::array({1, 2}), DataKind::list) == Json::array({1, 2}));
    request.operation = QueryOperation::get_keys;
    CHECK(code_of(evaluate(request, Json::array({1, 2}), DataKind::list)) == ErrorCode::unsupported_get_keys);
    request.operation = QueryOperation::get_attributes;
    request.indexes.clear();
    CHECK(code_of(evaluate(request, Json::array({1}), DataKind::list)) == ErrorCode::no_index);
    // A list value that is not an array is unavailable, not a crash.
    request.indexes = {{0, 0}};
    CHECK(code_of(evaluate(request, Json("oops"), DataKind::list)) == ErrorCode::unavailable);
}

TEST_CASE("every failure carries the table-19 reason") {
    const auto result = evaluate_query(Json::parse(R"({"operation": "get_keys"})"), example_list(), DataKind::list);
    REQUIRE_FALSE(result.ok());
    CHECK(reason(result.error().code) == "unsupported operation get_keys");
    CHECK_FALSE(result.error().message.empty());
}
