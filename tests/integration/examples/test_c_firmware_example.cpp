// The C firmware example (examples/c-firmware: C11 over nclink.h, its driver
// a C struct) as a vendor meets it: run against a real mosquitto, it answers
// Query and Set, refuses an out-of-range Set with 101, and passes
// nclink-conform with writes and its method (home_axes, progress per axis);
// its real-time thread's rows all get into the channel (none refused), and it
// stops cleanly on SIGTERM.
#include "support/child_process.hpp"
#include "support/cli.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <regex>
#include <string>

using namespace nclink::test;

namespace {

const std::string kDevice = "acme-cfw-0001";

}  // namespace

TEST_CASE("the C firmware example answers Query and Set, runs its method and passes nclink-conform") {
    if (!cli_built() || !std::filesystem::exists(binary_path("nclink-c-firmware")) ||
        !std::filesystem::exists(binary_path("nclink-conform"))) {
        WARN("nclink, nclink-conform or nclink-c-firmware not built: skipped");
        return;
    }
    MosquittoBroker broker;
    const std::string out = std::string(NCLINK_BINARY_DIR) + "/c-firmware-test.out";
    std::filesystem::remove(out);
    ChildProcess firmware({binary_path("nclink-c-firmware"), "--broker", broker.url()}, out, out + ".err");
    firmware.start();
    REQUIRE(eventually([&] { return run_cli_on(broker.url(), kDevice, "state").out.find("online") != std::string::npos; },
                       std::chrono::seconds(30)));

    const auto query = run_cli_on(broker.url(), kDevice, "query x_position status part_count feed_override");
    INFO(query.out);
    CHECK(query.status == 0);
    CHECK(query.out.find("feed_override = 100") != std::string::npos);
    CHECK(run_cli_on(broker.url(), kDevice, "set feed_override=120").status == 0);
    CHECK(run_cli_on(broker.url(), kDevice, "query feed_override").out.find("feed_override = 120") != std::string::npos);
    const auto refused = run_cli_on(broker.url(), kDevice, "set feed_override=200");
    INFO(refused.out);
    CHECK(refused.status == 1);
    CHECK(refused.out.find("101") != std::string::npos);
    CHECK(run_cli_on(broker.url(), kDevice, "set feed_override=100").status == 0);

    const std::string conform = binary_path("nclink-conform") + " --broker " + broker.url() + " --device " + kDevice +
                                " --allow-write --method home_axes --timeout-ms 3000 --max-wait-ms 5000 --json " +
                                NCLINK_BINARY_DIR + "/c-firmware-conform.json > /dev/null 2>&1";
    const int conform_status = std::system(conform.c_str());
    REQUIRE(WIFEXITED(conform_status));
    CHECK(WEXITSTATUS(conform_status) == 0);

    firmware.terminate();
    CHECK(firmware.wait_exit(std::chrono::milliseconds(0)) == 0);
    const std::string printed = firmware.out();
    INFO(printed);
    std::smatch m;
    REQUIRE(std::regex_search(printed, m, std::regex(R"(c-firmware: (\d+) rows pushed, (\d+) refused)")));
    CHECK(std::stoul(m[1]) > 100);  // 100 Hz for the seconds the test ran
    CHECK(m[2] == "0");
}
