// The text syntax of request items (nclink query/set) and result lines.
#include "client_args.hpp"

#include <catch2/catch.hpp>

using namespace nclink;

TEST_CASE("query specs: bare id and id with JSON params") {
    auto bare = parse_query_spec("0103");
    REQUIRE(bare.ok());
    CHECK(bare->id == "0103");
    CHECK_FALSE(bare->params.has_value());

    auto with = parse_query_spec(R"(0103:{"operation":"get_length"})");
    REQUIRE(with.ok());
    CHECK(with->id == "0103");
    CHECK((*with->params)["operation"] == "get_length");

    CHECK(parse_query_spec("").error().code == ErrorCode::parameter_missing);
    CHECK(parse_query_spec(":{}").error().code == ErrorCode::parameter_missing);
    CHECK(parse_query_spec("x:[1]").error().code == ErrorCode::syntax_error);
    CHECK(parse_query_spec("x:{oops").error().code == ErrorCode::syntax_error);
}

TEST_CASE("set specs: ID=VALUE takes JSON when it parses, else a string") {
    auto number = parse_set_spec("0103=5");
    REQUIRE(number.ok());
    CHECK(number->id == "0103");
    CHECK(*number->params == Json{{"value", 5}});
    CHECK((*parse_set_spec("a=true")->params)["value"] == true);
    CHECK((*parse_set_spec("a=hello world")->params)["value"] == "hello world");
    CHECK((*parse_set_spec(R"(a="5")")->params)["value"] == "5");
    CHECK((*parse_set_spec("a=")->params)["value"] == "");
    CHECK((*parse_set_spec("a=[1,2]")->params)["value"] == Json::array({1, 2}));
    CHECK((*parse_set_spec(R"(a={"k":1})")->params)["value"] == Json{{"k", 1}});
    CHECK((*parse_set_spec("a=x:y")->params)["value"] == "x:y");
}

TEST_CASE("set specs: ID:{params} gives the full params") {
    auto full = parse_set_spec(R"(0103:{"value":5,"index":2})");
    REQUIRE(full.ok());
    CHECK(full->id == "0103");
    CHECK(*full->params == Json{{"value", 5}, {"index", 2}});
    CHECK(parse_set_spec("0103").error().code == ErrorCode::parameter_missing);
    CHECK(parse_set_spec("=5").error().code == ErrorCode::parameter_missing);
    CHECK(parse_set_spec("a:5").error().code == ErrorCode::syntax_error);
}

TEST_CASE("result lines") {
    QueryResult ok;
    ok.id = "0103";
    ok.values = Json::array({42});
    CHECK(format_query_result(ok) == "0103 = 42");
    ok.values = Json::array({1, 2});
    CHECK(format_query_result(ok) == "0103 = [1,2]");
    ok.values = Json::array({"s"});
    CHECK(format_query_result(ok) == "0103 = \"s\"");

    QueryResult ng;
    ng.id = "zz";
    ng.status = ResponseStatus::failure(ErrorCode::node_not_exists);
    CHECK(format_query_result(ng) == "zz: NG 401 Node not exists");

    SetResult set;
    set.id = "a";
    CHECK(format_set_result(set) == "a: OK");
    set.status = ResponseStatus::failure(ErrorCode::value_type);
    CHECK(format_set_result(set).rfind("a: NG 405 ", 0) == 0);
}
