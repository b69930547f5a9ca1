// Shared plumbing of the device subcommands; see cli_device.hpp.
#include "cli_device.hpp"

#include <nclink/mqtt_transport.hpp>

#include <nclink/log.hpp>

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <stdexcept>
#include <thread>

namespace nclink::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;  // the one global a signal handler can touch

extern "C" void on_interrupt(int) { g_interrupted = 1; }

double number_member(const Json& object, const char* key) {
    const auto it = object.find(key);
    if (it == object.end()) return 0;
    if (it->is_number()) return it->get<double>();
    if (it->is_string()) {
        try {
            return std::stod(it->get<std::string>());
        } catch (...) {
            return 0;
        }
    }
    return 0;
}

void collect_channels(const Json& node, std::vector<ChannelInfo>& out, int depth) {
    if (depth > 64) return;
    if (node.is_array()) {
        for (const auto& child : node) collect_channels(child, out, depth + 1);
        return;
    }
    if (!node.is_object()) return;
    const std::string type = string_member(node, {"type"});
    if (type == "SAMPLE_CHANNEL" || type == "sample_channel") {
        ChannelInfo channel;
        channel.id = string_member(node, {"id"});
        channel.name = string_member(node, {"name"});
        channel.sample_interval = number_member(node, "sampleInterval");
        channel.upload_interval = number_member(node, "uploadInterval");
        if (const auto ids = node.find("ids"); ids != node.end() && ids->is_array())
            for (const auto& point : *ids) {
                if (point.is_string()) channel.points.push_back(point.get<std::string>());
                else if (point.is_object()) channel.points.push_back(string_member(point, {"id"}));
            }
        out.push_back(std::move(channel));
        return;
    }
    for (const auto& [key, child] : node.items())
        if (child.is_structured()) collect_channels(child, out, depth + 1);
}

}  // namespace

bool parse_device_command(const Args& args, const OptionSpec& spec, const char* usage, CliOptions& out) {
    out = parse_cli_options(args, spec);
    if (out.help) {
        std::fputs(usage, stdout);
        return true;
    }
    check_terminal_id("--device", out.device);
    if (out.client_id.empty()) out.client_id = "nclink-cli-" + std::to_string(::getpid());
    check_terminal_id("--client-id", out.client_id);
    return false;
}

static std::string broker_password(const CliOptions& options) {
    if (options.password_file.empty()) {
        const char* env = std::getenv("NCLINK_PASSWORD");
        return env ? env : "";
    }
    std::ifstream in(options.password_file);
    std::string line;
    if (!in || !std::getline(in, line)) throw std::runtime_error("cannot read the password file " + options.password_file);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
}

std::unique_ptr<Client> connect_client(const CliOptions& options, const std::function<void(Client&)>& before_start) {
    MqttOptions mqtt;
    mqtt.broker_url = options.broker;
    mqtt.failover_urls = options.failover;
    mqtt.client_id = options.client_id;
    mqtt.clean_session = !options.persistent;
    mqtt.connect_timeout = options.timeout;
    mqtt.username = options.username;
    mqtt.password = broker_password(options);
    if (!options.ca_file.empty() || !options.cert_file.empty() || !options.key_file.empty() || options.insecure) {
        MqttTlsOptions tls;
        tls.ca_file = options.ca_file;
        tls.cert_file = options.cert_file;
        tls.key_file = options.key_file;
        tls.verify_server = !options.insecure;
        mqtt.tls = tls;
    }
    // A broker without TCP_NODELAY makes every answer 40-90 ms late: say so
    // once, naming the setting (docs/performance.md). An unreachable broker
    // is reported by the connect below.
    if (auto trip = measure_broker_round_trip(mqtt, 2, options.timeout))
        if (const std::string warning = broker_delay_warning(*trip); !warning.empty())
            std::fprintf(stderr, "nclink: warning: %s\n", warning.c_str());
    ClientOptions client_options;
    client_options.ex_cid = options.client_id;
    client_options.default_timeout = options.timeout;
    // error, not warn: a refused connection is told once, in the line below,
    // not also by the transport's retry warnings.
    client_options.logger = Logger(stderr_sink(), LogLevel::error);
    auto client = Client::create(std::move(mqtt), std::move(client_options));
    if (!client) throw std::runtime_error(client.error().describe());
    auto c = std::move(client).value();
    if (before_start) before_start(*c);
    if (auto started = c->start(); !started) throw std::runtime_error(started.error().describe());
    // Connected, or refused (credentials, a certificate): then say why at
    // once, in one line (docs/security.md, "Errors").
    const auto deadline = std::chrono::steady_clock::now() + options.timeout;
    while (!c->wait_connected(std::chrono::milliseconds(20))) {
        const TransportStats link = c->stats().transport;
        if (link.refused) throw std::runtime_error("cannot connect to " + options.broker + ": " + link.last_error);
        if (std::chrono::steady_clock::now() >= deadline)
            throw std::runtime_error("cannot reach the broker at " + options.broker +
                                     (link.last_error.empty() ? "" : ": " + link.last_error));
    }
    // The device's retained state, so a request that times out says when the
    // device is offline rather than only "no response".
    if (!options.device.empty()) (void)c->subscribe_state(options.device, [](const NotifyState&) {});
    // Registration is an agent feature: send it, do not wait for it.
    c->register_async([](Result<RegisterOutcome> outcome) {
        if (outcome.ok() && outcome->kind == RegisterOutcome::Kind::refused)
            std::fprintf(stderr, "nclink: the agent refused the registration (%s)\n",
                         outcome->status.reason.value_or("no reason").c_str());
    });
    return c;
}

bool interrupted() { return g_interrupted != 0; }

void install_interrupt_handler() {
    std::signal(SIGINT, on_interrupt);
    std::signal(SIGTERM, on_interrupt);
}

std::string format_time_ms(std::int64_t ms) {
    const std::time_t seconds = static_cast<std::time_t>(ms / 1000);
    std::tm utc{};
    gmtime_r(&seconds, &utc);
    char text[40];
    const std::size_t n = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
    std::snprintf(text + n, sizeof text - n, ".%03dZ", static_cast<int>(((ms % 1000) + 1000) % 1000));
    return text;
}

std::vector<ChannelInfo> find_channels(const Json& model) {
    std::vector<ChannelInfo> out;
    collect_channels(model, out, 0);
    return out;
}

std::string string_member(const Json& object, std::initializer_list<const char*> keys) {
    if (!object.is_object()) return {};
    for (const char* key : keys) {
        const auto it = object.find(key);
        if (it == object.end()) continue;
        if (it->is_string()) return it->get<std::string>();
        if (!it->is_null()) return it->dump();
    }
    return {};
}

}  // namespace nclink::cli
