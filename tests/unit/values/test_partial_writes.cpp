// offset/length on list elements: bits of integers (HNC registers), code
// points of strings, elements of arrays.
#include "values_test_util.hpp"

#include <cstdint>

using namespace nclink;
using namespace values_test;

namespace {
Json patched(Json list, const char* params) {
    INFO(params);
    auto result = apply_set(Json::parse(params), list, DataKind::list, true);
    if (!result) FAIL(result.error().describe());
    return list;
}
ErrorCode patch_fails(const Json& list, const char* params) {
    INFO(params);
    Json copy = list;
    auto result = apply_set(Json::parse(params), copy, DataKind::list, true);
    CHECK(copy == list);
    return code_of(result);
}
}  // namespace

TEST_CASE("example 8.2.13-3: bit field of 10 bits at offset 5 set to 16") {
    const Json list = Json::parse("[0, 65535]");
    CHECK(patched(list, R"({"operation": "set_value", "index": 0, "offset": 5, "length": 10, "value": 16})") ==
          Json::parse("[512, 65535]"));
    CHECK(patched(list, R"({"index": 1, "offset": 5, "length": 10, "value": 16})") == Json::array({0, 0x821F}));
    // Offset and length as numeric strings too.
    CHECK(patched(list, R"({"index": "0", "offset": "5", "length": "10", "value": 16})") == Json::parse("[512, 65535]"));
}

TEST_CASE("HNC register convention: value sets or clears bit `offset`") {
    const Json regs = Json::parse("[10, 4.0]");  // 0b1010
    CHECK(patched(regs, R"({"index": 0, "offset": 0, "value": 1})")[0] == 11);
    CHECK(patched(regs, R"({"index": 0, "offset": 0, "value": true})")[0] == 11);
    CHECK(patched(regs, R"({"index": 0, "offset": 3, "value": 0})")[0] == 2);
    CHECK(patched(regs, R"({"index": 0, "offset": 3, "value": false})")[0] == 2);
    CHECK(patched(regs, R"({"index": 0, "offset": 1, "value": 5})")[0] == 10);  // already set
    CHECK(patched(regs, R"({"index": 1, "offset": 0, "value": 1})")[1] == 5);   // integral float register
    // Bit 63 of a signed register makes it negative; an unsigned one stays unsigned.
    CHECK(patched(regs, R"({"index": 0, "offset": 63, "value": 1})")[0] == static_cast<std::int64_t>(0x800000000000000AULL));
    Json unsigned_reg = Json::array({Json(std::uint64_t{1})});
    const Json top = patched(unsigned_reg, R"({"index": 0, "offset": 63, "value": 1})");
    CHECK(top[0].is_number_unsigned());
    CHECK(top[0].get<std::uint64_t>() == 0x8000000000000001ULL);
    // Several registers at once, and the same register twice (both writes apply in order).
    CHECK(patched(Json::parse("[0, 0, 0]"), R"({"indexes": ["0-2"], "offset": 4, "value": 1})") == Json::parse("[16, 16, 16]"));
    CHECK(patched(Json::parse("[0]"), R"({"indexes": [0, "0"], "offset": 4, "values": [1, 0]})") == Json::parse("[0]"));
    CHECK(patched(Json::parse("[0]"), R"({"indexes": [0, "0-0"], "length": 2, "values": [3, 1]})") == Json::parse("[1]"));
    // Length alone: a bit field at offset 0.
    CHECK(patched(Json::parse("[255]"), R"({"index": 0, "length": 4, "value": 0})") == Json::parse("[240]"));
    // A full 64-bit field.
    CHECK(patched(Json::parse("[1]"), R"({"index": 0, "offset": 0, "length": 64, "value": 7})") == Json::parse("[7]"));
}

TEST_CASE("bit access errors") {
    const Json regs = Json::parse(R"([10, 4.5, true, {"a": 1}, null])");
    CHECK(patch_fails(regs, R"({"index": 0, "offset": 64, "value": 1})") == ErrorCode::out_of_range);
    CHECK(patch_fails(regs, R"({"index": 0, "offset": 60, "length": 5, "value": 1})") == ErrorCode::out_of_range);
    CHECK(patch_fails(regs, R"({"index": 0, "offset": 0, "length": 0, "value": 0})") == ErrorCode::out_of_range);
    CHECK(patch_fails(regs, R"({"index": 0, "offset": 5, "length": 10, "value": 1024})") == ErrorCode::out_of_range);
    CHECK(patch_fails(regs, R"({"index": 0, "offset": 5, "length": 10, "value": -1})") == ErrorCode::out_of_range);
    CHECK(patch_fails(regs, R"({"index": 0, "offset": -1, "value": 1})") == ErrorCode::out_of_range);
    CHECK(patch_fails(regs, R"({"index": 0, "offset": 1, "value": "1"})") == ErrorCode::value_type);
    CHECK(patch_fails(regs, R"({"index": 0, "offset": 1, "length": 2, "value": 1.5})") == ErrorCode::value_type);
    CHECK(patch_fails(regs, R"({"index": 1, "offset": 1, "value": 1})") == ErrorCode::value_type);
    CHECK(patch_fails(regs, R"({"index": 2, "offset": 1, "value": 1})") == ErrorCode::value_type);
    CHECK(patch_fails(regs, R"({"index": 3, "offset": 1, "value": 1})") == ErrorCode::value_type);
    CHECK(patch_fails(regs, R"({"index": 4, "offset": 1, "value": 1})") == ErrorCode::unavailable);
}

TEST_CASE("string elements: offset and length count UTF-8 code points") {
    const Json list = Json::parse(R"(["数控机床", "héllo wörld"])");
    CHECK(patched(list, R"({"index": 0, "offset": 2, "value": "系统"})")[0] == "数控系统");
    CHECK(patched(list, R"({"index": 0, "offset": 1, "length": 2, "value": "X"})")[0] == "数X床");
    CHECK(patched(list, R"({"index": 0, "offset": 4, "length": 0, "value": "!"})")[0] == "数控机床!");
    CHECK(patched(list, R"({"index": 0, "offset": 0, "length": 4, "value": ""})")[0] == "");
    CHECK(patched(list, R"({"index": 1, "offset": 6, "value": "earth"})")[1] == "héllo earth");
    CHECK(patched(list, R"({"index": 1, "offset": 1, "value": "e"})")[1] == "hello wörld");
    CHECK(patched(list, R"({"index": 1, "length": 1, "value": "H"})")[1] == "Héllo wörld");

    CHECK(patch_fails(list, R"({"index": 0, "offset": 5, "length": 0, "value": "x"})") == ErrorCode::out_of_range);
    CHECK(patch_fails(list, R"({"index": 0, "offset": 3, "value": "xy"})") == ErrorCode::out_of_range);
    CHECK(patch_fails(list, R"({"index": 0, "offset": 0, "length": 5, "value": "x"})") == ErrorCode::out_of_range);
    CHECK(patch_fails(list, R"({"index": 0, "offset": 0, "value": 1})") == ErrorCode::value_type);
}

TEST_CASE("array elements: offset and length count elements") {
    const Json list = Json::parse("[[1, 2, 3, 4]]");
    CHECK(patched(list, R"({"index": 0, "offset": 1, "value": [9, 9]})")[0] == Json::parse("[1, 9, 9, 4]"));
    CHECK(patched(list, R"({"index": 0, "offset": 1, "length": 0, "value": [7]})")[0] == Json::parse("[1, 7, 2, 3, 4]"));
    CHECK(patched(list, R"({"index": 0, "offset": 1, "length": 2, "value": []})")[0] == Json::parse("[1, 4]"));
    CHECK(patched(list, R"({"index": 0, "offset": 0, "value": 5})")[0] == Json::parse("[5, 2, 3, 4]"));
    CHECK(patched(list, R"({"index": 0, "offset": 4, "length": 0, "value": [5]})")[0] == Json::parse("[1, 2, 3, 4, 5]"));
    CHECK(patch_fails(list, R"({"index": 0, "offset": 4, "value": 5})") == ErrorCode::out_of_range);
    CHECK(patch_fails(list, R"({"index": 0, "offset": 5, "length": 0, "value": [5]})") == ErrorCode::out_of_range);
}
