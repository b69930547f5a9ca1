// A real ejabberd cluster for the cluster tests (tests/integration/cluster/,
// label `cluster`, docs/scaling.md): N nodes of Debian's ejabberd 23.01 (its
// mod_mqtt listener) on 127.0.0.1, each with its own MQTT and Erlang
// distribution port (free ports), their own epmd on a free port, their own
// cookie, node names, configuration and Mnesia spool in a scratch
// directory, so two clusters (a RabbitMQ one of the same tests, or a system
// ejabberd) never meet. Nodes 2..N join node 1 with `ejabberdctl
// join_cluster`. Starting three takes about 6 s on an idle 2-core box, the
// joins being most of it. kill_node() is kill -9 of a node's whole process group;
// start_node() starts it again with its old spool, and Mnesia brings it back
// into the cluster by itself. Everything is killed and the directory removed
// on destruction; what a crashed test left behind is killed by the next
// cluster a test starts.
//
// mod_mqtt takes the MQTT user name as the user of an ejabberd account and
// checks the password with the host's authentication; the nodes use
// anonymous login, so any user name with any non-empty password gets in.
// A CONNECT without a password is refused (23.01 then accepts only a TLS
// client certificate): every client of these tests logs in as username() /
// password().
#pragma once

#include <string>
#include <sys/types.h>
#include <vector>

namespace nclink::test {

class EjabberdCluster {
public:
    /// "" when ejabberd (and the epmd it brings) is installed; else why the
    /// ejabberd tests are skipped, for the test's WARN.
    static std::string unavailable_reason();

    /// Starts `nodes` nodes and joins them; throws std::runtime_error (with
    /// the tail of the failing node's output) when it cannot.
    explicit EjabberdCluster(int nodes = 3);
    ~EjabberdCluster();
    EjabberdCluster(const EjabberdCluster&) = delete;
    EjabberdCluster& operator=(const EjabberdCluster&) = delete;

    int size() const { return static_cast<int>(nodes_.size()); }
    /// Node i (0-based): its MQTT port and broker URL.
    int mqtt_port(int i) const { return nodes_.at(static_cast<std::size_t>(i)).mqtt_port; }
    std::string url(int i) const { return "tcp://127.0.0.1:" + std::to_string(mqtt_port(i)); }
    std::string node_name(int i) const { return nodes_.at(static_cast<std::size_t>(i)).name; }
    bool running(int i) const { return nodes_.at(static_cast<std::size_t>(i)).pid > 0; }

    /// The login every MQTT client of the tests uses (anonymous login: any
    /// pair with a non-empty password would do).
    static std::string username() { return "nclink"; }
    static std::string password() { return "nclink-test"; }

    /// kill -9 of node i (the shell script, the Erlang VM and its helpers);
    /// returns once its MQTT port no longer accepts.
    void kill_node(int i);
    /// Starts node i again (after kill_node()) and waits until its MQTT
    /// listener accepts; it comes back into the cluster from its own spool.
    void start_node(int i);

    /// Runs `ejabberdctl --node <node i> args...` and returns what it
    /// printed; throws when it fails.
    std::string ctl(int i, const std::vector<std::string>& args) const;
    /// ctl(), given again (at most five times, a second apart) while the
    /// node does not answer the RPC yet ("nodedown").
    std::string ctl_reaching_node(int i, const std::vector<std::string>& args) const;

    /// Resident memory of node i's Erlang VM in KiB (VmRSS), 0 if not found.
    long resident_kib(int i) const;

private:
    struct Node {
        std::string name;
        std::string dir;
        int mqtt_port = 0;
        int dist_port = 0;
        pid_t pid = -1;  ///< the ejabberdctl script; also its process group
    };
    void write_node_config(const Node& node) const;
    void spawn_node(Node& node);
    void wait_node_up(const Node& node) const;
    void boot_node(Node& node);
    std::vector<std::string> environment() const;

    std::string dir_;
    int epmd_port_ = 0;
    pid_t epmd_pid_ = -1;
    std::vector<Node> nodes_;
};

}  // namespace nclink::test
