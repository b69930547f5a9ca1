// The simulated mill's methods: program_transfer (files, progress, pause,
// cancel without a partial file) and the operator methods acting on the
// simulated state.
#include "sim_test_util.hpp"

#include "support/wait.hpp"

#include <nclink/driver_plugin_loader.hpp>

#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <thread>

using namespace nclink;
using sim_test::Rig;
namespace fs = std::filesystem;

namespace {

/// A MethodControl the test steers from its own thread.
class TestControl final : public MethodControl {
public:
    void progress(double percent) override {
        std::lock_guard<std::mutex> lock(mutex_);
        seen_.push_back(percent);
    }
    bool cancelled() const override {
        std::lock_guard<std::mutex> lock(mutex_);
        return cancel_;
    }
    bool checkpoint() override {
        std::unique_lock<std::mutex> lock(mutex_);
        if (pause_) {
            paused_ = true;
            changed_.notify_all();
        }
        changed_.wait(lock, [&] { return !pause_ || cancel_; });
        paused_ = false;
        return !cancel_;
    }
    void pause(bool on) {
        std::lock_guard<std::mutex> lock(mutex_);
        pause_ = on;
        changed_.notify_all();
    }
    void cancel() {
        std::lock_guard<std::mutex> lock(mutex_);
        cancel_ = true;
        changed_.notify_all();
    }
    bool wait_paused() {
        std::unique_lock<std::mutex> lock(mutex_);
        return changed_.wait_for(lock, std::chrono::seconds(10), [&] { return paused_; });
    }
    std::vector<double> seen() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return seen_;
    }
    double last() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return seen_.empty() ? -1 : seen_.back();
    }

private:
    mutable std::mutex mutex_;
    std::condition_variable changed_;
    bool pause_ = false, paused_ = false, cancel_ = false;
    std::vector<double> seen_;
};

struct Dirs {
    fs::path root = fs::temp_directory_path() / ("nclink-sim-methods-" + std::to_string(std::random_device{}()));
    fs::path programs = root / "prog";
    fs::path outside = root / "outside";
    Dirs() {
        fs::create_directories(programs);
        fs::create_directories(outside);
    }
    ~Dirs() {
        std::error_code ec;
        fs::remove_all(root, ec);
    }
    static void write(const fs::path& path, std::size_t bytes) {
        std::ofstream out(path, std::ios::binary);
        for (std::size_t i = 0; i < bytes; ++i) out.put(static_cast<char>('A' + i % 26));
    }
    static std::string read(const fs::path& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }
    static std::size_t entries(const fs::path& dir) {
        return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
    }
};

/// The mill with a program directory, configured through open() as an
/// adapter's driver configuration does.
struct TransferRig : Rig {
    Dirs dirs;
    explicit TransferRig(std::uint64_t rate) : Rig("sim-mill.json") {
        REQUIRE(driver->open(DriverContext{Json{{"program_dir", dirs.programs.string()}, {"transfer_rate", rate}}, {}}).ok());
    }
    Result<Json> transfer(const Json& args, MethodControl& control) {
        return driver->run_method(PointRef{"program_transfer"}, args, control);
    }
};

}  // namespace

TEST_CASE("program_transfer push copies a local file into the program directory") {
    TransferRig rig(0);
    Dirs::write(rig.dirs.outside / "O1234.nc", 5000);
    TestControl control;
    auto r = rig.transfer(Json{{"operation", "push"}, {"source", (rig.dirs.outside / "O1234.nc").string()}}, control);
    REQUIRE(r.ok());
    CHECK(r.value()["bytes"] == 5000);
    CHECK(r.value()["destination"] == "O1234.nc");  // the source's file name by default
    CHECK(Dirs::read(rig.dirs.programs / "O1234.nc") == Dirs::read(rig.dirs.outside / "O1234.nc"));
    CHECK(Dirs::entries(rig.dirs.programs) == 1);  // no temp file left
    const auto seen = control.seen();
    REQUIRE(seen.size() >= 5);  // per KiB
    CHECK(seen.front() == 0);
    CHECK(seen.back() == 100);
    CHECK(std::is_sorted(seen.begin(), seen.end()));
}

TEST_CASE("program_transfer pull copies a program out to a local path") {
    TransferRig rig(0);
    Dirs::write(rig.dirs.programs / "O2000", 3000);
    TestControl control;
    const fs::path target = rig.dirs.outside / "backup" / "O2000.nc";
    auto r = rig.transfer(Json{{"operation", "pull"}, {"source", "O2000"}, {"destination", target.string()}}, control);
    REQUIRE(r.ok());
    CHECK(r.value()["bytes"] == 3000);
    CHECK(Dirs::read(target) == Dirs::read(rig.dirs.programs / "O2000"));
}

TEST_CASE("program_transfer refuses what it cannot or must not do") {
    TransferRig rig(0);
    Dirs::write(rig.dirs.outside / "p.nc", 10);
    TestControl control;
    const std::string src = (rig.dirs.outside / "p.nc").string();
    CHECK(rig.transfer(Json{{"source", src}, {"destination", "../escape"}}, control).error().code == ErrorCode::permission_denied);
    CHECK(rig.transfer(Json{{"operation", "pull"}, {"source", "../p.nc"}, {"destination", "/tmp/x"}}, control).error().code ==
          ErrorCode::permission_denied);
    CHECK(rig.transfer(Json{{"operation", "pull"}, {"source", "p.nc"}}, control).error().code == ErrorCode::parameter_missing);
    CHECK(rig.transfer(Json{{"source", (rig.dirs.outside / "missing.nc").string()}}, control).error().code ==
          ErrorCode::unavailable);
    CHECK(rig.transfer(Json{{"source", src}, {"protocol", "FTP"}}, control).error().code == ErrorCode::out_of_range);
    CHECK(rig.transfer(Json{{"source", src}, {"operation", "sync"}}, control).error().code == ErrorCode::out_of_range);
    CHECK(rig.transfer(Json::object(), control).error().code == ErrorCode::parameter_missing);
    CHECK(Dirs::entries(rig.dirs.programs) == 0);
    Rig no_dir("sim-mill.json");
    CHECK(no_dir.driver->run_method(PointRef{"program_transfer"}, Json{{"source", src}}, control).error().code ==
          ErrorCode::unavailable);
}

TEST_CASE("a paced transfer follows the clock, pauses at checkpoints and cancels without a partial file") {
    TransferRig rig(1024);  // 1 KiB per simulated second
    Dirs::write(rig.dirs.outside / "big.nc", 8 * 1024);
    Dirs::write(rig.dirs.programs / "big.nc", 100);  // an older version that must survive a cancel
    TestControl control;
    Result<Json> outcome = make_error(ErrorCode::unavailable);
    std::thread method([&] { outcome = rig.transfer(Json{{"source", (rig.dirs.outside / "big.nc").string()}}, control); });

    REQUIRE(nclink::test::eventually([&] { return !control.seen().empty(); }));  // started: its pace counts from now
    rig.advance_ms(2'000);
    REQUIRE(nclink::test::eventually([&] { return control.last() >= 25; }));
    // Reads go on while the transfer runs: it does not hold the simulator.
    CHECK(rig.value("status") == "running");
    control.pause(true);
    rig.advance_ms(1'000);  // the chunk under way completes; the next checkpoint pauses
    REQUIRE(control.wait_paused());
    const double at_pause = control.last();
    rig.advance_ms(4'000);
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    CHECK(control.last() == at_pause);
    control.pause(false);
    REQUIRE(nclink::test::eventually([&] { return control.last() >= 50; }));
    CHECK(control.last() < 100);
    control.cancel();
    method.join();
    REQUIRE(outcome.ok());                                          // a cancelled method returns what it did
    CHECK(outcome.value()["bytes"].get<int>() >= 4 * 1024);         // what was copied before the cancel
    CHECK(Dirs::read(rig.dirs.programs / "big.nc").size() == 100);  // untouched
    CHECK(Dirs::entries(rig.dirs.programs) == 1);                   // no temp file
}

TEST_CASE("operator methods act on the simulated state") {
    Rig rig("sim-mill.json", 1, false);
    TestControl control;
    CHECK(rig.value("status") == "free");
    auto started = rig.driver->run_method(PointRef{"cycle_start"}, Json::object(), control);
    REQUIRE(started.ok());
    CHECK(started.value() == Json{{"status", "running"}});
    CHECK(rig.value("status") == "running");
    CHECK(rig.driver->run_method(PointRef{"feed_hold"}, Json::object(), control).value()["status"] == "holding");
    CHECK(rig.value("status") == "holding");
    rig.driver->raise_alarm("1001", "spindle overload");
    CHECK(rig.driver->run_method(PointRef{"reset"}, Json::object(), control).value()["status"] == "free");
    CHECK(rig.value("status") == "free");
    CHECK(rig.value("line_number") == "0");
    CHECK(control.last() == 100);
}

TEST_CASE("the plugin transfers programs with the directory from its configuration") {
    Dirs dirs;
    Dirs::write(dirs.outside / "O9.nc", 2048);
    auto loaded = load_driver_plugin(std::string(NCLINK_BINARY_DIR) + "/lib/nclink-sim.so",
                                     Json{{"model", std::string(NCLINK_MODELS_DIR) + "/sim-mill.json"},
                                          {"program_dir", dirs.programs.string()},
                                          {"transfer_rate", 0}});
    REQUIRE(loaded.ok());
    TestControl control;
    auto r = loaded.value()->run_method(PointRef{"program_transfer"}, Json{{"source", (dirs.outside / "O9.nc").string()}}, control);
    REQUIRE(r.ok());
    CHECK(r.value()["bytes"] == 2048);
    CHECK(fs::file_size(dirs.programs / "O9.nc") == 2048);
    CHECK(control.last() == 100);
}
