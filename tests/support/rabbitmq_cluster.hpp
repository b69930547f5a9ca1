// A real RabbitMQ cluster for the cluster tests (tests/integration/cluster/,
// label `cluster`, docs/scaling.md): N nodes of Debian's rabbitmq-server
// (3.10, its rabbitmq_mqtt plugin enabled) on 127.0.0.1, each with its own
// MQTT, AMQP and Erlang distribution port (free ports), their own epmd on a
// free port, their own cookie, node names and scratch directory, so two
// clusters (or a system RabbitMQ) never meet. Nodes 2..N join node 1 with
// `rabbitmqctl join_cluster`. Starting takes about 30 s on a quiet box.
// kill_node() is kill -9 of a node's whole process group; start_node() starts
// it again with its old data, and it rejoins the cluster by itself.
// Everything is killed and the directory removed on destruction; what a
// crashed test left behind is killed by the next cluster a test starts.
#pragma once

#include <string>
#include <sys/types.h>
#include <vector>

namespace nclink::test {

class RabbitCluster {
public:
    /// "" when rabbitmq-server (and the epmd it brings) is installed; else
    /// why the cluster tests are skipped, for the test's WARN.
    static std::string unavailable_reason();

    /// Starts `nodes` nodes and joins them; throws std::runtime_error (with
    /// the tail of the failing node's output) when it cannot.
    explicit RabbitCluster(int nodes = 3);
    ~RabbitCluster();
    RabbitCluster(const RabbitCluster&) = delete;
    RabbitCluster& operator=(const RabbitCluster&) = delete;

    int size() const { return static_cast<int>(nodes_.size()); }
    /// Node i (0-based): its MQTT port and broker URL.
    int mqtt_port(int i) const { return nodes_.at(static_cast<std::size_t>(i)).mqtt_port; }
    std::string url(int i) const { return "tcp://127.0.0.1:" + std::to_string(mqtt_port(i)); }
    std::string node_name(int i) const { return nodes_.at(static_cast<std::size_t>(i)).name; }
    bool running(int i) const { return nodes_.at(static_cast<std::size_t>(i)).pid > 0; }

    /// kill -9 of node i (the Erlang VM and its helpers); returns once its
    /// MQTT port no longer accepts.
    void kill_node(int i);
    /// Starts node i again (after kill_node()) and waits until its MQTT
    /// listener accepts; it rejoins the cluster from its own data.
    void start_node(int i);

    /// Runs `rabbitmqctl -n <node i> args...` and returns what it printed;
    /// throws when it fails.
    std::string ctl(int i, const std::vector<std::string>& args) const;

private:
    struct Node {
        std::string name;
        int mqtt_port = 0;
        int amqp_port = 0;
        int dist_port = 0;
        pid_t pid = -1;  ///< also its process group
    };
    void write_node_config(const Node& node) const;
    void spawn_node(Node& node);
    void wait_node_up(const Node& node) const;
    void boot_node(Node& node);
    std::vector<std::string> environment(const Node* node) const;

    std::string dir_;
    int epmd_port_ = 0;
    pid_t epmd_pid_ = -1;
    std::vector<Node> nodes_;
};

}  // namespace nclink::test
