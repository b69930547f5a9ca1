// Option parsing of the `nclink` device commands (tools/nclink/cli_options.hpp,
// header-only so it can be tested here without the program).
#include "cli_options.hpp"

#include <catch2/catch.hpp>

using namespace nclink::cli;

TEST_CASE("cli: defaults and global options in both spellings") {
    const auto d = parse_cli_options({});
    CHECK(d.broker == "tcp://127.0.0.1:1883");
    CHECK(d.device.empty());
    CHECK(d.timeout == std::chrono::milliseconds(2000));
    CHECK_FALSE(d.json);

    const auto o = parse_cli_options(
        {"--broker", "tcp://h:1884", "--device=dev1", "--client-id", "me", "--timeout=150", "--json", "x=1", "y"});
    CHECK(o.broker == "tcp://h:1884");
    CHECK(o.device == "dev1");
    CHECK(o.client_id == "me");
    CHECK(o.timeout == std::chrono::milliseconds(150));
    CHECK(o.json);
    CHECK(o.positionals == std::vector<std::string>{"x=1", "y"});
    CHECK(o.failover.empty());
}

TEST_CASE("cli: --failover adds brokers to fail over to, in order") {
    const auto o = parse_cli_options({"--broker", "tcp://a:1883", "--failover", "b:1883", "--failover=tcp://c:1884"});
    CHECK(o.failover == std::vector<std::string>{"b:1883", "tcp://c:1884"});
    CHECK_THROWS_AS(parse_cli_options({"--failover="}), UsageError);
    CHECK_THROWS_AS(parse_cli_options({"--failover"}), UsageError);
}

TEST_CASE("cli: command-specific options and positionals after --") {
    const OptionSpec spec{{"--follow"}, {"--count"}};
    const auto o = parse_cli_options({"--follow", "--count", "5", "--", "--odd", "-1"}, spec);
    CHECK(o.flags.count("--follow") == 1);
    CHECK(o.values.at("--count") == "5");
    CHECK(o.positionals == std::vector<std::string>{"--odd", "-1"});
    CHECK(parse_cli_options({"-h"}).help);
    // A lone "-" and JSON-looking specs are positionals.
    CHECK(parse_cli_options({"-", R"(a:{"x":1})"}).positionals.size() == 2);
}

TEST_CASE("cli: usage errors") {
    CHECK_THROWS_AS(parse_cli_options({"--bogus"}), UsageError);
    CHECK_THROWS_AS(parse_cli_options({"--device"}), UsageError);
    CHECK_THROWS_AS(parse_cli_options({"--timeout", "0"}), UsageError);
    CHECK_THROWS_AS(parse_cli_options({"--timeout", "12ms"}), UsageError);
    CHECK_THROWS_AS(parse_cli_options({"--json=yes"}), UsageError);
    CHECK_THROWS_AS(parse_cli_options({"--follow"}), UsageError);  // not this command's
    CHECK_THROWS_AS(check_terminal_id("--device", ""), UsageError);
    CHECK_THROWS_AS(check_terminal_id("--device", "a/b"), UsageError);
    CHECK_NOTHROW(check_terminal_id("--device", "nclink-sim-mill-01"));
    CHECK(parse_count("--count", "0", true) == 0);
    CHECK_THROWS_AS(parse_count("--count", "0"), UsageError);
}
