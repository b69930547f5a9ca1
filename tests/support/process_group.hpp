// Processes the broker clusters of the cluster tests run (ejabberd_cluster,
// an Erlang VM under a shell script each): started in a process group of
// their own, so kill -9 of the group takes the script, the VM and its helper
// processes together, and found again by the next test when one crashed
// without cleaning up. No Catch assertion in here.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace nclink::test {

/// Spawns argv in a process group of its own with environment `env`, stdin
/// from /dev/null, stdout and stderr appended to `output`.
inline pid_t spawn_in_group(const std::vector<std::string>& argv, const std::vector<std::string>& env, const std::string& output) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    std::vector<char*> envp;
    for (const auto& e : env) envp.push_back(const_cast<char*>(e.c_str()));
    envp.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, output.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
    pid_t pid = -1;
    const int rc = ::posix_spawn(&pid, argv[0].c_str(), &actions, &attributes, args.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    if (rc != 0) throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(rc));
    return pid;
}

inline std::string whole_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

/// The last 2,000 characters of a file (a node's output, for an error).
inline std::string file_tail(const std::string& path) {
    const std::string all = whole_file(path);
    return all.size() > 2000 ? all.substr(all.size() - 2000) : all;
}

/// Alive: not gone and not a zombie nobody reaped (state Z in /proc/PID/stat).
inline bool process_alive(pid_t pid) {
    if (::kill(pid, 0) != 0 && errno != EPERM) return false;
    const std::string stat = whole_file("/proc/" + std::to_string(pid) + "/stat");
    const auto paren = stat.rfind(')');
    return paren == std::string::npos || paren + 2 >= stat.size() || stat[paren + 2] != 'Z';
}

/// kill -9 of the group `pid` leads, reaping its leader; pid becomes -1.
inline void kill_group(pid_t& pid) {
    if (pid <= 0) return;
    ::kill(-pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    pid = -1;
}

/// Runs argv (a broker's control script) in a group of its own to its end,
/// its output in `output`, at most two minutes; returns the output's tail.
/// Throws, naming `what`, when it fails or hangs (the group is killed then).
inline std::string run_in_group(const std::vector<std::string>& argv, const std::vector<std::string>& env,
                                const std::string& output, const std::string& what) {
    std::remove(output.c_str());
    pid_t pid = spawn_in_group(argv, env, output);
    int status = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (::waitpid(pid, &status, WNOHANG) != pid) {
        if (std::chrono::steady_clock::now() > deadline) {
            kill_group(pid);
            throw std::runtime_error(what + " did not finish");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    const std::string said = file_tail(output);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) throw std::runtime_error(what + " failed:\n" + said);
    return said;
}

/// Waits (at most three minutes) until `up()` says a node started as `pid`
/// serves; throws, naming `what` and the tail of its `log`, when the node
/// exits first or never does.
inline void wait_until_up(pid_t pid, const std::function<bool()>& up, const std::string& what, const std::string& log) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(180);
    while (!up()) {
        int status = 0;
        if (pid > 0 && ::waitpid(pid, &status, WNOHANG) == pid)
            throw std::runtime_error(what + " exited at start:\n" + file_tail(log));
        if (std::chrono::steady_clock::now() > deadline)
            throw std::runtime_error(what + " did not open its MQTT port:\n" + file_tail(log));
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

/// A test that died without running a cluster's destructor (a crash, the
/// SIGKILL of ctest's timeout) leaves its nodes running. Each cluster keeps
/// its owner's pid in <dir>/owner and its process groups in <dir>/groups,
/// under /tmp/<prefix>XXXXXX; this ends those whose owner is gone. A group
/// whose leader still exists is killed only if that leader's command line
/// names `leader_word` or epmd (the number was not reused).
inline void end_orphaned_clusters(const std::string& prefix, const std::string& leader_word) {
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator("/tmp", error)) {
        const std::string dir = entry.path().string();
        if (entry.path().filename().string().rfind(prefix, 0) != 0) continue;
        const pid_t owner = std::atoi(whole_file(dir + "/owner").c_str());
        if (owner <= 0 || process_alive(owner)) continue;
        std::istringstream groups(whole_file(dir + "/groups"));
        for (pid_t group = 0; groups >> group;) {
            if (group <= 0) continue;
            const std::string leader = whole_file("/proc/" + std::to_string(group) + "/cmdline");
            if (!leader.empty() && leader.find(leader_word) == std::string::npos && leader.find("epmd") == std::string::npos)
                continue;
            ::kill(-group, SIGKILL);
        }
        std::filesystem::remove_all(dir, error);
    }
}

/// A scratch directory /tmp/<prefix>XXXXXX for a new cluster, with the file
/// `owner` (this process) that end_orphaned_clusters() reads, and the Erlang
/// cookie every node and ctl command read from $HOME in it: this cluster's
/// own (`tag`, this pid, `salt`), so no other Erlang node on the machine can
/// join it. Throws when the directory cannot be made.
inline std::string make_cluster_dir(const std::string& prefix, const std::string& tag, int salt) {
    std::string pattern = "/tmp/" + prefix + "XXXXXX";
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    std::ofstream(pattern + "/owner") << ::getpid() << "\n";
    std::ofstream(pattern + "/.erlang.cookie") << tag << ::getpid() << "X" << salt;
    ::chmod((pattern + "/.erlang.cookie").c_str(), 0400);
    return pattern;
}

}  // namespace nclink::test
