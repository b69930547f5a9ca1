#include "support/rabbitmq_cluster.hpp"

#include "support/mosquitto_broker.hpp"  // free_loopback_port(), port_accepts()
#include "support/process_group.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace nclink::test {
namespace {

// The scripts themselves, not the /usr/sbin wrappers: those switch to the
// rabbitmq user when run as root and drop the environment that points the
// node at its own directory.
constexpr const char* server_script = "/usr/lib/rabbitmq/bin/rabbitmq-server";
constexpr const char* ctl_script = "/usr/lib/rabbitmq/bin/rabbitmqctl";
constexpr const char* epmd_binary = "/usr/bin/epmd";

}  // namespace

std::string RabbitCluster::unavailable_reason() {
    for (const char* path : {server_script, ctl_script, epmd_binary})
        if (::access(path, X_OK) != 0)
            return std::string("RabbitMQ is not installed (") + path +
                   " missing): the cluster tests are skipped; NCLINK_WITH_RABBITMQ=1 tools/install-deps.sh installs it";
    return "";
}

RabbitCluster::RabbitCluster(int nodes) {
    const std::string reason = unavailable_reason();
    if (!reason.empty()) throw std::runtime_error(reason);
    end_orphaned_clusters("nclink-rabbitmq-", "rabbitmq");
    dir_ = make_cluster_dir("nclink-rabbitmq-", "NCLINKTEST", free_loopback_port());
    try {
        std::ofstream(dir_ + "/enabled_plugins") << "[rabbitmq_mqtt].\n";
        std::ofstream(dir_ + "/rabbitmq-env.conf") << "";  // not /etc/rabbitmq's

        // An epmd of its own, on loopback only: node names need be unique
        // only within this cluster, and nothing outside it sees them.
        epmd_port_ = free_loopback_port();
        epmd_pid_ = spawn_in_group({epmd_binary, "-port", std::to_string(epmd_port_), "-address", "127.0.0.1"},
                                   environment(nullptr), dir_ + "/epmd.out");
        std::ofstream(dir_ + "/groups", std::ios::app) << epmd_pid_ << "\n";
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (!port_accepts(epmd_port_)) {
            if (std::chrono::steady_clock::now() > deadline) throw std::runtime_error("epmd did not start");
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }

        for (int i = 0; i < nodes; ++i) {
            Node node;
            node.name = "nclink" + std::to_string(i + 1) + "@localhost";
            node.mqtt_port = free_loopback_port();
            node.amqp_port = free_loopback_port();
            node.dist_port = free_loopback_port();
            nodes_.push_back(node);
            write_node_config(node);
        }
        // All nodes boot at once (the boot is most of the time), then 2..N join 1.
        for (auto& node : nodes_) spawn_node(node);
        for (auto& node : nodes_) boot_node(node);
        for (int i = 1; i < nodes; ++i) {
            ctl(i, {"stop_app"});
            ctl(i, {"join_cluster", nodes_[0].name});
            ctl(i, {"start_app"});
            wait_node_up(nodes_[static_cast<std::size_t>(i)]);
        }
    } catch (...) {
        for (auto& node : nodes_) kill_group(node.pid);
        kill_group(epmd_pid_);
        std::error_code ignored;
        std::filesystem::remove_all(dir_, ignored);
        throw;
    }
}

RabbitCluster::~RabbitCluster() {
    // The data is thrown away with the directory: no clean shutdown needed.
    for (auto& node : nodes_) kill_group(node.pid);
    kill_group(epmd_pid_);
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
}

void RabbitCluster::write_node_config(const Node& node) const {
    // RabbitMQ's own configuration format (rabbitmq.conf): every listener on
    // loopback; anonymous MQTT clients as the guest user, which may connect
    // from loopback only by default (loopback_users none lifts even that).
    std::ofstream conf(dir_ + "/" + node.name + ".conf");
    conf << "listeners.tcp.1 = 127.0.0.1:" << node.amqp_port << "\n"
         << "mqtt.listeners.tcp.1 = 127.0.0.1:" << node.mqtt_port << "\n"
         << "mqtt.allow_anonymous = true\n"
         << "loopback_users = none\n";
}

std::vector<std::string> RabbitCluster::environment(const Node* node) const {
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e) {
        const std::string entry = *e;
        // Whatever the caller's environment says about RabbitMQ or Erlang
        // would point the nodes elsewhere.
        if (entry.rfind("RABBITMQ_", 0) == 0 || entry.rfind("ERL_", 0) == 0 || entry.rfind("HOME=", 0) == 0) continue;
        env.push_back(entry);
    }
    env.push_back("HOME=" + dir_);
    env.push_back("ERL_EPMD_PORT=" + std::to_string(epmd_port_));
    env.push_back("ERL_EPMD_ADDRESS=127.0.0.1");
    env.push_back("RABBITMQ_CONF_ENV_FILE=" + dir_ + "/rabbitmq-env.conf");
    if (node) {
        env.push_back("RABBITMQ_NODENAME=" + node->name);
        env.push_back("RABBITMQ_NODE_IP_ADDRESS=127.0.0.1");
        env.push_back("RABBITMQ_NODE_PORT=" + std::to_string(node->amqp_port));
        env.push_back("RABBITMQ_DIST_PORT=" + std::to_string(node->dist_port));
        env.push_back("RABBITMQ_MNESIA_BASE=" + dir_ + "/mnesia");
        env.push_back("RABBITMQ_LOG_BASE=" + dir_ + "/log");
        env.push_back("RABBITMQ_ENABLED_PLUGINS_FILE=" + dir_ + "/enabled_plugins");
        env.push_back("RABBITMQ_CONFIG_FILE=" + dir_ + "/" + node->name + ".conf");
        env.push_back("RABBITMQ_ADVANCED_CONFIG_FILE=" + dir_ + "/" + node->name + "-advanced.config");
        // The distribution listener on loopback too.
        env.push_back("RABBITMQ_SERVER_ADDITIONAL_ERL_ARGS=-kernel inet_dist_use_interface {127,0,0,1}");
    }
    return env;
}

void RabbitCluster::spawn_node(Node& node) {
    node.pid = spawn_in_group({server_script}, environment(&node), dir_ + "/" + node.name + ".out");
    std::ofstream(dir_ + "/groups", std::ios::app) << node.pid << "\n";
}

// A port found free can be taken before the node binds it (by another
// test, or as an outgoing connection's ephemeral port: RabbitMQ then stops
// with dist_port_already_used or eaddrinuse). Such a node boots again on
// new ports, at most twice more.
void RabbitCluster::boot_node(Node& node) {
    for (int attempt = 1;; ++attempt) {
        try {
            wait_node_up(node);
            return;
        } catch (const std::runtime_error& e) {
            const std::string why = e.what();
            const bool port_taken = why.find("already_used") != std::string::npos || why.find("eaddrinuse") != std::string::npos;
            if (!port_taken || attempt == 3) throw;
        }
        node.mqtt_port = free_loopback_port();
        node.amqp_port = free_loopback_port();
        node.dist_port = free_loopback_port();
        write_node_config(node);
        spawn_node(node);
    }
}

void RabbitCluster::wait_node_up(const Node& node) const {
    // The MQTT listener opens last, once the plugin has started.
    wait_until_up(
        node.pid, [&] { return port_accepts(node.mqtt_port); }, "RabbitMQ node " + node.name, dir_ + "/" + node.name + ".out");
}

std::string RabbitCluster::ctl(int i, const std::vector<std::string>& args) const {
    const Node& node = nodes_.at(static_cast<std::size_t>(i));
    std::vector<std::string> argv{ctl_script, "-q", "-n", node.name};
    argv.insert(argv.end(), args.begin(), args.end());
    return run_in_group(argv, environment(nullptr), dir_ + "/ctl.out", "rabbitmqctl " + args.at(0) + " on " + node.name);
}

void RabbitCluster::kill_node(int i) {
    Node& node = nodes_.at(static_cast<std::size_t>(i));
    kill_group(node.pid);
    while (port_accepts(node.mqtt_port)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

void RabbitCluster::start_node(int i) {
    Node& node = nodes_.at(static_cast<std::size_t>(i));
    if (node.pid > 0) return;
    spawn_node(node);
    wait_node_up(node);
}

}  // namespace nclink::test
