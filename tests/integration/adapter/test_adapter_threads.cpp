// A single adapter's threads (docs/footprint.md, "Where the threads go"): its
// serial background work (outbox sender, sample uploader, events engine,
// method status ticker, spool, housekeeping, deadline watchdog) runs as
// pollables of two background threads ("nclink-work"), beside the MQTT I/O
// thread, the sampler, the driver worker and the request workers. Before, each
// piece had a thread of its own: 12 threads for one simulated mill. The second
// request worker exists during a burst of requests only.
#include "support/sim_mill_rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

using namespace nclink;
using namespace nclink::test;

namespace {

std::map<long, std::string> threads_now() {
    std::map<long, std::string> out;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
        std::ifstream comm(task.path() / "comm");
        std::string name;
        std::getline(comm, name);
        out[std::stol(task.path().filename().string())] = name;
    }
    return out;
}

// A PollHost names its threads "<name>-<n>"; the others carry the name.
std::string family(const std::string& name) {
    const auto dash = name.rfind('-');
    if (dash != std::string::npos && name.find_first_not_of("0123456789", dash + 1) == std::string::npos &&
        name.compare(0, 11, "nclink-work") == 0)
        return "nclink-work";
    return name;
}

std::uint64_t rows_published(const Adapter& adapter) {
    std::uint64_t n = 0;
    for (const auto& c : adapter.sampling_stats().channels) n += c.rows_published;
    return n;
}

}  // namespace

TEST_CASE("a single adapter runs its background work on two threads, not a thread per piece") {
    SimMillRig rig;
    const auto before = threads_now();
    rig.start();

    // A thread names itself once running: wait until every new one has.
    std::map<long, std::string> now;
    auto all_named = [&] {
        now = threads_now();
        for (const auto& [tid, name] : now)
            if (before.count(tid) == 0 && name.compare(0, 7, "nclink-") != 0) return false;
        return true;
    };
    (void)eventually(all_named, std::chrono::seconds(5));
    std::map<std::string, int> started;
    std::string listed;
    for (const auto& [tid, name] : now)
        if (before.count(tid) == 0) {
            ++started[family(name)];
            listed += name + " ";
        }
    INFO("threads the adapter started: " << listed);
    // What may run: these and nothing else (a method thread runs only while
    // a method does, and none is called here).
    const std::set<std::string> expected{"nclink-mqtt-io", "nclink-sampler", "nclink-driver", "nclink-request", "nclink-work"};
    for (const auto& [name, n] : started) CHECK(expected.count(name) == 1);
    CHECK(started["nclink-work"] == 2);
    // One request worker at rest, whatever request_threads (2 by default):
    // the others start only while requests queue up (src/core/executor.hpp).
    REQUIRE(rig.config.request_threads == 2);
    CHECK(started["nclink-request"] == 1);
    std::size_t total = 0;
    for (const auto& [name, n] : started) total += static_cast<std::size_t>(n);
    CHECK(total == 6);  // the goal of docs/footprint.md: a single adapter <= 6 threads

    // The work moved, it did not stop: the uploader publishes the channels'
    // rows, the outbox delivers a Query's answer and the events engine
    // polls, all from the two background threads.
    const auto rows = rows_published(*rig.adapter);
    CHECK(eventually([&] { return rows_published(*rig.adapter) > rows; }, std::chrono::seconds(5)));
    rig.client = rig.make_client("threads");
    CHECK_FALSE(rig.query_one("status").is_null());
}
