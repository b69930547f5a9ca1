#include "support/ejabberd_cluster.hpp"

#include "support/mosquitto_broker.hpp"  // free_loopback_port(), port_accepts()
#include "support/process_group.hpp"

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace nclink::test {
namespace {

// Debian's control script. Run as root it would switch to the ejabberd user
// (su), which resets $HOME (where the cookie is) and cannot write to the
// scratch directory; the ejabberdctl.cfg it sources keeps the current user.
constexpr const char* ctl_script = "/usr/sbin/ejabberdctl";
constexpr const char* epmd_binary = "/usr/bin/epmd";

// What ejabberdctl reads from the environment besides its options: none of
// the caller's may point the nodes elsewhere.
bool foreign_setting(const std::string& entry) {
    for (const char* prefix :
         {"ERL_", "ERLANG_", "EJABBERD", "CONTRIB_MODULES", "HOME=", "SPOOL_DIR=", "LOGS_DIR=", "CONFIG_DIR=", "VMARGS=",
          "EXEC_CMD=", "INSTALLUSER=", "FIREWALL_WINDOW=", "INET_DIST_INTERFACE=", "NO_TIMEOUT=", "SCRIPT="})
        if (entry.rfind(prefix, 0) == 0) return true;
    return false;
}

}  // namespace

std::string EjabberdCluster::unavailable_reason() {
    for (const char* path : {ctl_script, epmd_binary})
        if (::access(path, X_OK) != 0)
            return std::string("ejabberd is not installed (") + path +
                   " missing): the ejabberd cluster tests are skipped; NCLINK_WITH_EJABBERD=1 tools/install-deps.sh installs it";
    return "";
}

EjabberdCluster::EjabberdCluster(int nodes) {
    const std::string reason = unavailable_reason();
    if (!reason.empty()) throw std::runtime_error(reason);
    end_orphaned_clusters("nclink-ejabberd-", "ejabberd");
    dir_ = make_cluster_dir("nclink-ejabberd-", "NCLINKEJ", free_loopback_port());
    try {
        // ejabberdctl's own directory for the commands: no distribution
        // port (a command's VM listens on a port of its own), no node
        // configuration; the host table every VM reads (not /etc/ejabberd's).
        std::filesystem::create_directories(dir_ + "/ctl");
        std::ofstream(dir_ + "/ctl/ejabberdctl.cfg") << "EXEC_CMD=as_current_user\n";
        std::ofstream(dir_ + "/ctl/ejabberd.yml") << "";
        std::ofstream(dir_ + "/ctl/inetrc") << "{lookup,[\"file\",\"native\"]}.\n{host,{127,0,0,1},[\"localhost\"]}.\n";

        // An epmd of its own, on loopback only: node names need be unique
        // only within this cluster, and nothing outside it sees them.
        epmd_port_ = free_loopback_port();
        epmd_pid_ = spawn_in_group({epmd_binary, "-port", std::to_string(epmd_port_), "-address", "127.0.0.1"}, environment(),
                                   dir_ + "/epmd.out");
        std::ofstream(dir_ + "/groups", std::ios::app) << epmd_pid_ << "\n";
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (!port_accepts(epmd_port_)) {
            if (std::chrono::steady_clock::now() > deadline) throw std::runtime_error("epmd did not start");
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }

        for (int i = 0; i < nodes; ++i) {
            Node node;
            // Not the RabbitMQ cluster's names: ejabberdctl looks for a
            // running VM by its node name before it starts one.
            node.name = "nclinkej" + std::to_string(i + 1) + "@localhost";
            node.dir = dir_ + "/node" + std::to_string(i + 1);
            node.mqtt_port = free_loopback_port();
            node.dist_port = free_loopback_port();
            std::filesystem::create_directories(node.dir + "/spool");
            std::filesystem::create_directories(node.dir + "/log");
            nodes_.push_back(node);
            write_node_config(node);
        }
        // All nodes boot at once, then 2..N join 1 one after the other: a
        // join stops the joining node's ejabberd, copies the tables and
        // starts it again; join_cluster returns when it is back.
        for (auto& node : nodes_) spawn_node(node);
        for (auto& node : nodes_) boot_node(node);
        for (int i = 1; i < nodes; ++i) {
            ctl_reaching_node(i, {"join_cluster", nodes_[0].name});
            wait_node_up(nodes_[static_cast<std::size_t>(i)]);
        }
        if (nodes > 1) {
            const std::string members = ctl(0, {"list_cluster"});
            for (const auto& node : nodes_)
                if (members.find(node.name) == std::string::npos)
                    throw std::runtime_error("ejabberd node " + node.name + " is not in the cluster after join_cluster:\n" +
                                             members);
        }
    } catch (...) {
        for (auto& node : nodes_) kill_group(node.pid);
        kill_group(epmd_pid_);
        std::error_code ignored;
        std::filesystem::remove_all(dir_, ignored);
        throw;
    }
}

EjabberdCluster::~EjabberdCluster() {
    // The data is thrown away with the directory: no clean shutdown needed.
    for (auto& node : nodes_) kill_group(node.pid);
    kill_group(epmd_pid_);
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
}

void EjabberdCluster::write_node_config(const Node& node) const {
    // ejabberd's configuration: one virtual host, the MQTT listener on
    // loopback, mod_mqtt with its defaults (Mnesia: retained messages on
    // disc, sessions and subscriptions in RAM tables shared by the cluster)
    // and anonymous login (any user name with a non-empty password). Nothing
    // XMPP listens.
    std::ofstream yml(node.dir + "/ejabberd.yml");
    yml << "hosts:\n"
        << "  - localhost\n"
        << "loglevel: info\n"
        << "log_rotate_count: 0\n"
        << "auth_method: [anonymous]\n"
        << "anonymous_protocol: login_anon\n"
        << "listen:\n"
        << "  -\n"
        << "    port: " << node.mqtt_port << "\n"
        << "    ip: \"127.0.0.1\"\n"
        << "    module: mod_mqtt\n"
        << "    backlog: 1000\n"
        << "modules:\n"
        << "  mod_mqtt: {}\n";
    // ejabberdctl.cfg is sourced by the script: the node's name, its
    // distribution listener on loopback and on its own port, the current user.
    std::ofstream cfg(node.dir + "/ejabberdctl.cfg");
    cfg << "EXEC_CMD=as_current_user\n"
        << "ERLANG_NODE=" << node.name << "\n"
        << "ERL_OPTIONS=\"-kernel inet_dist_use_interface {127,0,0,1} -kernel inet_dist_listen_min " << node.dist_port
        << " -kernel inet_dist_listen_max " << node.dist_port << "\"\n";
    std::ofstream(node.dir + "/inetrc") << "{lookup,[\"file\",\"native\"]}.\n{host,{127,0,0,1},[\"localhost\"]}.\n";
}

std::vector<std::string> EjabberdCluster::environment() const {
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e)
        if (!foreign_setting(*e)) env.emplace_back(*e);
    env.push_back("HOME=" + dir_);
    env.push_back("ERL_EPMD_PORT=" + std::to_string(epmd_port_));
    env.push_back("ERL_EPMD_ADDRESS=127.0.0.1");
    return env;
}

void EjabberdCluster::spawn_node(Node& node) {
    node.pid = spawn_in_group(
        {ctl_script, "--config-dir", node.dir, "--spool", node.dir + "/spool", "--logs", node.dir + "/log", "foreground"},
        environment(), node.dir + "/out");
    std::ofstream(dir_ + "/groups", std::ios::app) << node.pid << "\n";
}

// A port found free can be taken before the node binds it (by another test,
// or as an outgoing connection's ephemeral port: the VM then stops with
// eaddrinuse, or the listener fails). Such a node boots again on new ports,
// at most twice more.
void EjabberdCluster::boot_node(Node& node) {
    for (int attempt = 1;; ++attempt) {
        try {
            wait_node_up(node);
            return;
        } catch (const std::runtime_error& e) {
            const std::string why = e.what();
            const bool port_taken = why.find("eaddrinuse") != std::string::npos || why.find("already") != std::string::npos;
            if (!port_taken || attempt == 3) throw;
        }
        kill_group(node.pid);
        node.mqtt_port = free_loopback_port();
        node.dist_port = free_loopback_port();
        write_node_config(node);
        spawn_node(node);
    }
}

void EjabberdCluster::wait_node_up(const Node& node) const {
    // The MQTT listener opens once ejabberd has started.
    wait_until_up(
        node.pid, [&] { return port_accepts(node.mqtt_port); }, "ejabberd node " + node.name, node.dir + "/out");
}

std::string EjabberdCluster::ctl(int i, const std::vector<std::string>& args) const {
    const Node& node = nodes_.at(static_cast<std::size_t>(i));
    std::vector<std::string> argv{ctl_script, "--config-dir", dir_ + "/ctl", "--node", node.name};
    argv.insert(argv.end(), args.begin(), args.end());
    return run_in_group(argv, environment(), dir_ + "/ctl.out", "ejabberdctl " + args.at(0) + " on " + node.name);
}

std::string EjabberdCluster::ctl_reaching_node(int i, const std::vector<std::string>& args) const {
    // A node whose MQTT listener is open may not yet answer ejabberdctl's
    // RPC on a busy machine ("Failed RPC connection to the node ...:
    // nodedown"): nothing was done then, so the command is given again.
    for (int attempt = 1;; ++attempt) {
        try {
            return ctl(i, args);
        } catch (const std::runtime_error& e) {
            const std::string why = e.what();
            if (attempt == 5 || why.find("nodedown") == std::string::npos) throw;
        }
        std::this_thread::sleep_for(std::chrono::seconds(1));
    }
}

void EjabberdCluster::kill_node(int i) {
    Node& node = nodes_.at(static_cast<std::size_t>(i));
    kill_group(node.pid);
    while (port_accepts(node.mqtt_port)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

void EjabberdCluster::start_node(int i) {
    Node& node = nodes_.at(static_cast<std::size_t>(i));
    if (node.pid > 0) return;
    spawn_node(node);
    wait_node_up(node);
}

long EjabberdCluster::resident_kib(int i) const {
    const Node& node = nodes_.at(static_cast<std::size_t>(i));
    if (node.pid <= 0) return 0;
    // The VM is the process of the node's group named beam.smp.
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator("/proc", error)) {
        const std::string pid = entry.path().filename().string();
        if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
        const std::string stat = whole_file("/proc/" + pid + "/stat");
        const auto open = stat.find('('), close = stat.rfind(')');
        if (open == std::string::npos || close == std::string::npos) continue;
        if (stat.substr(open + 1, close - open - 1) != "beam.smp") continue;
        std::istringstream rest(stat.substr(close + 2));
        std::string state;
        long parent = 0, group = 0;
        rest >> state >> parent >> group;
        if (group != node.pid) continue;
        std::istringstream status(whole_file("/proc/" + pid + "/status"));
        for (std::string line; std::getline(status, line);)
            if (line.rfind("VmRSS:", 0) == 0) return std::atol(line.c_str() + 6);
    }
    return 0;
}

}  // namespace nclink::test
