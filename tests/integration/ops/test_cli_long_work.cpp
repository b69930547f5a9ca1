// Long work in the `nclink` tool against the simulated mill and a real
// mosquitto: probe-set to several devices with progress lines, call with
// --no-progress, and `nclink top` in a real terminal (tmux): live values
// refreshed in place, resize, q to quit.
#include <nclink/adapter.hpp>

#include "support/cli.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

const std::string kDev = kSimMillDevice;

struct SimRig {
    MosquittoBroker broker;
    ScratchDir scratch{"nclink-itest-ops-rig-"};
    std::unique_ptr<Adapter> adapter;
    explicit SimRig(bool sampling) {
        fs::create_directories(scratch.path / "programs");
        AdapterConfig config;
        config.broker_url = broker.url();
        config.model_path = sim_mill_path();
        config.register_timeout = 200ms;
        config.sampling.enabled = sampling;
        config.methods.status_period = 100ms;
        // program_transfer copies at 2 KiB/s: a 6 KiB file takes about 3 s.
        config.driver_config = Json{{"program_dir", (scratch.path / "programs").string()}, {"transfer_rate", 2048}};
        adapter = started_adapter(config, sim_for(config.model_path));
    }
    std::string program(std::size_t bytes) const {
        const fs::path file = scratch.path / "O42.nc";
        std::ofstream(file) << std::string(bytes, 'G');
        return file.string();
    }
};

// A shell command's standard output and exit status.
CliRun shell(const std::string& command) {
    CliRun run;
    std::FILE* pipe = ::popen((command + " 2>/dev/null").c_str(), "r");
    if (!pipe) return run;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.out.append(buffer, n);
    const int status = ::pclose(pipe);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
}

bool have(const char* program) { return shell(std::string("command -v ") + program).status == 0; }

}  // namespace

TEST_CASE("nclink probe-set sends a model to each device with progress and says which took it") {
    if (!cli_built()) return;
    SimRig rig(false);
    const std::string common = "--broker " + rig.broker.url() + " --timeout 3000 ";
    const CliRun sent = run_cli("probe-set " + common + sim_mill_path() + " " + kDev);
    CHECK(sent.status == 0);
    CHECK_THAT(sent.out, Catch::Contains("probe-set 0% " + kDev + " (1/1)\n"));
    CHECK_THAT(sent.out, Catch::Contains(kDev + ": OK\n"));
    CHECK_THAT(sent.out, Catch::Contains("probe-set 100% " + kDev + " (1/1)\n"));

    // A device that is not there: NG for it, the others still get the model.
    // The timeout also bounds the connection: 2 s, so a loaded machine
    // still connects and the 203 is the absent device's, not the broker's.
    const CliRun partly = run_cli("probe-set --no-progress --broker " + rig.broker.url() + " --timeout 2000 " + sim_mill_path() +
                                  " nobody-here " + kDev);
    CHECK(partly.status == 1);
    CHECK_THAT(partly.out, Catch::Contains("nobody-here: NG 203"));
    CHECK_THAT(partly.out, Catch::Contains(kDev + ": OK"));
    CHECK_THAT(partly.out, !Catch::Contains("probe-set "));

    ScratchDir dir("nclink-itest-ops-");
    fs::create_directories(dir.path);
    std::ofstream(dir.path / "broken.json") << "{\"not\": \"a model\"}";
    CHECK(run_cli("probe-set " + common + (dir.path / "broken.json").string() + " " + kDev).status == 1);
    CHECK(run_cli("probe-set " + common + sim_mill_path()).status == 2);
}

TEST_CASE("nclink call --no-progress prints only the result") {
    if (!cli_built()) return;
    SimRig rig(false);
    const CliRun quiet = run_cli("call --no-progress --broker " + rig.broker.url() + " --timeout 5000 " + kDev + " feed_hold");
    CHECK(quiet.status == 0);
    CHECK_THAT(quiet.out, !Catch::Contains("status "));
    CHECK_THAT(quiet.out, Catch::StartsWith("finished\n"));
}

TEST_CASE("nclink top shows live values full screen in a terminal, follows a resize and quits on q") {
    if (!cli_built()) return;
    if (!have("tmux")) {
        WARN("tmux not installed (Debian package tmux; tools/install-deps.sh): nclink top not tested in a terminal");
        return;
    }
    SimRig rig(true);
    // A tmux server of our own, so nothing of the user's is touched.
    const std::string tmux = "tmux -L nclink-top-" + std::to_string(std::random_device{}()) + " ";
    // Its exit status goes to a file: tmux's #{pane_dead_status} is
    // sometimes left empty when the pane's terminal closes before tmux
    // reaps the process (seen under load).
    const fs::path status_file = rig.scratch.path / "top.status";
    const fs::path script = rig.scratch.path / "top.sh";
    std::ofstream(script) << cli_path() << " top --broker " << rig.broker.url() << " --device " << kDev << "\n"
                          << "echo $? > " << status_file.string() << "\n";
    const std::string command = "sh " + script.string();
    REQUIRE(shell(tmux + "-f /dev/null new-session -d -s top -x 100 -y 30 '" + command + "'").status == 0);
    shell(tmux + "set-option -t top remain-on-exit on");
    auto screen = [&] { return shell(tmux + "capture-pane -p -t top").out; };
    auto dtus = [&](const std::string& text) {
        const auto at = text.find("DTUs ");
        return at == std::string::npos ? -1 : std::atoi(text.c_str() + at + 5);
    };

    std::string shown;
    REQUIRE(eventually(
        [&] {
            shown = screen();
            return shown.find("x_position") != std::string::npos && shown.find("spindle_speed") != std::string::npos &&
                   dtus(shown) > 0;
        },
        20s));
    INFO(shown);
    CHECK_THAT(shown, Catch::StartsWith("nclink top  " + kDev));
    CHECK_THAT(shown, Catch::Contains("CHANNEL"));
    CHECK_THAT(shown, Catch::Contains("q quit"));
    // Refreshed in place: the DTU count grows on the same screen line.
    const int first = dtus(shown);
    REQUIRE(eventually([&] { return dtus(screen()) > first; }, 20s));
    CHECK(screen().find("nclink top") == 0);

    // Narrower and shorter: every line fits, the help line is on the last row.
    REQUIRE(shell(tmux + "resize-window -t top -x 50 -y 12").status == 0);
    std::string small;
    REQUIRE(eventually(
        [&] {
            small = screen();
            std::size_t rows = 0, longest = 0, start = 0;
            while (start < small.size()) {
                const auto end = small.find('\n', start);
                longest = std::max(longest, (end == std::string::npos ? small.size() : end) - start);
                ++rows;
                if (end == std::string::npos) break;
                start = end + 1;
            }
            return rows == 12 && longest <= 50 && small.find("q quit") != std::string::npos;
        },
        10s));

    // q quits, and the terminal is left as it was (the alternate screen is gone).
    shell(tmux + "send-keys -t top q");
    std::string after;
    REQUIRE(eventually(
        [&] {
            after = shell(tmux + "list-panes -t top -F '#{pane_dead}'").out;
            return after.rfind("1", 0) == 0;
        },
        10s));
    std::string status;
    REQUIRE(eventually(
        [&] {
            std::ifstream(status_file) >> status;
            return !status.empty();
        },
        10s));
    CHECK(status == "0");
    CHECK(screen().find("nclink top") == std::string::npos);
    shell(tmux + "kill-server");
}

TEST_CASE("nclink call draws a progress bar redrawn in place in a terminal") {
    if (!cli_built()) return;
    if (!have("tmux")) {
        WARN("tmux not installed (Debian package tmux; tools/install-deps.sh): the progress bar not tested in a terminal");
        return;
    }
    SimRig rig(false);
    const std::string tmux = "tmux -L nclink-call-" + std::to_string(std::random_device{}()) + " ";
    const std::string command = cli_path() + " call --broker " + rig.broker.url() + " --timeout 10000 " + kDev +
                                " program_transfer '{\\\"source\\\":\\\"" + rig.program(6144) + "\\\"}'";
    REQUIRE(shell(tmux + "-f /dev/null new-session -d -s call -x 100 -y 20 \"" + command + "\"").status == 0);
    shell(tmux + "set-option -t call remain-on-exit on");
    // With the lines scrolled off the top: when the pane ends, tmux may move
    // the screen up a line for its "Pane is dead" note.
    auto screen = [&] { return shell(tmux + "capture-pane -p -S -100 -t call").out; };
    std::string during;
    REQUIRE(eventually(
        [&] {
            during = screen();
            return during.find("program_transfer [#") != std::string::npos && during.find("executing") != std::string::npos;
        },
        20s));
    INFO(during);
    CHECK(during.find("status ") == std::string::npos);  // a bar, not lines
    std::string after;
    REQUIRE(eventually(
        [&] {
            after = screen();
            return after.find("finished") != std::string::npos;
        },
        20s));
    INFO(after);
    // One line for the bar (redrawn in place), then the result on the next.
    CHECK_THAT(after, Catch::StartsWith("program_transfer ["));
    CHECK_THAT(after, Catch::Contains("100.0% finished") && Catch::Contains("\nfinished\n"));
    CHECK_THAT(after, Catch::Contains("100.0% finished"));
    CHECK(std::count(after.begin(), after.end(), '[') == 1);
    shell(tmux + "kill-server");
}
