// The lathe example as a user meets it: the program examples/lathe builds,
// run against a real mosquitto; the nclink tool queries and sets it (a Set
// outside the declared range answers 101), a Query after it stopped names the
// retained offline state, and nclink-conform passes it.
#include "support/cli.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <csignal>
#include <filesystem>
#include <spawn.h>
#include <string>
#include <sys/wait.h>

extern char** environ;

using namespace nclink::test;

namespace {

const std::string kDevice = "acme-lathe-0001";

std::string bin(const std::string& name) { return std::string(NCLINK_BINARY_DIR) + "/bin/" + name; }

/// The lathe program in the background; SIGTERM and a reaped exit status at the end.
class LatheProcess {
public:
    explicit LatheProcess(const std::string& broker) {
        std::vector<std::string> args{bin("nclink-lathe"), "--broker", broker, "--log-level", "warn"};
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        if (posix_spawn(&pid_, argv[0], nullptr, nullptr, argv.data(), environ) != 0) pid_ = -1;
    }
    /// Stops it with SIGTERM; its exit status (-1 if it did not exit normally).
    int stop() {
        if (pid_ <= 0) return -1;
        ::kill(pid_, SIGTERM);
        int status = 0;
        ::waitpid(pid_, &status, 0);
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    ~LatheProcess() { stop(); }
    bool running() const { return pid_ > 0; }

private:
    pid_t pid_ = -1;
};

/// `nclink COMMAND --broker URL --device DEV REST...` for "COMMAND REST...".
std::string cli(const MosquittoBroker& broker, const std::string& args) {
    const auto space = args.find(' ');
    const std::string command = args.substr(0, space);
    const std::string rest = space == std::string::npos ? std::string() : args.substr(space);
    return command + " --broker " + broker.url() + " --device " + kDevice + rest;
}

}  // namespace

TEST_CASE("the lathe example answers Query and Set, checks ranges, and passes nclink-conform") {
    if (!cli_built() || !std::filesystem::exists(bin("nclink-lathe"))) {
        WARN("nclink or nclink-lathe not built: skipped");
        return;
    }
    MosquittoBroker broker;
    LatheProcess lathe(broker.url());
    REQUIRE(lathe.running());
    REQUIRE(eventually([&] { return run_cli(cli(broker, "state")).out.find("online") != std::string::npos; },
                       std::chrono::seconds(30)));

    const auto query = run_cli(cli(broker, "query x_position z_position spindle_speed status machine_category"));
    INFO(query.out);
    CHECK(query.status == 0);
    CHECK(query.out.find("machine_category = \"lathe\"") != std::string::npos);

    CHECK(run_cli(cli(broker, "set spindle_override=110")).status == 0);
    CHECK(run_cli(cli(broker, "query spindle_override")).out.find("spindle_override = 110") != std::string::npos);
    const auto refused = run_cli(cli(broker, "set spindle_override=200"));
    INFO(refused.out);
    CHECK(refused.status == 1);
    CHECK(refused.out.find("101") != std::string::npos);

    const std::string conform = bin("nclink-conform") + " --broker " + broker.url() + " --device " + kDevice +
                                " --allow-write --timeout-ms 2000 --max-wait-ms 3000 > /dev/null 2>&1";
    const int conform_status = std::system(conform.c_str());
    REQUIRE(WIFEXITED(conform_status));
    CHECK(WEXITSTATUS(conform_status) == 0);

    CHECK(lathe.stop() == 0);  // SIGTERM: a clean stop, exit status 0
    const auto dead = run_cli(cli(broker, "query --timeout 500 x_position"));
    CHECK(dead.status == 1);
}
