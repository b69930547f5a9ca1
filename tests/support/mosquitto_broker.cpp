#include "support/mosquitto_broker.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <pwd.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace nclink::test {
namespace {

std::string find_mosquitto() {
    for (const char* path : {"/usr/sbin/mosquitto", "/usr/bin/mosquitto", "/usr/local/sbin/mosquitto"})
        if (::access(path, X_OK) == 0) return path;
    throw std::runtime_error("mosquitto not found (tools/install-deps.sh installs it)");
}

}  // namespace

bool port_accepts(int port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return false;
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
    ::close(fd);
    return ok;
}

int free_loopback_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = 0;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
        throw std::runtime_error("cannot find a free port");
    ::close(fd);
    return ntohs(addr.sin_port);
}

MosquittoBroker::MosquittoBroker(MosquittoOptions options) {
    char pattern[] = "/tmp/nclink-mosquitto-XXXXXX";
    if (!::mkdtemp(pattern)) throw std::runtime_error("mkdtemp failed");
    dir_ = pattern;
    // Started as root (CI, containers), mosquitto drops to its own user
    // ("mosquitto", else "nobody"): that user must be able to write the
    // persistence file here, or every save fails ("Permission denied", unseen
    // with log_dest none) and a restart forgets every session and queued
    // message, as a plant's /var/lib/mosquitto owned by root would.
    if (::geteuid() == 0) {
        const passwd* user = ::getpwnam("mosquitto");
        if (!user) user = ::getpwnam("nobody");
        if (user && ::chown(dir_.c_str(), user->pw_uid, user->pw_gid) != 0)
            throw std::runtime_error("cannot hand the broker's directory to its user");
    }
    config_ = dir_ + "/mosquitto.conf";
    port_ = options.port ? options.port : free_loopback_port();
    std::ofstream conf(config_);
    conf << "listener " << port_ << " 127.0.0.1\n"
         << "allow_anonymous " << (options.password_file.empty() ? "true" : "false") << "\n";
    if (!options.acl_file.empty()) conf << "acl_file " << options.acl_file << "\n";
    if (!options.password_file.empty()) conf << "password_file " << options.password_file << "\n";
    if (options.persistent && options.save_every_change)
        conf << "persistence true\npersistence_location " << dir_ << "/\nautosave_on_changes true\nautosave_interval "
             << options.save_after_changes << "\n";
    else if (options.persistent) conf << "persistence true\npersistence_location " << dir_ << "/\nautosave_interval 0\n";
    else conf << "persistence false\n";
    // The settings nclink ships for a plant's broker, as a user would add them.
    if (options.shipped_settings) {
        std::ifstream shipped(std::string(NCLINK_SOURCE_DIR) + "/tools/mosquitto/nclink.conf");
        if (!shipped) throw std::runtime_error("tools/mosquitto/nclink.conf not found");
        conf << shipped.rdbuf() << "\n";
    }
    if (options.large_queues) conf << "max_queued_messages 100000\n";  // tests burst harder than a plant
    conf << "log_dest none\n";
    // Last: more listeners (TLS) whose own options follow their listener line.
    conf << options.extra_config << "\n";
    conf.close();
    if (options.start) start();
}

MosquittoBroker::~MosquittoBroker() {
    stop();
    std::remove(config_.c_str());
    std::remove((dir_ + "/mosquitto.db").c_str());
    ::rmdir(dir_.c_str());
}

void MosquittoBroker::start() {
    if (pid_ > 0) return;
    const std::string binary = find_mosquitto();
    std::string arg_c = "-c";
    char* argv[] = {const_cast<char*>(binary.c_str()), arg_c.data(), config_.data(), nullptr};
    pid_t pid = -1;
    // stdio to /dev/null: a broker left behind by a crashed test must not hold
    // ctest's output pipe open (ctest would wait for it until the timeout).
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    for (int fd : {0, 1, 2}) posix_spawn_file_actions_addopen(&actions, fd, "/dev/null", O_RDWR, 0);
    const int spawned = ::posix_spawn(&pid, binary.c_str(), &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) throw std::runtime_error("cannot start mosquitto");
    pid_ = pid;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!port_accepts(port_)) {
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            throw std::runtime_error("mosquitto exited at start (port " + std::to_string(port_) + ")");
        }
        if (std::chrono::steady_clock::now() > deadline) throw std::runtime_error("mosquitto did not start");
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

void MosquittoBroker::crash() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    while (port_accepts(port_)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

void MosquittoBroker::freeze() {
    if (pid_ > 0) ::kill(pid_, SIGSTOP);
}

void MosquittoBroker::thaw() {
    if (pid_ > 0) ::kill(pid_, SIGCONT);
}

void MosquittoBroker::stop() {
    if (pid_ <= 0) return;
    thaw();  // a stopped process would not act on SIGTERM
    ::kill(pid_, SIGTERM);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) != pid_) {
        if (std::chrono::steady_clock::now() > deadline) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, &status, 0);
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    pid_ = -1;
    // The port is free again once nothing listens.
    while (port_accepts(port_)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

}  // namespace nclink::test
