// The fleet benchmark: N simulated machines x 10 points sampled every 100 ms
// and uploaded every second (bench/fleet-machine.json; --points and
// --interval change both, see below), in ONE gateway
// process (nclink-sim --machines N), one mosquitto with the settings nclink
// ships, nclink-agent, and an application subscribed to every channel.
// Reports, per N: points/s delivered against produced, gateway and agent
// CPU % and RSS, time until every machine is online, Discovery time, Query
// p50/p99 to a random machine under that load, and the time for every
// machine to come back online after a broker restart. The measured window
// (points, CPU, Query and its floor) starts once every machine's
// registration was answered, or 120 s after the start: it is the load's
// steady state. How long the start took is the columns "all online" and
// "all registered"; a window during it measured the start's backlog
// (docs/performance.md).
//
// The floor of the queries, in the same run: a bare paho echo (its own
// process, answering from inside paho's callback with an answer of the same
// shape and size) queried by the same application through the same broker,
// alternating one by one with the queries to the machines. On a small box
// the broker, the agent, the application and the gateway share the CPUs; the
// floor shows what a round trip costs there without nclink's gateway in it.
//
//   build/bench/bench_fleet [--machines 100,300,1000] [--seconds 30] [--queries 1000] [--config FILE]
//                           [--points 10] [--interval 100] [--gateways 1]
//
// --points N: points per machine in its one channel (the model's first 10,
// then axes added to the model, four points each); --interval MS: how often
// they are sampled (uploaded every second, or every interval if longer).
// Other than 10 x 100 ms the machines run a model written to /tmp from
// bench/fleet-machine.json. The threads and RSS columns are the gateway's
// at the end of the measured window.
//
// --gateways K: the machines split over K gateway processes (GUID prefixes
// fleet0-, fleet1-, ...); the gateway columns are then their sums. One
// libmosquitto client takes three file descriptors (its socket and a socket
// pair that wakes its loop), so a process whose hard limit is 20,000 serves at
// most about 6,600 machines (docs/gateway.md).
//
// --cluster rabbitmq|ejabberd: a 3-node RabbitMQ cluster on loopback
// (Debian's rabbitmq-server, tests/support/rabbitmq_cluster.hpp) or a
// 3-node ejabberd one (Debian's ejabberd and its mod_mqtt,
// tests/support/ejabberd_cluster.hpp; every program logs in, as ejabberd
// wants) instead of the one mosquitto: one gateway process per node (at
// least), each with the other nodes as failover list, the agent on node 3
// (MQTT 3.1.1, plain subscriptions: docs/scaling.md), the application on
// node 2, the floor's echo on node 1. The broker columns are then the
// cluster's (every beam.smp process); no broker restart.
//
// --config FILE: adapter settings every machine of the gateway shares
// (nclink-sim --config), e.g. {"heap_keep_bytes": 0} to measure a setting.
//
// A program, not a test: the figures depend on the box (docs/performance.md).
#include <nclink/client.hpp>
#include <nclink/dtu.hpp>
#include <nclink/json.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/topics.hpp>

#include "bench_util.hpp"
#include "paho_echo.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/ejabberd_cluster.hpp"
#include "support/rabbitmq_cluster.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

using namespace nclink;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

// The floor's device: no machine of the fleet, answered by the echo.
const char* kEchoDev = "fleet-echo";

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

pid_t spawn(const std::vector<std::string>& args, const std::string& log) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t pid = -1;
    if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&actions);
    return pid;
}

void finish(pid_t pid) {
    if (pid <= 0) return;
    ::kill(pid, SIGTERM);
    int status = 0;
    for (int i = 0; i < 300; ++i) {
        if (::waitpid(pid, &status, WNOHANG) == pid) return;
        std::this_thread::sleep_for(100ms);
    }
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
}

// CPU seconds (user + system) and resident MB of a process.
struct Usage {
    double cpu_s = 0;
    double rss_mb = 0;
    int threads = 0;
};
Usage usage(pid_t pid) {
    Usage u;
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
    const auto close = text.rfind(')');
    if (close != std::string::npos) {
        std::istringstream fields(text.substr(close + 2));
        std::vector<std::string> f;
        for (std::string s; fields >> s;) f.push_back(s);
        // fields after the name: state(0) ... utime(11) stime(12) ... num_threads(17)
        if (f.size() > 17) {
            const double tick = static_cast<double>(::sysconf(_SC_CLK_TCK));
            u.cpu_s = (std::stod(f[11]) + std::stod(f[12])) / tick;
            u.threads = std::stoi(f[17]);
        }
    }
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("VmRSS:", 0) == 0) u.rss_mb = std::stod(line.substr(6)) / 1024.0;
    return u;
}

// The summed usage of every process whose name is `comm` (a cluster's nodes).
Usage usage_named(const std::string& comm) {
    Usage sum;
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator("/proc", error)) {
        const std::string pid = entry.path().filename().string();
        if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
        std::ifstream name(entry.path() / "comm");
        std::string got;
        if (!std::getline(name, got) || got != comm) continue;
        const Usage u = usage(static_cast<pid_t>(std::stol(pid)));
        sum.cpu_s += u.cpu_s;
        sum.rss_mb += u.rss_mb;
        sum.threads += u.threads;
    }
    return sum;
}

// One mosquitto, or a 3-node cluster (--cluster rabbitmq|ejabberd).
struct Brokers {
    std::optional<nclink::test::MosquittoBroker> mosquitto;
    std::unique_ptr<nclink::test::RabbitCluster> rabbit;
    std::unique_ptr<nclink::test::EjabberdCluster> ejabberd;
    explicit Brokers(const std::string& cluster) {
        if (cluster == "rabbitmq") rabbit = std::make_unique<nclink::test::RabbitCluster>(3);
        else if (cluster == "ejabberd") ejabberd = std::make_unique<nclink::test::EjabberdCluster>(3);
        else mosquitto.emplace();
    }
    int size() const { return rabbit ? rabbit->size() : ejabberd ? ejabberd->size() : 1; }
    int port(int i) const {
        return rabbit ? rabbit->mqtt_port(i % size()) : ejabberd ? ejabberd->mqtt_port(i % size()) : mosquitto->port();
    }
    std::string url(int i) const { return "tcp://127.0.0.1:" + std::to_string(port(i)); }
    Usage usage() const { return mosquitto ? ::usage(mosquitto->pid()) : usage_named("beam.smp"); }
    // The login every program uses: ejabberd's mod_mqtt refuses a CONNECT
    // without a password; the others take anonymous ones.
    std::string username() const { return ejabberd ? nclink::test::EjabberdCluster::username() : ""; }
    std::string password() const { return ejabberd ? nclink::test::EjabberdCluster::password() : ""; }
    // The broker section of a program's configuration: the login.
    Json login() const {
        Json section = Json::object();
        if (!username().empty()) section = Json{{"username", username()}, {"password", password()}};
        return section;
    }
};

// The application's view of every Sample and Notify/State on the broker.
struct Watcher {
    std::atomic<std::uint64_t> points{0}, samples{0}, register_requests{0};
    std::mutex mutex;
    std::map<std::string, std::pair<std::string, Clock::time_point>> state;  // tid -> last state, when
    std::map<std::string, Clock::time_point> registered;                     // tid -> first Register/Response OK
    std::unique_ptr<Transport> transport;

    explicit Watcher(const std::string& url, const std::string& username, const std::string& password) {
        MqttOptions o;
        o.broker_url = url;
        o.client_id = "bench-fleet-watcher";
        o.username = username;
        o.password = password;
        transport = make_mqtt_transport(o).value();
        transport->set_message_handler([this](const Message& m) {
            const auto topic = parse_topic(m.topic);
            if (!topic) return;
            if (topic->kind == TopicKind::sample) {
                auto dtu = decode<SampleDtu>(m.payload);
                if (!dtu) return;
                std::uint64_t n = 0;
                for (const auto& column : dtu->data) n += column.is_array() ? column.size() : 1;
                points += n;
                ++samples;
            } else if (topic->kind == TopicKind::notify_state && !m.payload.empty()) {
                auto n = decode<NotifyState>(m.payload);
                if (!n) return;
                std::lock_guard<std::mutex> lock(mutex);
                state[topic->dev] = {n->state, Clock::now()};
            } else if (topic->kind == TopicKind::register_request) {
                ++register_requests;
            } else if (topic->kind == TopicKind::register_response) {
                auto r = decode<RegisterResponse>(m.payload);
                if (!r || !r->status.ok) return;
                std::lock_guard<std::mutex> lock(mutex);
                registered.emplace(topic->dev, Clock::now());
            }
        });
        (void)transport->subscribe(
            {"Sample/#", topics::notify_state("+"), topics::register_request(), topics::register_response("+")}, 0);
        (void)transport->start();
    }
    ~Watcher() { transport->stop(0ms); }

    // Machines whose last state is online and came after `since`.
    std::size_t online_since(const std::string& prefix, Clock::time_point since) {
        std::lock_guard<std::mutex> lock(mutex);
        std::size_t n = 0;
        for (const auto& [tid, s] : state)
            if (tid.rfind(prefix, 0) == 0 && s.first == "online" && s.second >= since) ++n;
        return n;
    }
    // When the last of `machines` got its first Register/Response OK, in
    // seconds after `since`; -1 while some have none.
    double all_registered(const std::string& prefix, std::size_t machines, Clock::time_point since) {
        std::lock_guard<std::mutex> lock(mutex);
        std::size_t n = 0;
        Clock::time_point last = since;
        for (const auto& [tid, when] : registered)
            if (tid.rfind(prefix, 0) == 0) ++n, last = std::max(last, when);
        return n < machines ? -1 : std::chrono::duration<double>(last - since).count();
    }
};

struct Row {
    std::size_t machines = 0;
    double produced = 0, delivered = 0;
    Usage gw, agent;
    double gw_cpu = 0, agent_cpu = 0;
    double all_online_s = 0, all_registered_s = 0, registers_per_machine = 0, discovery_ms = 0, query_p50 = 0, query_p99 = 0,
           restart_s = 0;
    double floor_p50 = 0, floor_p99 = 0;
    double broker_cpu = 0;
    std::size_t discovered = 0, query_failures = 0;
};

// bench/fleet-machine.json with `points` points sampled every `interval_ms`
// in its channel; the model's own path when that is what it has already.
std::string fleet_model(const std::string& src, std::size_t points, int interval_ms) {
    const std::string original = src + "/bench/fleet-machine.json";
    if (points == 10 && interval_ms == 100) return original;
    std::ifstream in(original);
    Json model = Json::parse(in);
    Json& device = model["devices"][0];
    Json* channel = nullptr;
    for (auto& config : device["configs"])
        if (config.value("type", "") == "SAMPLE_CHANNEL") channel = &config;
    Json ids = Json::array();
    for (const auto& id : (*channel)["ids"]) {
        if (ids.size() == points) break;
        ids.push_back(id);
    }
    // Axes of four points each until there are enough.
    for (std::size_t axis = 0; ids.size() < points; ++axis) {
        const std::string name = fmt::format("b{}", axis);
        Json items = Json::array();
        for (const auto& [type, suffix] : std::vector<std::pair<std::string, std::string>>{
                 {"POSITION", "position"}, {"SPEED", "speed"}, {"AXIS_LOAD", "load"}, {"CURRENT", "current"}}) {
            const std::string id = name + "_" + suffix;
            items.push_back(Json{{"id", id}, {"name", id}, {"type", type}});
            if (ids.size() < points) ids.push_back(Json{{"id", id}});
        }
        device["components"].push_back(
            Json{{"id", "axis_" + name}, {"name", "axis " + name}, {"type", "AXIS"}, {"number", name}, {"dataItems", items}});
    }
    (*channel)["ids"] = ids;
    (*channel)["sampleInterval"] = interval_ms;
    (*channel)["uploadInterval"] = std::max(1000, interval_ms);
    (*channel)["description"] = fmt::format("{} points every {} ms (bench_fleet)", points, interval_ms);
    const std::string path = fmt::format("/tmp/bench_fleet_model_{}x{}ms.json", points, interval_ms);
    std::ofstream(path) << model.dump(1);
    return path;
}

Row run(std::size_t machines, double seconds, std::size_t queries, const std::string& bin, const std::string& src,
        const std::string& config, std::size_t points, int interval_ms, std::size_t gateways, const std::string& cluster_kind) {
    Row row;
    row.machines = machines;
    Brokers broker(cluster_kind);
    const bool cluster = !broker.mosquitto;
    // Where each program goes: all on the one mosquitto, or the agent on
    // node 3, the application on node 2, the echo on node 1.
    const std::string url = broker.url(1);
    const std::string prefix = "fleet";
    std::vector<std::string> agent_args{bin + "/bin/nclink-agent", "--broker", broker.url(2), "--log-level", "warn"};
    if (cluster) {
        const std::string path = "/tmp/bench_fleet_agent.json";
        Json broker_section = broker.login();
        broker_section["mqtt_version"] = 4;
        std::ofstream(path) << Json{{"share_group", ""}, {"broker", broker_section}}.dump();
        agent_args.insert(agent_args.end(), {"--config", path});
    }
    const pid_t agent = spawn(agent_args, "/tmp/bench_fleet_agent.log");
    Watcher watcher(url, broker.username(), broker.password());
    std::this_thread::sleep_for(500ms);
    const auto t0 = Clock::now();
    // The machines of each gateway process and their GUIDs (nclink-sim
    // --machines names them <prefix>-0000, -0001, ...).
    std::vector<pid_t> gws;
    std::vector<std::string> devs;
    const std::string model = fleet_model(src, points, interval_ms);
    for (std::size_t g = 0; g < gateways; ++g) {
        const std::size_t count = machines / gateways + (g < machines % gateways ? 1 : 0);
        const std::string guid = gateways == 1 ? prefix : fmt::format("{}{}", prefix, g);
        for (std::size_t i = 0; i < count; ++i) devs.push_back(fmt::format("{}-{:04d}", guid, i));
        const int node = static_cast<int>(g);
        std::vector<std::string> gateway{bin + "/bin/nclink-sim",
                                         "--machines",
                                         std::to_string(count),
                                         "--model",
                                         model,
                                         "--guid",
                                         guid,
                                         "--broker",
                                         broker.url(node),
                                         "--log-level",
                                         "warn"};
        if (cluster) {
            // The user's settings, and the other nodes as failover list.
            Json settings = Json::object();
            if (!config.empty()) settings = Json::parse(std::ifstream(config));
            settings["broker"].update(broker.login());
            settings["broker"]["failover"] = Json::array();
            for (int k = 1; k < broker.size(); ++k) settings["broker"]["failover"].push_back(broker.url(node + k));
            const std::string path = fmt::format("/tmp/bench_fleet_gateway{}.json", g);
            std::ofstream(path) << settings.dump();
            gateway.insert(gateway.end(), {"--config", path});
        } else if (!config.empty()) {
            gateway.insert(gateway.end(), {"--config", config});
        }
        gws.push_back(spawn(gateway, fmt::format("/tmp/bench_fleet_gateway{}.log", gateways == 1 ? "" : std::to_string(g))));
    }
    const auto gateway_usage = [&gws] {
        Usage sum;
        for (const pid_t gw : gws) {
            const Usage u = usage(gw);
            sum.cpu_s += u.cpu_s;
            sum.rss_mb += u.rss_mb;
            sum.threads += u.threads;
        }
        return sum;
    };
    while (watcher.online_since(prefix, t0) < machines && seconds_since(t0) < 600) std::this_thread::sleep_for(50ms);
    row.all_online_s = seconds_since(t0);

    ClientOptions co;
    co.ex_cid = "bench-fleet-app";
    co.default_timeout = 10s;
    MqttOptions mo;
    mo.broker_url = url;
    mo.client_id = "bench-fleet-app";
    mo.username = broker.username();
    mo.password = broker.password();
    auto app = Client::create(mo, co).value();
    (void)app->start();
    (void)app->wait_connected(10s);
    std::this_thread::sleep_for(2s);  // let the upload rhythm settle

    // Discovery of every machine, the median of 5.
    std::vector<double> discovery;
    for (int i = 0; i < 5; ++i) {
        const auto t = Clock::now();
        auto list = app->discover();
        discovery.push_back(seconds_since(t) * 1000);
        if (list) row.discovered = list->size();
        else
            std::fprintf(stderr, "bench_fleet: Discovery %d of 5 failed after %.0f ms: %s\n", i + 1, discovery.back(),
                         list.error().message.c_str());
    }
    row.discovery_ms = bench::median(discovery);

    // The floor's echo, answering as soon as it has subscribed.
    const pid_t echo =
        spawn({"/proc/self/exe", "--echo-child", std::to_string(broker.port(0)), broker.username(), broker.password()},
              "/tmp/bench_fleet_echo.log");
    RequestOptions quick;
    quick.timeout = 1s;
    const auto ask_echo = [&app, &quick] {
        auto values = app->query(kEchoDev, {QueryItem{"spindle_speed", std::nullopt}}, quick);
        return values && !values->empty() && (*values)[0].status.ok;
    };
    for (const auto e0 = Clock::now(); !ask_echo() && seconds_since(e0) < 10;) std::this_thread::sleep_for(100ms);
    while (watcher.all_registered(prefix, machines, t0) < 0 && seconds_since(t0) < 120) std::this_thread::sleep_for(100ms);

    // The measured window: points delivered, CPU, queries to random machines
    // and, after each, one to the floor's echo.
    const Usage gw0 = gateway_usage(), agent0 = usage(agent), broker0 = broker.usage();
    const std::uint64_t points0 = watcher.points;
    const auto w0 = Clock::now();
    std::mt19937 random(7);
    std::vector<double> query_ms, floor_ms;
    const auto pause = std::chrono::duration<double>(seconds / static_cast<double>(queries + 1));
    while (seconds_since(w0) < seconds) {
        const std::string& dev = devs[random() % devs.size()];
        const auto t = Clock::now();
        auto values = app->query(dev, {QueryItem{"spindle_speed", std::nullopt}});
        if (values && !values->empty() && (*values)[0].status.ok) query_ms.push_back(seconds_since(t) * 1000);
        else ++row.query_failures;
        // The same pause before either: a request after an idle gap costs
        // more than one right after another (caches go cold), so the echo
        // must not ride on the path the machine's query has just warmed.
        std::this_thread::sleep_for(pause / 2);
        const auto f = Clock::now();
        if (ask_echo()) floor_ms.push_back(seconds_since(f) * 1000);
        std::this_thread::sleep_for(pause / 2);
    }
    const double window = seconds_since(w0);
    const std::uint64_t points1 = watcher.points;
    row.gw = gateway_usage();
    row.agent = usage(agent);
    row.broker_cpu = (broker.usage().cpu_s - broker0.cpu_s) / window * 100;
    row.gw_cpu = (row.gw.cpu_s - gw0.cpu_s) / window * 100;
    row.agent_cpu = (row.agent.cpu_s - agent0.cpu_s) / window * 100;
    row.delivered = static_cast<double>(points1 - points0) / window;
    row.produced = static_cast<double>(machines) * static_cast<double>(points) * 1000.0 / interval_ms;
    row.query_p50 = bench::percentile(query_ms, 50);
    row.query_p99 = bench::percentile(query_ms, 99);
    row.floor_p50 = bench::percentile(floor_ms, 50);
    row.floor_p99 = bench::percentile(floor_ms, 99);
    finish(echo);
    // Registration as the agent answered it, before the restart below: the
    // machines serve without it, but each asks again when no answer comes
    // within register_timeout_ms, and those repeats are start-up load.
    row.all_registered_s = watcher.all_registered(prefix, machines, t0);
    row.registers_per_machine = static_cast<double>(watcher.register_requests) / static_cast<double>(machines);

    // Broker restart: until every machine has announced itself online again
    // (a cluster's node loss is the cluster tests' business: docs/scaling.md).
    if (broker.mosquitto) {
        const auto r0 = Clock::now();
        broker.mosquitto->restart();
        while (watcher.online_since(prefix, r0) < machines && seconds_since(r0) < 600) std::this_thread::sleep_for(50ms);
        row.restart_s = seconds_since(r0);
    } else {
        row.restart_s = -1;
    }

    app->stop();
    for (const pid_t gw : gws) finish(gw);
    finish(agent);
    return row;
}

}  // namespace

// The floor: answers Query/Request/fleet-echo/{ex} with the answer a
// machine gives to the bench's query (same shape and size), the request's
// @id mirrored. Runs until killed.
int echo_child(int port, const std::string& username, const std::string& password) {
    const std::string request_topic = topics::query_request(kEchoDev, "+");
    const std::string request_prefix = request_topic.substr(0, request_topic.size() - 1);
    const std::string response_prefix = topics::query_response(kEchoDev) + "/";
    bench::PahoEcho echo(
        "tcp://127.0.0.1:" + std::to_string(port), "bench-fleet-echo", request_topic, port,
        [&](const mqtt::message& request, mqtt::async_client& client) {
            static const std::string key = "\"@id\":\"";
            const std::string& payload = request.get_payload();
            const auto at = payload.find(key);
            if (at == std::string::npos) return;
            const auto from = at + key.size();
            const auto to = payload.find('"', from);
            if (to == std::string::npos) return;
            std::string reply = "{\"@id\":\"";
            reply.append(payload, from, to - from)
                .append(
                    "\",\"guid\":\"fleet-echo\",\"values\":[{\"code\":\"OK\",\"id\":"
                    "\"spindle_speed\",\"values\":[2133]}]}");
            const std::string& topic = request.get_topic();
            client.publish(response_prefix + topic.substr(request_prefix.size()), reply.data(), reply.size(), 1, false);
        },
        username, password);
    for (;;) ::pause();
}

int main(int argc, char** argv) {
    if (argc >= 5 && std::string(argv[1]) == "--echo-child") return echo_child(std::atoi(argv[2]), argv[3], argv[4]);
    std::vector<std::size_t> sizes = {100, 300, 1000};
    double seconds = 30;
    std::size_t queries = 1000;  // the p99 of 200 would be their second slowest
    std::string config;
    std::size_t points = 10;
    int interval_ms = 100;
    std::size_t gateways = 1;
    std::string cluster;  // "": one mosquitto
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string arg = argv[i], value = argv[i + 1];
        if (arg == "--machines") {
            sizes.clear();
            std::stringstream list(value);
            for (std::string n; std::getline(list, n, ',');) sizes.push_back(std::stoul(n));
        } else if (arg == "--seconds") {
            seconds = std::stod(value);
        } else if (arg == "--queries") {
            queries = std::stoul(value);
        } else if (arg == "--config") {
            config = value;
        } else if (arg == "--points") {
            points = std::max<std::size_t>(1, std::stoul(value));
        } else if (arg == "--interval") {
            interval_ms = std::max(1, std::stoi(value));
        } else if (arg == "--gateways") {
            gateways = std::max<std::size_t>(1, std::stoul(value));
        } else if (arg == "--cluster") {
            if (value != "rabbitmq" && value != "ejabberd") {
                std::fprintf(stderr, "bench_fleet: --cluster takes rabbitmq or ejabberd\n");
                return 2;
            }
            const std::string why = value == "rabbitmq" ? nclink::test::RabbitCluster::unavailable_reason()
                                                        : nclink::test::EjabberdCluster::unavailable_reason();
            if (!why.empty()) {
                std::fprintf(stderr, "bench_fleet: %s\n", why.c_str());
                return 2;
            }
            cluster = value;
        }
    }
    if (!cluster.empty()) gateways = std::max<std::size_t>(gateways, 3);  // a gateway process on each node
    std::printf("%zu point(s) per machine every %d ms", points, interval_ms);
    if (!cluster.empty()) std::printf("; a 3-node %s cluster", cluster == "rabbitmq" ? "RabbitMQ" : "ejabberd");
    if (gateways > 1) std::printf("; the machines split over %zu gateway processes (their sums below)", gateways);
    std::printf("\n\n");
    std::printf(
        "| machines | points/s produced | delivered | gateway CPU %% | gateway RSS MB (per machine) | threads "
        "| agent CPU %% | agent RSS MB | all online s | all registered s (Register/Request per machine) | Discovery ms (listed) "
        "| Query p50 / p99 ms (failed) "
        "| floor p50 / p99 ms | online again after broker restart s | broker CPU %% |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (std::size_t n : sizes) {
        const Row r =
            run(n, seconds, queries, NCLINK_BINARY_DIR, NCLINK_SOURCE_DIR, config, points, interval_ms, gateways, cluster);
        std::printf(
            "| %zu | %.0f | %.0f (%.1f%%) | %.0f | %.0f (%.2f) | %d | %.0f | %.0f | %.1f | %.1f (%.2f) | %.1f (%zu) | %.2f / "
            "%.2f (%zu) | %.2f "
            "/ %.2f | %s | %.0f |\n",
            r.machines, r.produced, r.delivered, 100 * r.delivered / r.produced, r.gw_cpu, r.gw.rss_mb,
            r.gw.rss_mb / static_cast<double>(r.machines), r.gw.threads, r.agent_cpu, r.agent.rss_mb, r.all_online_s,
            r.all_registered_s, r.registers_per_machine, r.discovery_ms, r.discovered, r.query_p50, r.query_p99, r.query_failures,
            r.floor_p50, r.floor_p99, r.restart_s < 0 ? "-" : fmt::format("{:.1f}", r.restart_s).c_str(), r.broker_cpu);
        std::fflush(stdout);
    }
    return 0;
}
