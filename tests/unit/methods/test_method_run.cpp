// MethodRun's phases (8.2.23 `status`): waiting -> executing, and a run
// cancelled before its driver was called goes to "sleep" (not called).
#include "methods/method_run.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace nclink;
using namespace nclink::methods_detail;

namespace {

MethodRun make_run() { return MethodRun(1, "m1", ParsedTopic{}, MessageId(Json("call-1")), Json::object()); }

}  // namespace

TEST_CASE("a run that is not cancelled begins executing and announces it") {
    MethodRun run = make_run();
    std::vector<std::string> seen;
    run.set_phase_listener([&](MethodRun& r) { seen.push_back(to_string(r.snapshot().phase)); });
    CHECK(run.snapshot().phase == RunPhase::waiting);
    CHECK(run.begin());
    CHECK(seen == std::vector<std::string>{"executing"});
}

TEST_CASE("a run cancelled while waiting is never called and goes to sleep") {
    MethodRun run = make_run();
    std::vector<std::string> seen;
    run.set_phase_listener([&](MethodRun& r) { seen.push_back(to_string(r.snapshot().phase)); });
    run.request_cancel();
    CHECK_FALSE(run.begin());
    CHECK(run.snapshot().phase == RunPhase::sleep);
    CHECK(run.cancelled());
    CHECK(seen == std::vector<std::string>{"sleep"});
}
