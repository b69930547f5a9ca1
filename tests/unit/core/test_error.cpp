#include <nclink/error.hpp>
#include <nclink/log.hpp>
#include <nclink/result.hpp>

#include <catch2/catch.hpp>

#include <mutex>
#include <vector>

using namespace nclink;

TEST_CASE("every table-19 code has its exact reason string") {
    CHECK(reason(ErrorCode::success) == "Success");
    CHECK(reason(ErrorCode::out_of_range) == "Out of Range");
    CHECK(reason(ErrorCode::parameter_missing) == "Parameter Missing");
    CHECK(reason(ErrorCode::unavailable) == "Unavailable");
    CHECK(reason(ErrorCode::timeout) == "Timeout");
    CHECK(reason(ErrorCode::permission_denied) == "Permission Denied");
    CHECK(reason(ErrorCode::node_not_exists) == "Node not exists");
    CHECK(reason(ErrorCode::no_index) == "No index passed in");
    CHECK(reason(ErrorCode::no_key) == "No key passed in");
    CHECK(reason(ErrorCode::memory_configured) == "Memory configured error");
    CHECK(reason(ErrorCode::value_type) == "Value type error");
    CHECK(reason(ErrorCode::unsupported_get_length) == "unsupported operation get_length");
    CHECK(reason(ErrorCode::unsupported_get_attributes) == "unsupported operation get_attributes");
    CHECK(reason(ErrorCode::unsupported_get_keys) == "unsupported operation get_keys");
    CHECK(reason(ErrorCode::arguments_nimiety) == "arguments nimiety");
    CHECK(reason(ErrorCode::key_error) == "key error");
    CHECK(reason(ErrorCode::attribute_error) == "Attribute error");
    CHECK(reason(ErrorCode::syntax_error) == "syntax error");
    CHECK(reason(ErrorCode::keys_of_arguments) == "keys of arguments error");
    CHECK(reason(ErrorCode::unsupported_terminal_id) == "unsupported terminal identifier");
    CHECK(reason(ErrorCode::insufficient_dynamic_sampling) == "Insufficient dynamic sampling resources");
    CHECK(reason(ErrorCode::insufficient_event) == "Insufficient event resources");
    CHECK(reason(ErrorCode::insufficient_method) == "Insufficient method resources");
    CHECK(reason(ErrorCode::method_action_type) == "method action type error");
    CHECK(reason(ErrorCode::filter_type) == "filter type error");
    CHECK(reason(ErrorCode::trigger_type) == "trigger type error");
    CHECK(reason(ErrorCode::filter_arguments_mismatch) == "filter type and arguments not matched");
}

TEST_CASE("codes map back from numbers and from reasons") {
    CHECK(error_code_from_int(401) == ErrorCode::node_not_exists);
    CHECK(error_code_from_int(0) == ErrorCode::success);
    CHECK_FALSE(error_code_from_int(999).has_value());
    CHECK_FALSE(error_code_from_int(-5).has_value());
    CHECK(error_code_from_reason("Node not exists") == ErrorCode::node_not_exists);
    // The standard's own example 8.2.12 writes " Unavailable" with a space.
    CHECK(error_code_from_reason(" Unavailable") == ErrorCode::unavailable);
    CHECK(error_code_from_reason("SYNTAX_ERROR") == ErrorCode::syntax_error);
    CHECK_FALSE(error_code_from_reason("DEV_UNREACHABLE").has_value());
}

TEST_CASE("Error::describe names code, reason and detail") {
    CHECK(make_error(ErrorCode::out_of_range, "index 12 of 10").describe() == "101 Out of Range: index 12 of 10");
    CHECK(make_error(ErrorCode::timeout).describe() == "203 Timeout");
}

TEST_CASE("Result carries a value or an error") {
    Result<int> good = 42;
    REQUIRE(good.ok());
    CHECK(*good == 42);
    CHECK(good.value_or(7) == 42);

    Result<int> bad = make_error(ErrorCode::key_error, "k9");
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().code == ErrorCode::key_error);
    CHECK(bad.value_or(7) == 7);

    Result<void> done;
    CHECK(done.ok());
    Result<void> failed = make_error(ErrorCode::timeout);
    CHECK_FALSE(failed);
    CHECK(failed.error().code == ErrorCode::timeout);

    Result<std::string> moved = std::string("abc");
    std::string taken = std::move(moved).value();
    CHECK(taken == "abc");
}

TEST_CASE("Logger filters by level and sends formatted text to its sink") {
    std::mutex mutex;
    std::vector<std::pair<LogLevel, std::string>> lines;
    Logger logger(
        [&](LogLevel level, std::string_view text) {
            std::lock_guard<std::mutex> lock(mutex);
            lines.emplace_back(level, std::string(text));
        },
        LogLevel::info);
    logger.debug("hidden {}", 1);
    logger.info("item {} = {:.1f}", "X", 2.5);
    logger.error("boom");
    REQUIRE(lines.size() == 2);
    CHECK(lines[0].first == LogLevel::info);
    CHECK(lines[0].second == "item X = 2.5");
    CHECK(lines[1].second == "boom");

    Logger silent;
    CHECK_FALSE(silent.enabled(LogLevel::error));
    silent.error("nothing happens {}", 1);
}
