// The C firmware example (examples/c-firmware: C11 over nclink.h, its driver
// a C struct) as a vendor meets it: run against a real mosquitto, it answers
// Query and Set, refuses an out-of-range Set with 101, and passes
// nclink-conform with writes and its method (home_axes, progress per axis);
// its real-time thread's rows all get into the channel (none refused), and it
// stops cleanly on SIGTERM.
#include "support/cli.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <spawn.h>
#include <string>
#include <sys/wait.h>

extern char** environ;

using namespace nclink::test;

namespace {

const std::string kDevice = "acme-cfw-0001";

std::string bin(const std::string& name) { return std::string(NCLINK_BINARY_DIR) + "/bin/" + name; }

/// The firmware in the background, its stdout in a file; SIGTERM at the end.
class FirmwareProcess {
public:
    FirmwareProcess(const std::string& broker, const std::string& out) {
        std::vector<std::string> args{bin("nclink-c-firmware"), "--broker", broker};
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
        posix_spawn_file_actions_destroy(&actions);
    }
    int stop() {
        if (pid_ <= 0) return -1;
        ::kill(pid_, SIGTERM);
        int status = 0;
        ::waitpid(pid_, &status, 0);
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    ~FirmwareProcess() { stop(); }
    bool running() const { return pid_ > 0; }

private:
    pid_t pid_ = -1;
};

std::string cli(const MosquittoBroker& broker, const std::string& args) {
    const auto space = args.find(' ');
    const std::string command = args.substr(0, space);
    const std::string rest = space == std::string::npos ? std::string() : args.substr(space);
    return command + " --broker " + broker.url() + " --device " + kDevice + rest;
}

}  // namespace

TEST_CASE("the C firmware example answers Query and Set, runs its method and passes nclink-conform") {
    if (!cli_built() || !std::filesystem::exists(bin("nclink-c-firmware")) || !std::filesystem::exists(bin("nclink-conform"))) {
        WARN("nclink, nclink-conform or nclink-c-firmware not built: skipped");
        return;
    }
    MosquittoBroker broker;
    const std::string out = std::string(NCLINK_BINARY_DIR) + "/c-firmware-test.out";
    FirmwareProcess firmware(broker.url(), out);
    REQUIRE(firmware.running());
    REQUIRE(eventually([&] { return run_cli(cli(broker, "state")).out.find("online") != std::string::npos; },
                       std::chrono::seconds(30)));

    const auto query = run_cli(cli(broker, "query x_position status part_count feed_override"));
    INFO(query.out);
    CHECK(query.status == 0);
    CHECK(query.out.find("feed_override = 100") != std::string::npos);
    CHECK(run_cli(cli(broker, "set feed_override=120")).status == 0);
    CHECK(run_cli(cli(broker, "query feed_override")).out.find("feed_override = 120") != std::string::npos);
    const auto refused = run_cli(cli(broker, "set feed_override=200"));
    INFO(refused.out);
    CHECK(refused.status == 1);
    CHECK(refused.out.find("101") != std::string::npos);
    CHECK(run_cli(cli(broker, "set feed_override=100")).status == 0);

    const std::string conform = bin("nclink-conform") + " --broker " + broker.url() + " --device " + kDevice +
                                " --allow-write --method home_axes --timeout-ms 3000 --max-wait-ms 5000 --json " +
                                NCLINK_BINARY_DIR + "/c-firmware-conform.json > /dev/null 2>&1";
    const int conform_status = std::system(conform.c_str());
    REQUIRE(WIFEXITED(conform_status));
    CHECK(WEXITSTATUS(conform_status) == 0);

    CHECK(firmware.stop() == 0);
    std::ifstream in(out);
    const std::string printed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    INFO(printed);
    std::smatch m;
    REQUIRE(std::regex_search(printed, m, std::regex(R"(c-firmware: (\d+) rows pushed, (\d+) refused)")));
    CHECK(std::stoul(m[1]) > 100);  // 100 Hz for the seconds the test ran
    CHECK(m[2] == "0");
}
