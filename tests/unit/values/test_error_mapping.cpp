// One scenario per table-19 code the value operations produce, checked
// against the exact reason string (docs/values.md has the full table).
#include "values_test_util.hpp"

#include <string>

using namespace nclink;
using namespace values_test;

namespace {

struct Scenario {
    const char* dtu;  // "query" or "set"
    const char* params;
    Json current;
    DataKind kind;
    ErrorCode code;
    const char* reason;
};

ErrorCode run(const Scenario& s) {
    if (std::string(s.dtu) == "query") return code_of(evaluate_query(Json::parse(s.params), s.current, s.kind));
    Json copy = s.current;
    const bool setable = std::string(s.dtu) != "set-readonly";
    return code_of(apply_set(Json::parse(s.params), copy, s.kind, setable));
}

}  // namespace

TEST_CASE("each error code comes with its table-19 reason") {
    const Json list = example_list();
    const Json dict = example_dict();
    const std::vector<Scenario> scenarios{
        {"query", R"({"indexes": ["9-10"]})", list, DataKind::list, ErrorCode::out_of_range, "Out of Range"},
        {"set", R"({"operation": "add", "key": "n"})", dict, DataKind::dict, ErrorCode::parameter_missing, "Parameter Missing"},
        {"query", R"({"operation": "get_length"})", Json(), DataKind::list, ErrorCode::unavailable, "Unavailable"},
        {"set-readonly", R"({"value": 1})", Json(0), DataKind::single, ErrorCode::permission_denied, "Permission Denied"},
        {"query", R"({"operation": "get_attributes"})", list, DataKind::list, ErrorCode::no_index, "No index passed in"},
        {"set", R"({"operation": "delete"})", dict, DataKind::dict, ErrorCode::no_key, "No key passed in"},
        {"query", R"({"indexes": ["abc"]})", list, DataKind::list, ErrorCode::value_type, "Value type error"},
        {"query", R"({"operation": "get_length"})", dict, DataKind::dict, ErrorCode::unsupported_get_length,
         "unsupported operation get_length"},
        {"query", R"({"operation": "get_attributes"})", Json(1), DataKind::single, ErrorCode::unsupported_get_attributes,
         "unsupported operation get_attributes"},
        {"query", R"({"operation": "get_keys"})", list, DataKind::list, ErrorCode::unsupported_get_keys,
         "unsupported operation get_keys"},
        {"query", R"({"keys": ["a"]})", Json(1), DataKind::single, ErrorCode::arguments_nimiety, "arguments nimiety"},
        {"query", R"({"keys": ["nope"]})", dict, DataKind::dict, ErrorCode::key_error, "key error"},
        {"set", R"({"operation": "add", "value": 1})", Json(1), DataKind::single, ErrorCode::attribute_error, "Attribute error"},
        {"query", R"({"indexes": ["8-5"]})", list, DataKind::list, ErrorCode::syntax_error, "syntax error"},
        {"set", R"({"operation": "upsert", "value": 1})", Json(1), DataKind::single, ErrorCode::keys_of_arguments,
         "keys of arguments error"},
    };
    for (const auto& s : scenarios) {
        INFO(s.dtu << " " << s.params);
        const auto code = run(s);
        CHECK(code == s.code);
        CHECK(reason(code) == s.reason);
    }
}
