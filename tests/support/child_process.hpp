// A program run by a test (nclink-sim, nclink-agent, the nclink CLI) that the
// test can kill -9 and start again: the fault tests (tests/faults/). Its
// standard output goes to a file the test reads; standard error to another
// (kept for a failing test's message). Killed on destruction.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace nclink::test {

class ChildProcess {
public:
    ChildProcess(std::vector<std::string> argv, std::string out_file, std::string err_file)
        : argv_(std::move(argv)), out_(std::move(out_file)), err_(std::move(err_file)) {}
    ~ChildProcess() { kill9(); }
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    /// Starts the program; its output is appended to the files.
    void start() {
        if (pid_ > 0) return;
        std::vector<char*> args;
        for (auto& a : argv_) args.push_back(a.data());
        args.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 1, out_.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        posix_spawn_file_actions_addopen(&actions, 2, err_.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        pid_t pid = -1;
        const int spawned = ::posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        if (spawned != 0) throw std::runtime_error("cannot start " + argv_[0]);
        pid_ = pid;
    }
    /// kill -9, and reaps it.
    void kill9() { end(SIGKILL); }
    /// SIGTERM (a clean stop), and reaps it (SIGKILL after 10 s).
    void terminate() { end(SIGTERM); }
    bool running() {
        if (pid_ <= 0) return false;
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            return false;
        }
        return true;
    }
    std::string out() const { return read(out_); }
    std::string err() const { return read(err_); }

private:
    void end(int signal) {
        if (pid_ <= 0) return;
        ::kill(pid_, signal);
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        int status = 0;
        while (::waitpid(pid_, &status, WNOHANG) != pid_) {
            if (std::chrono::steady_clock::now() > deadline) {
                ::kill(pid_, SIGKILL);
                ::waitpid(pid_, &status, 0);
                break;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        pid_ = -1;
    }
    static std::string read(const std::string& path) {
        std::ifstream in(path);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }

    std::vector<std::string> argv_;
    std::string out_, err_;
    pid_t pid_ = -1;
};

}  // namespace nclink::test
