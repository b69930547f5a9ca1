// A program of the build (bin/nclink-agent, bin/nclink-sim, ...) run by an
// integration test: its standard error goes to a file the test reads (the
// program's log), it gets signals (SIGHUP reloads), and it is stopped
// (SIGTERM, then SIGKILL) when the object goes. No Catch assertion in here.
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
    /// Starts argv[0] with argv; stdin and stdout from/to /dev/null, stderr to `log_path`.
    ChildProcess(std::vector<std::string> argv, const std::string& log_path) : log_(log_path) {
        std::vector<char*> args;
        for (auto& a : argv) args.push_back(a.data());
        args.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 2, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (::posix_spawn(&pid_, argv[0].c_str(), &actions, nullptr, args.data(), environ) != 0) pid_ = -1;
        posix_spawn_file_actions_destroy(&actions);
    }
    ~ChildProcess() {
        if (pid_ <= 0 || exit_status_) return;
        ::kill(pid_, SIGTERM);
        if (!wait_exit(std::chrono::seconds(5))) {
            ::kill(pid_, SIGKILL);
            int status = 0;
            ::waitpid(pid_, &status, 0);
        }
    }
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    bool started() const { return pid_ > 0; }
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
            if (std::chrono::steady_clock::now() > deadline) break;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return std::nullopt;
    }
    /// The program's standard error so far.
    std::string log() const { return read_text(log_); }
    /// How many times `text` appears in the log so far.
    std::size_t count(const std::string& text) const {
        const std::string all = log();
        std::size_t n = 0;
        for (auto at = all.find(text); at != std::string::npos; at = all.find(text, at + text.size())) ++n;
        return n;
    }

private:
    pid_t pid_ = -1;
    std::string log_;
    std::optional<int> exit_status_;
};

}  // namespace nclink::test
