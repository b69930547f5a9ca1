#include "values_test_util.hpp"

#include <cstdint>

using namespace nclink;
using namespace values_test;

TEST_CASE("parse_index accepts numbers, numeric strings and ranges") {
    CHECK(*parse_index(Json(7)) == IndexRange{7, 7});
    CHECK(*parse_index(Json(7u)) == IndexRange{7, 7});
    CHECK(*parse_index(Json(3.0)) == IndexRange{3, 3});
    CHECK(*parse_index(Json("12")) == IndexRange{12, 12});
    CHECK(*parse_index(Json(" 4 ")) == IndexRange{4, 4});
    CHECK(*parse_index(Json("5-8")) == IndexRange{5, 8});
    CHECK(*parse_index(Json("5 - 8")) == IndexRange{5, 8});
    CHECK(*parse_index(Json("6-6")) == IndexRange{6, 6});
    CHECK(parse_index(Json("5-8"))->count() == 4);
}

TEST_CASE("parse_index rejects bad entries with the table-19 code") {
    CHECK(code_of(parse_index(Json("abc"))) == ErrorCode::value_type);
    CHECK(code_of(parse_index(Json("1.5"))) == ErrorCode::value_type);
    CHECK(code_of(parse_index(Json(1.5))) == ErrorCode::value_type);
    CHECK(code_of(parse_index(Json(true))) == ErrorCode::value_type);
    CHECK(code_of(parse_index(Json(nullptr))) == ErrorCode::value_type);
    CHECK(code_of(parse_index(Json::object())) == ErrorCode::value_type);
    CHECK(code_of(parse_index(Json(""))) == ErrorCode::value_type);
    CHECK(code_of(parse_index(Json("8-5"))) == ErrorCode::syntax_error);
    CHECK(code_of(parse_index(Json("5-"))) == ErrorCode::syntax_error);
    CHECK(code_of(parse_index(Json("-5"))) == ErrorCode::syntax_error);
    CHECK(code_of(parse_index(Json("1-2-3"))) == ErrorCode::syntax_error);
    CHECK(code_of(parse_index(Json("a-b"))) == ErrorCode::syntax_error);
    CHECK(code_of(parse_index(Json(-1))) == ErrorCode::out_of_range);
    CHECK(code_of(parse_index(Json("99999999999999999999999"))) == ErrorCode::out_of_range);
    CHECK(code_of(parse_index(Json(1e30))) == ErrorCode::out_of_range);
}

TEST_CASE("expand_indexes flattens in request order and checks the length first") {
    const std::vector<IndexRange> ranges{{0, 0}, {4, 7}, {5, 5}};
    const auto expanded = expand_indexes(ranges, 10);
    REQUIRE(expanded.ok());
    CHECK(*expanded == std::vector<std::size_t>{0, 4, 5, 6, 7, 5});
    CHECK(index_count(ranges) == 6);

    const auto beyond = expand_indexes({{8, 12}}, 10);
    CHECK(code_of(beyond) == ErrorCode::out_of_range);
    CHECK(beyond.error().message == "index 12 is beyond the list length 10");
    // A hostile range is refused before anything is allocated.
    CHECK(code_of(expand_indexes({{0, 4000000000u}}, 10)) == ErrorCode::out_of_range);
    CHECK(index_count({{0, SIZE_MAX}, {0, 5}}) == SIZE_MAX);
}

TEST_CASE("a request selecting too many elements is refused with 404") {
    const std::vector<IndexRange> ranges(3, IndexRange{0, max_selected_indexes / 2});
    const auto expanded = expand_indexes(ranges, max_selected_indexes + 1);
    CHECK(code_of(expanded) == ErrorCode::memory_configured);
    CHECK(reason(ErrorCode::memory_configured) == "Memory configured error");
    CHECK(expand_indexes({{0, 9}, {0, 9}}, 10)->size() == 20);
}

TEST_CASE("value_for never reads past the values") {
    SetParams request;
    CHECK(request.value_for(0).is_null());
    request.values = {Json(1), Json(2)};
    CHECK(request.value_for(1) == 2);
    CHECK(request.value_for(2).is_null());
    request.values = {Json(7)};
    CHECK(request.value_for(5) == 7);
}
