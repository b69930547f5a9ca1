// nclink-bridge figures (docs/bridge.md "Figures"), through a real mosquitto
// and the simulated mill (models/sim-mill.json: ch_fast 1 ms x 6 items):
//  1. /current latency, median and p99, against the floor of the same HTTP
//     server answering a constant document of the same size (same run);
//  2. /sample following the 1 ms channel for N seconds: observations per
//     second and whether any sequence number was skipped (gap) or fell out
//     of the buffer;
//  3. the bridge's RSS with a 131,072-slot buffer, filled.
//
//   bench_bridge [--seconds N] [--requests N]    (defaults 60 s, 2000)
#include "bridge/bridge.hpp"
#include "bridge/mtconnect_api.hpp"
#include "http/http_server.hpp"

#include <nclink/adapter.hpp>
#include <nclink/model.hpp>
#include "sim/sim_driver.hpp"

#include "bench_util.hpp"
#include "support/mosquitto_broker.hpp"

#include <httplib.h>

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>
#include <thread>

namespace {

long status_kb(const char* key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key, 0) == 0) return std::atol(line.c_str() + std::string(key).size());
    return -1;
}

std::vector<double> latencies(int port, const std::string& path, int requests) {
    httplib::Client client("127.0.0.1", port);
    client.set_keep_alive(true);
    std::vector<double> us;
    for (int i = 0; i < requests; ++i) {
        const auto t0 = nclink::bench::now_ns();
        auto r = client.Get(path.c_str());
        const auto t1 = nclink::bench::now_ns();
        if (!r || r->status != 200) {
            std::fprintf(stderr, "request failed\n");
            std::exit(3);
        }
        us.push_back(static_cast<double>(t1 - t0) / 1000.0);
    }
    return us;
}

std::string attribute(const std::string& xml, const char* name) {
    std::smatch m;
    if (std::regex_search(xml, m, std::regex(std::string(" ") + name + "=\"([0-9]+)\""))) return m[1];
    return "0";
}

}  // namespace

int main(int argc, char** argv) {
    double seconds = 60;
    int requests = 2000;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (std::string(argv[i]) == "--seconds") seconds = std::atof(argv[i + 1]);
        if (std::string(argv[i]) == "--requests") requests = std::atoi(argv[i + 1]);
    }
    nclink::test::MosquittoBroker broker;
    nclink::AdapterConfig config;
    config.broker_url = broker.url();
    config.model_path = NCLINK_SOURCE_DIR "/models/sim-mill.json";
    const auto loaded = nclink::load_model_file(config.model_path);
    nclink::Adapter adapter(config, nclink::SimDriver::create(loaded.model).value());
    if (!adapter.start().ok()) return 3;

    const long rss_before = status_kb("VmRSS:");
    nclink::bridge::BridgeConfig bc;
    bc.broker_url = broker.url();
    bc.http_port = 0;
    bc.shdr_port = 0;
    bc.buffer_size = 131072;
    nclink::bridge::Bridge bridge(bc, nclink::Logger{});
    if (!bridge.start().ok()) return 3;
    httplib::Client client("127.0.0.1", bridge.http_port());
    for (int i = 0; i < 2000; ++i) {
        auto r = client.Get("/current");
        if (r && r->body.find(">AVAILABLE</Availability>") != std::string::npos) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    // The first Query answers and events fill the document over a second or
    // two; the floor copies the document, so take it once it is complete.
    std::this_thread::sleep_for(std::chrono::seconds(3));
    if (const char* dump = std::getenv("NCLINK_BENCH_DUMP")) std::ofstream(dump) << client.Get("/current")->body;

    // 1. /current vs a constant document of the same size on the same server code.
    const std::string current_doc = client.Get("/current")->body;
    nclink::http::HttpOptions ho;
    ho.workers = 4;
    nclink::http::HttpServer floor_server(ho);
    floor_server.get(
        "/current", [&](const nclink::http::HttpRequest&) { return nclink::http::text_response(current_doc, "application/xml"); });
    if (!floor_server.start().ok()) return 3;
    latencies(floor_server.port(), "/current", 100);
    latencies(bridge.http_port(), "/current", 100);
    const auto floor_us = latencies(floor_server.port(), "/current", requests);
    const auto bridge_us = latencies(bridge.http_port(), "/current", requests);
    floor_server.stop();
    using nclink::bench::median;
    using nclink::bench::percentile;
    // Where the time goes, without HTTP: the same /current built in-process
    // (lock + select + render), and the bare wait for the store's lock,
    // which the thread applying Sample DTUs holds too.
    const nclink::bridge::MtConnectApi api(bridge.store());
    std::vector<double> render_us, lock_us;
    std::size_t rendered_bytes = 0;
    for (int i = 0; i < requests; ++i) {
        const auto t0 = nclink::bench::now_ns();
        const auto response = api.current("", {});
        const auto t1 = nclink::bench::now_ns();
        bridge.store().read([](const nclink::bridge::BridgeState&) { return 0; });
        const auto t2 = nclink::bench::now_ns();
        rendered_bytes = response.body.size();
        render_us.push_back(static_cast<double>(t1 - t0) / 1000.0);
        lock_us.push_back(static_cast<double>(t2 - t1) / 1000.0);
    }
    std::printf(
        "/current (%zu bytes, %d requests): median %.1f us, p99 %.1f us; floor (constant document): "
        "median %.1f us, p99 %.1f us; ratio median %.2f, p99 %.2f\n",
        current_doc.size(), requests, median(bridge_us), percentile(bridge_us, 99), median(floor_us), percentile(floor_us, 99),
        median(bridge_us) / median(floor_us), percentile(bridge_us, 99) / percentile(floor_us, 99));
    std::printf(
        "  in-process /current (%zu bytes, no HTTP): median %.1f us, p99 %.1f us; "
        "store lock alone: median %.1f us, p99 %.1f us\n",
        rendered_bytes, median(render_us), percentile(render_us, 99), median(lock_us), percentile(lock_us, 99));

    // 2. /sample keeping up with the 1 ms channel.
    std::uint64_t from = std::stoull(attribute(client.Get("/current")->body, "nextSequence"));
    std::uint64_t observations = 0, gaps = 0, calls = 0, positions = 0;
    const auto start = std::chrono::steady_clock::now();
    const std::regex seq(" sequence=\"([0-9]+)\"");
    while (std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds)) {
        auto r = client.Get(("/sample?count=10000&from=" + std::to_string(from)).c_str());
        ++calls;
        if (!r || r->status != 200) {
            ++gaps;  // OUT_OF_RANGE: we fell behind the buffer
            from = std::stoull(attribute(client.Get("/current")->body, "nextSequence"));
            continue;
        }
        // Documents group observations by component: sort before checking for gaps.
        std::vector<std::uint64_t> seen;
        for (auto it = std::sregex_iterator(r->body.begin(), r->body.end(), seq); it != std::sregex_iterator(); ++it)
            seen.push_back(std::stoull((*it)[1]));
        std::sort(seen.begin(), seen.end());
        seen.erase(std::unique(seen.begin(), seen.end()), seen.end());  // a condition's second element
        std::uint64_t expected = from;
        for (std::uint64_t s : seen) {
            if (s != expected) ++gaps;
            expected = s + 1;
            ++observations;
        }
        for (std::size_t p = r->body.find("<Position"); p != std::string::npos; p = r->body.find("<Position", p + 1)) ++positions;
        from = std::stoull(attribute(r->body, "nextSequence"));
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "/sample for %.0f s in %llu calls: %.0f observations/s (%.0f Position/s; the 1 ms channel offers "
        "6 x 1000/s, unchanged values are not recorded), sequence gaps %llu\n",
        elapsed, static_cast<unsigned long long>(calls), observations / elapsed, positions / elapsed,
        static_cast<unsigned long long>(gaps));

    // 3. RSS with the buffer full (131,072 slots; 60 s of the sim mill fill it several times).
    std::printf("bridge RSS: %ld kB before the bridge, %ld kB now (buffer %zu slots, last sequence %s), peak %ld kB\n",
                rss_before, status_kb("VmRSS:"), bc.buffer_size, attribute(client.Get("/current")->body, "lastSequence").c_str(),
                status_kb("VmHWM:"));
    bridge.stop();
    adapter.stop();
    return 0;
}
