// nclink-conform: the conformance tester of GB/T 41970-2022 chapter 9 against
// any adapter on a broker. Parsing, running and reporting live in conform/
// (a library the tests link); this file only wires them to the process.
#include "conform/cli_options.hpp"
#include "conform/report.hpp"
#include "conform/runner.hpp"
#include "conform/wire.hpp"

#include <nclink/mqtt_transport.hpp>

#include <cstdio>
#include <exception>
#include <fstream>
#include <random>

namespace {

bool write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    return static_cast<bool>(out.flush());
}

int run(const std::vector<std::string>& args) {
    using namespace nclink;
    auto parsed = conform::parse_cli(args);
    if (!parsed) {
        std::fprintf(stderr, "nclink-conform: %s\n\n%s", parsed.error().message.c_str(), conform::usage_text);
        return 2;
    }
    conform::CliOptions o = std::move(parsed).value();
    if (o.help) {
        std::fputs(conform::usage_text, stdout);
        return 0;
    }
    if (o.client_id.empty()) o.client_id = fmt::format("nclink-conform-{:08x}", std::random_device{}());
    if (o.verbose) o.run.logger = Logger(stderr_sink(), LogLevel::info);

    MqttOptions mqtt;
    mqtt.broker_url = o.broker;
    mqtt.client_id = o.client_id;
    mqtt.username = o.username;
    mqtt.password = o.password;
    if (o.broker.rfind("ssl://", 0) == 0 || o.broker.rfind("wss://", 0) == 0) mqtt.tls = MqttTlsOptions{};
    auto transport = make_mqtt_transport(mqtt, o.run.logger);
    if (!transport) {
        std::fprintf(stderr, "nclink-conform: %s\n", transport.error().describe().c_str());
        return 2;
    }
    conform::Wire wire(*transport.value(), o.client_id);
    if (auto connected = wire.connect(conform::tester_subscriptions(o.run.device, o.client_id),
                                      std::max(o.run.timeout, std::chrono::milliseconds(5000)));
        !connected) {
        std::fprintf(stderr, "nclink-conform: cannot use the broker %s: %s\n", o.broker.c_str(),
                     connected.error().describe().c_str());
        return 2;
    }
    const conform::TestRecord record = conform::run_conformance(wire, o.run);
    wire.close();

    const std::string md = conform::render_markdown(record);
    if (!o.report_md.empty() && !write_file(o.report_md, md)) {
        std::fprintf(stderr, "nclink-conform: cannot write %s\n", o.report_md.c_str());
        return 2;
    }
    if (!o.report_json.empty() && !write_file(o.report_json, conform::render_json(record).dump(2) + "\n")) {
        std::fprintf(stderr, "nclink-conform: cannot write %s\n", o.report_json.c_str());
        return 2;
    }
    if (o.report_md.empty() && o.report_json.empty()) std::fputs(md.c_str(), stdout);
    const bool pass = record.verdict() == conform::Verdict::pass;
    std::fprintf(stderr, "nclink-conform: %s: %zu passed, %zu failed, %zu not supported, %zu skipped\n", pass ? "PASS" : "FAIL",
                 record.count(conform::Outcome::pass), record.count(conform::Outcome::fail),
                 record.count(conform::Outcome::not_supported), record.count(conform::Outcome::skipped));
    return pass ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "nclink-conform: %s\n", e.what());
        return 2;
    }
}
