// check_method_args: the METHOD object's declared args against a call's args.
#include "methods/method_args.hpp"

#include "methods/methods_config.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using nclink::methods_detail::check_method_args;

namespace {
Method method(Json args) {
    Method m;
    m.id = "m";
    m.args = std::move(args);
    return m;
}
}  // namespace

TEST_CASE("object-declared args are all required and nothing else is accepted") {
    const Method m = method(Json{{"source", "/gcodes/O1"}, {"destination", "/prog/O1"}});
    auto ok = check_method_args(m, Json{{"source", "a"}, {"destination", "b"}});
    REQUIRE(ok.ok());
    CHECK(ok.value() == Json{{"source", "a"}, {"destination", "b"}});
    auto missing = check_method_args(m, Json{{"source", "a"}});
    REQUIRE_FALSE(missing.ok());
    CHECK(missing.error().code == ErrorCode::parameter_missing);
    CHECK(missing.error().message == "method m needs args destination");
    CHECK(check_method_args(m, std::nullopt).error().code == ErrorCode::parameter_missing);
    auto extra = check_method_args(m, Json{{"source", "a"}, {"destination", "b"}, {"speed", 1}});
    REQUIRE_FALSE(extra.ok());
    CHECK(extra.error().code == ErrorCode::arguments_nimiety);
    CHECK(extra.error().message == "method m takes no args speed");
}

TEST_CASE("array-declared args: names, defaults and optional entries") {
    const Method m = method(Json::array({"source", Json{{"name", "operation"}, {"default", "push"}},
                                         Json{{"name", "note"}, {"optional", true}}, Json{{"id", "mode"}}, 42}));
    auto filled = check_method_args(m, Json{{"source", "a"}, {"mode", 1}});
    REQUIRE(filled.ok());
    CHECK(filled.value() == Json{{"source", "a"}, {"mode", 1}, {"operation", "push"}});
    CHECK(check_method_args(m, Json{{"mode", 1}}).error().code == ErrorCode::parameter_missing);
    CHECK(check_method_args(m, Json{{"source", "a"}, {"mode", 1}, {"note", "x"}, {"operation", "pull"}}).value()["operation"] ==
          "pull");
}

TEST_CASE("no declaration accepts any args object and every method refuses args that are not an object") {
    CHECK(check_method_args(method(nullptr), Json{{"anything", 1}}).ok());
    CHECK(check_method_args(method(nullptr), std::nullopt).value() == Json::object());
    CHECK(check_method_args(method(Json::object()), Json::object()).ok());
    CHECK(check_method_args(method(Json::object()), Json(nullptr)).ok());
    CHECK(check_method_args(method(nullptr), Json("text")).error().code == ErrorCode::value_type);
}

TEST_CASE("the methods configuration section") {
    MethodsConfig c;
    REQUIRE(
        methods_detail::read_methods_config(Json{{"max_running", 2}, {"status_period_ms", 250}, {"stop_grace_ms", 100}}, c).ok());
    CHECK(c.max_running == 2);
    CHECK(c.status_period == std::chrono::milliseconds(250));
    CHECK(c.stop_grace == std::chrono::milliseconds(100));
    CHECK(methods_detail::read_methods_config(Json{{"status_period_ms", 0}}, c).error().code == ErrorCode::out_of_range);
    CHECK(methods_detail::read_methods_config(Json{{"max_runing", 2}}, c).error().code == ErrorCode::keys_of_arguments);
    CHECK(methods_detail::read_methods_config(Json{{"max_running", -1}}, c).error().code == ErrorCode::value_type);
}
