// The lathe example as a user meets it: the program examples/lathe builds,
// run against a real mosquitto; the nclink tool queries and sets it (a Set
// outside the declared range answers 101), a Query after it stopped names the
// retained offline state, and nclink-conform passes it.
#include "support/child_process.hpp"
#include "support/cli.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

using namespace nclink::test;

namespace {

const std::string kDevice = "acme-lathe-0001";

}  // namespace

TEST_CASE("the lathe example answers Query and Set, checks ranges, and passes nclink-conform") {
    if (!cli_built() || !std::filesystem::exists(binary_path("nclink-lathe"))) {
        WARN("nclink or nclink-lathe not built: skipped");
        return;
    }
    MosquittoBroker broker;
    ChildProcess lathe({binary_path("nclink-lathe"), "--broker", broker.url(), "--log-level", "warn"},
                       std::string(NCLINK_BINARY_DIR) + "/lathe-test.log");
    REQUIRE(lathe.started());
    REQUIRE(eventually([&] { return run_cli_on(broker.url(), kDevice, "state").out.find("online") != std::string::npos; },
                       std::chrono::seconds(30)));

    const auto query = run_cli_on(broker.url(), kDevice, "query x_position z_position spindle_speed status machine_category");
    INFO(query.out);
    CHECK(query.status == 0);
    CHECK(query.out.find("machine_category = \"lathe\"") != std::string::npos);

    CHECK(run_cli_on(broker.url(), kDevice, "set spindle_override=110").status == 0);
    CHECK(run_cli_on(broker.url(), kDevice, "query spindle_override").out.find("spindle_override = 110") != std::string::npos);
    const auto refused = run_cli_on(broker.url(), kDevice, "set spindle_override=200");
    INFO(refused.out);
    CHECK(refused.status == 1);
    CHECK(refused.out.find("101") != std::string::npos);

    const std::string conform = binary_path("nclink-conform") + " --broker " + broker.url() + " --device " + kDevice +
                                " --allow-write --timeout-ms 2000 --max-wait-ms 3000 > /dev/null 2>&1";
    const int conform_status = std::system(conform.c_str());
    REQUIRE(WIFEXITED(conform_status));
    CHECK(WEXITSTATUS(conform_status) == 0);

    lathe.terminate();  // SIGTERM: a clean stop, exit status 0
    CHECK(lathe.wait_exit(std::chrono::milliseconds(0)) == 0);
    const auto dead = run_cli_on(broker.url(), kDevice, "query --timeout 500 x_position");
    CHECK(dead.status == 1);
}
