// A real mosquitto for integration tests: started on a free 127.0.0.1 port
// with the settings nclink ships (tools/mosquitto/nclink.conf), no persistence; stopped (SIGTERM, then SIGKILL) on
// destruction. restart() keeps the port so clients can reconnect.
#pragma once

#include <string>
#include <sys/types.h>

namespace nclink::test {

struct MosquittoOptions {
    /// Keep sessions and queued QoS 1 messages across restart() (saved on
    /// SIGTERM into the broker's scratch directory).
    bool persistent = false;
    /// With `persistent`: also save after every change (autosave_on_changes,
    /// autosave_interval 1), so sessions and queued messages survive a
    /// kill -9 too (crash(); docs/delivery.md).
    bool save_every_change = false;
    /// With save_every_change: save after this many changes (autosave_interval).
    int save_after_changes = 1;
    int port = 0;       ///< 0 = pick a free one
    bool start = true;  ///< false: construct stopped, call start() later
    /// mosquitto acl_file to enforce ("" = none). Without a password_file
    /// clients may still connect anonymously or with any user name.
    std::string acl_file;
    /// mosquitto password_file ("" = none); when set, anonymous clients are refused.
    std::string password_file;
    /// Include tools/mosquitto/nclink.conf (set_tcp_nodelay true, ...), the
    /// settings nclink ships for a plant's broker. false = mosquitto's
    /// defaults (a broker that delays small packets).
    bool shipped_settings = true;
    /// max_queued_messages 100000 over the shipped limit (tests burst
    /// harder than a plant); false = exactly what a plant's broker has.
    bool large_queues = true;
    /// Appended to the configuration as is, last: more listeners (TLS, see
    /// support/test_pki.hpp), each with its own options.
    std::string extra_config;
};

class MosquittoBroker {
public:
    explicit MosquittoBroker(MosquittoOptions options = {});  // throws std::runtime_error when it cannot start
    ~MosquittoBroker();
    MosquittoBroker(const MosquittoBroker&) = delete;
    MosquittoBroker& operator=(const MosquittoBroker&) = delete;

    void stop();
    /// kill -9: no shutdown save, no clean goodbye to the clients.
    void crash();
    void start();
    void restart() {
        stop();
        start();
    }
    /// SIGSTOP: the broker keeps its sockets open but reads and answers
    /// nothing (a hung broker: QoS 1 messages stay unacknowledged).
    void freeze();
    /// SIGCONT after freeze(); stop() resumes a frozen broker first.
    void thaw();
    bool running() const { return pid_ > 0; }
    /// The broker's process (benchmarks read its CPU); -1 when stopped.
    pid_t pid() const { return pid_; }

    int port() const { return port_; }
    std::string url() const { return "tcp://127.0.0.1:" + std::to_string(port_); }

private:
    int port_ = 0;
    pid_t pid_ = -1;
    std::string dir_;
    std::string config_;
};

/// A free TCP port on 127.0.0.1 (bound and released; tiny race accepted).
int free_loopback_port();

/// Whether something accepts TCP connections on 127.0.0.1:port now (a
/// broker or node that has come up, or not yet gone).
bool port_accepts(int port);

}  // namespace nclink::test
