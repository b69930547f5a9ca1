// Request decoding on the adapter's MQTT receive thread: decode<T>(text) of
// the plain requests applications send (a scan for Query and Set) against
// the floor every tree decoder starts with, nlohmann's parse of the same
// text, measured interleaved in the same run (medians over the runs).
//   bench_request_decode [runs=9] [iterations=20000]
#include "bench_util.hpp"

#include <nclink/dtu.hpp>
#include <nclink/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace nclink;

namespace {

std::string query_of(int items) {
    Json ids = Json::array();
    for (int i = 0; i < items; ++i) ids.push_back(Json{{"id", "item_" + std::to_string(i)}});
    return Json{{"@id", "r-000123"}, {"guid", "bench-dev"}, {"ids", ids}}.dump();
}

std::string set_of(const Json& value) {
    const Json values = Json::array({Json{{"id", "feed_ovr_cfg"}, {"params", {{"value", value}}}}});
    return Json{{"@id", "r-000123"}, {"guid", "bench-dev"}, {"values", values}}.dump();
}

template <class T>
void run_case(const char* name, const std::string& payload, int runs, std::size_t iterations) {
    if (!decode<T>(payload).ok()) {
        std::fprintf(stderr, "%s: does not decode\n", name);
        std::exit(1);
    }
    std::vector<double> ours_ns, floor_ns;
    for (int run = 0; run < runs; ++run) {  // interleaved, so both see the same noise
        ours_ns.push_back(bench::time_per_iteration(iterations, [&] {
            const auto decoded = decode<T>(payload);
            bench::do_not_optimize(decoded);
        }));
        floor_ns.push_back(bench::time_per_iteration(iterations, [&] {
            const Json tree = Json::parse(payload);
            bench::do_not_optimize(tree);
        }));
    }
    const double ours = bench::median(ours_ns);
    const double floor = bench::median(floor_ns);
    std::printf("%-10s %5zu B  decode %8.0f ns [%.0f-%.0f]  parse alone %8.0f ns  ratio %.2fx\n", name, payload.size(), ours,
                bench::minimum(ours_ns), bench::maximum(ours_ns), floor, ours / floor);
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::max(7, std::atoi(argv[1])) : 9;
    const std::size_t iterations = argc > 2 ? static_cast<std::size_t>(std::atol(argv[2])) : 20000;
    std::printf(
        "decode<T>(text) of plain requests against Json::parse of the same text (the tree decoder's first step);\n"
        "median of %d runs x %zu decodes\n",
        runs, iterations);
    run_case<QueryRequest>("Query 1", query_of(1), runs, iterations);
    run_case<QueryRequest>("Query 100", query_of(100), runs, iterations / 20);
    run_case<SetRequest>("Set int", set_of(42), runs, iterations);
    run_case<SetRequest>("Set double", set_of(12.345), runs, iterations);
    run_case<SetRequest>("Set string", set_of("on"), runs, iterations);
    return 0;
}
