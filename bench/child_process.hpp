// A copy of the running benchmark started as a child process
// (/proc/self/exe with other arguments), talking over its stdin/stdout in
// lines. Benchmarks run their subjects as children so that each has its own
// process, as in a deployment: paho's C library serves every client of a
// process with one receive thread, one send thread and one mutex, so clients
// sharing a process slow each other down in ways a deployment never sees.
// The child prints "ready" first; the constructor waits for it.
#pragma once

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace nclink::bench {

struct Child {
    pid_t pid = -1;
    FILE* to = nullptr;
    FILE* from = nullptr;

    explicit Child(std::vector<std::string> args) {
        int in_pipe[2], out_pipe[2];
        if (::pipe(in_pipe) != 0 || ::pipe(out_pipe) != 0) throw std::runtime_error("pipe");
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_adddup2(&actions, in_pipe[0], 0);
        posix_spawn_file_actions_adddup2(&actions, out_pipe[1], 1);
        posix_spawn_file_actions_addclose(&actions, in_pipe[1]);
        posix_spawn_file_actions_addclose(&actions, out_pipe[0]);
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        if (::posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ) != 0)
            throw std::runtime_error("spawn");
        posix_spawn_file_actions_destroy(&actions);
        ::close(in_pipe[0]);
        ::close(out_pipe[1]);
        to = ::fdopen(in_pipe[1], "w");
        from = ::fdopen(out_pipe[0], "r");
        if (read_line() != "ready") throw std::runtime_error("child did not start");
    }
    ~Child() {
        if (to) std::fclose(to);
        if (from) std::fclose(from);
        if (pid > 0) ::waitpid(pid, nullptr, 0);
    }
    void say(const char* line) {
        std::fprintf(to, "%s\n", line);
        std::fflush(to);
    }
    std::string read_line() {
        char buffer[1 << 16];
        std::string out;
        while (std::fgets(buffer, sizeof buffer, from)) {
            out += buffer;
            if (!out.empty() && out.back() == '\n') break;
        }
        while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
        return out;
    }
};

}  // namespace nclink::bench
