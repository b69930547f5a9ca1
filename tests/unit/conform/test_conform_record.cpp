// The test record: verdict rules, Markdown and JSON rendering, command line.
#include "conform/cli_options.hpp"
#include "conform/record.hpp"
#include "conform/report.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::conform;

namespace {

TestRecord sample_record() {
    TestRecord r;
    r.device = "dev-1";
    r.broker = "tcp://127.0.0.1:1883";
    r.client_id = "tester";
    r.date = "2024-01-01T00:00:00Z";
    r.tool_version = "0.1.0";
    r.model_version = "1.0.0";
    r.objects = ObjectCounts{3, 1, 20, 2, 2, 4};
    ItemResult probe;
    probe.key = "probe";
    probe.title = "Model probe (Probe/Query)";
    probe.required = true;
    probe.summary = "model received";
    ItemResult events;
    events.key = "event-register";
    events.title = "Event registration";
    events.not_supported("the adapter answers NG 202", "Register/Event/Response/dev-1/tester",
                         R"({"@id":"x","code":"NG","error":202})");
    ItemResult set;
    set.key = "set";
    set.title = "Data set";
    set.skip("skipped: needs --allow-write");
    r.items = {probe, events, set};
    return r;
}

}  // namespace

TEST_CASE("verdict: not supported and skipped optional items still pass") {
    auto r = sample_record();
    CHECK(r.verdict() == Verdict::pass);
    CHECK(r.count(Outcome::pass) == 1);
    CHECK(r.count(Outcome::not_supported) == 1);
    CHECK(r.count(Outcome::skipped) == 1);
}

TEST_CASE("verdict: one failed item fails the record") {
    auto r = sample_record();
    r.items[2].outcome = Outcome::pass;
    r.items[2].fail("answered NG 405", "Set/Response/dev-1/tester", "{}");
    CHECK(r.verdict() == Verdict::fail);
}

TEST_CASE("verdict: a required item that is not supported fails the record") {
    auto r = sample_record();
    r.items[0].not_supported("no answer");
    CHECK(r.verdict() == Verdict::fail);
}

TEST_CASE("an item outcome: fail dominates and skip does not hide a result") {
    ItemResult i;
    i.fail("bad");
    i.not_supported("later");
    i.skip("later");
    CHECK(i.outcome == Outcome::fail);
    CHECK(i.failures() == 1);
    ItemResult j;
    j.not_supported("202");
    j.skip("x");
    CHECK(j.outcome == Outcome::not_supported);
}

TEST_CASE("clip keeps UTF-8 whole and says how much was cut") {
    const std::string text = std::string(10, 'a') + "\xE4\xB8\xAD" + std::string(10, 'b');
    const std::string cut = clip(text, 11);
    CHECK(cut.rfind(std::string(10, 'a'), 0) == 0);
    CHECK(cut.find("more bytes") != std::string::npos);
    CHECK(cut.find('\xE4') == std::string::npos);
    CHECK(clip("short", 100) == "short");
}

TEST_CASE("markdown record has the C.1 sections and the evidence") {
    const std::string md = render_markdown(sample_record());
    CHECK(md.find("table C.1") != std::string::npos);
    CHECK(md.find("## Verdict: **PASS**") != std::string::npos);
    CHECK(md.find("| Component objects | 3 | 1 |") != std::string::npos);
    CHECK(md.find("| Data objects | 20 | 2 |") != std::string::npos);
    CHECK(md.find("| Model probe (Probe/Query) |") != std::string::npos);
    CHECK(md.find("not supported") != std::string::npos);
    CHECK(md.find(R"({"@id":"x","code":"NG","error":202})") != std::string::npos);
    CHECK(md.find("`Register/Event/Response/dev-1/tester`") != std::string::npos);
}

TEST_CASE("json record lists items with outcome and evidence") {
    const Json j = render_json(sample_record());
    CHECK(j["verdict"] == "pass");
    CHECK(j["basic"]["device"] == "dev-1");
    CHECK(j["objects"]["data_objects"]["custom"] == 2);
    CHECK(j["counts"]["not_supported"] == 1);
    REQUIRE(j["items"].size() == 3);
    CHECK(j["items"][0]["outcome"] == "pass");
    CHECK(j["items"][0]["supported"] == true);
    CHECK(j["items"][1]["outcome"] == "not supported");
    CHECK(j["items"][1]["supported"] == false);
    CHECK(j["items"][1]["evidence"][0]["topic"] == "Register/Event/Response/dev-1/tester");
    CHECK(j["items"][2]["supported"].is_null());
}

TEST_CASE("command line: required options, values and errors") {
    auto ok = parse_cli({"--broker", "tcp://h:1883", "--device", "d", "--allow-write", "--timeout-ms", "500", "--method", "m",
                         "--method-args", R"({"a":1})", "--json", "r.json"});
    REQUIRE(ok);
    CHECK(ok->broker == "tcp://h:1883");
    CHECK(ok->run.device == "d");
    CHECK(ok->run.allow_write);
    CHECK(ok->run.timeout == std::chrono::milliseconds(500));
    CHECK(ok->run.method == "m");
    CHECK((*ok->run.method_args)["a"] == 1);
    CHECK(ok->report_json == "r.json");
    CHECK_FALSE(parse_cli({"--device", "d"}));
    CHECK_FALSE(parse_cli({"--broker", "tcp://h:1883"}));
    CHECK(parse_cli({"--broker", "b", "--device", "d", "--nope"}).error().code == ErrorCode::keys_of_arguments);
    CHECK(parse_cli({"--broker", "b", "--device", "d", "--timeout-ms", "soon"}).error().code == ErrorCode::value_type);
    CHECK(parse_cli({"--broker", "b", "--device", "d", "--timeout-ms"}).error().code == ErrorCode::parameter_missing);
    CHECK(parse_cli({"--broker", "b", "--device", "d/+"}).error().code == ErrorCode::unsupported_terminal_id);
    CHECK(parse_cli({"--help"})->help);
    CHECK_FALSE(parse_cli({"--broker", "b", "--device", "d"})->run.allow_write);
}
