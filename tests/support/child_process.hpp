// A program of the build (bin/nclink-agent, bin/nclink-sim, the nclink CLI)
// run by a test, in one of two ways:
// - the fault tests (tests/faults/) kill it -9 and start it again: standard
//   output and standard error are appended to two files the test reads, and
//   the program starts only on start();
// - the service tests (tests/integration/ops/) read its log: standard output
//   goes to /dev/null, standard error to one log file, the program starts at
//   once and gets signals (SIGHUP reloads) and is waited for.
// It is stopped (SIGTERM, then SIGKILL) when the object goes. No Catch
// assertion in here.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace nclink::test {

inline std::string binary_path(const std::string& name) { return std::string(NCLINK_BINARY_DIR) + "/bin/" + name; }

inline std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

class ChildProcess {
public:
    /// Not started yet (start()); stdout and stderr are appended to the files,
    /// so a restarted program adds to what it wrote before.
    ChildProcess(std::vector<std::string> argv, std::string out_file, std::string err_file)
        : argv_(std::move(argv)), out_(std::move(out_file)), err_(std::move(err_file)), append_(true) {}
    /// Starts argv[0] with argv at once; stdin and stdout from/to /dev/null,
    /// stderr to `log_path` (truncated). started() says whether it could.
    ChildProcess(std::vector<std::string> argv, const std::string& log_path)
        : argv_(std::move(argv)), out_("/dev/null"), err_(log_path), append_(false) {
        spawn();
    }
    ~ChildProcess() { end(SIGTERM, std::chrono::seconds(5)); }
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    /// Starts the program (again, once it ended); throws when it cannot.
    void start() {
        if (pid_ > 0 && !exit_status_) return;
        if (!spawn()) throw std::runtime_error("cannot start " + argv_[0]);
    }
    /// kill -9, and reaps it.
    void kill9() { end(SIGKILL, std::chrono::seconds(10)); }
    /// SIGTERM (a clean stop), and reaps it (SIGKILL after 10 s).
    void terminate() { end(SIGTERM, std::chrono::seconds(10)); }

    bool started() const { return pid_ > 0; }
    /// Still running (reaps it when it ended).
    bool running() { return pid_ > 0 && !wait_exit(std::chrono::milliseconds(0)); }
    void signal(int number) const {
        if (pid_ > 0 && !exit_status_) ::kill(pid_, number);
    }
    /// The exit status once the program ended within `timeout` (-1: killed by a signal).
    std::optional<int> wait_exit(std::chrono::milliseconds timeout) {
        if (exit_status_) return exit_status_;
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        while (pid_ > 0) {
            int status = 0;
            if (::waitpid(pid_, &status, WNOHANG) == pid_) {
                exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
                return exit_status_;
            }
            if (std::chrono::steady_clock::now() >= deadline) break;
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        return std::nullopt;
    }

    /// Standard output and standard error so far.
    std::string out() const { return read_text(out_); }
    std::string err() const { return read_text(err_); }
    /// The program's standard error so far (its log).
    std::string log() const { return err(); }
    /// How many times `text` appears in the log so far.
    std::size_t count(const std::string& text) const {
        const std::string all = log();
        std::size_t n = 0;
        for (auto at = all.find(text); at != std::string::npos; at = all.find(text, at + text.size())) ++n;
        return n;
    }

private:
    bool spawn() {
        std::vector<char*> args;
        for (auto& a : argv_) args.push_back(a.data());
        args.push_back(nullptr);
        const int mode = O_WRONLY | O_CREAT | (append_ ? O_APPEND : O_TRUNC);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 1, out_.c_str(), out_ == "/dev/null" ? O_WRONLY : mode, 0644);
        posix_spawn_file_actions_addopen(&actions, 2, err_.c_str(), mode, 0644);
        pid_t pid = -1;
        const int spawned = ::posix_spawn(&pid, argv_[0].c_str(), &actions, nullptr, args.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        pid_ = spawned == 0 ? pid : -1;
        exit_status_.reset();
        return pid_ > 0;
    }
    /// Sends `number` and reaps the program, with SIGKILL after `grace`.
    void end(int number, std::chrono::milliseconds grace) {
        if (pid_ <= 0 || exit_status_) return;
        ::kill(pid_, number);
        if (!wait_exit(grace)) {
            ::kill(pid_, SIGKILL);
            int status = 0;
            ::waitpid(pid_, &status, 0);
            exit_status_ = -1;
        }
    }

    std::vector<std::string> argv_;
    std::string out_, err_;
    bool append_;
    pid_t pid_ = -1;
    std::optional<int> exit_status_;
};

}  // namespace nclink::test
