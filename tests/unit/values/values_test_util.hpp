// Shared helpers of the value-operation tests.
#pragma once

#include <nclink/values.hpp>

#include <catch2/catch.hpp>

namespace values_test {

using nclink::ErrorCode;
using nclink::Json;

/// The error code of a failed result (fails the test when it succeeded).
template <class R>
ErrorCode code_of(const R& result) {
    REQUIRE_FALSE(result.ok());
    return result.error().code;
}

/// The example list of 8.2.12-3 (the standard prints "100,234"; it means 100.234).
inline Json example_list() { return Json::parse(R"([100.234, 20, 30, 40, 50, "str_v_6", [1.1, 2.2, 3.3], 8, 9, 10])"); }

/// The example dict of 8.2.12-2.
inline Json example_dict() { return Json::parse(R"({"k1": 1234, "k2": "kv_string", "k3": [1, 2, 3, 4]})"); }

}  // namespace values_test
