// Sample DTU encoding: nclink's SampleEncoder against nlohmann build + dump of
// the same DTU, measured in the same run (medians over repeated runs).
//   bench_sample_encoder [runs=9] [iterations=2000]
// Cases (10 points x 100 rows each): "doubles" = axis-like values with 3
// decimals, "mixed" = ints, bools, nulls, a STATUS string column, "full" =
// full-precision doubles (the slow path of the double formatter).
#include "bench_util.hpp"

#include <nclink/json.hpp>
#include <nclink/sample_encoder.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace nclink;

namespace {

constexpr std::size_t kPoints = 10;
constexpr std::size_t kRows = 100;

/// nlohmann's form of one value (what an encoder without a fast path builds).
Json to_dom(const SampleValue& v) {
    switch (v.kind()) {
        case SampleValue::Kind::null: return nullptr;
        case SampleValue::Kind::boolean: return v.as_bool();
        case SampleValue::Kind::int64: return v.as_int64();
        case SampleValue::Kind::uint64: return v.as_uint64();
        case SampleValue::Kind::float64: return v.as_double();
        case SampleValue::Kind::text: return std::string(v.as_text());
        case SampleValue::Kind::json: return Json::parse(v.as_text());
    }
    return nullptr;
}

std::string nlohmann_encode(const SampleDtuHeader& h, const std::vector<SampleValue>& values) {
    Json dtu = Json::object();
    dtu["guid"] = h.guid;
    dtu["id"] = h.channel_id;
    dtu["beginTime"] = std::to_string(h.begin_time_ms);
    Json data = Json::array();
    for (std::size_t p = 0; p < kPoints; ++p) {
        Json column = Json::array();
        for (std::size_t r = 0; r < kRows; ++r) column.push_back(to_dom(values[p * kRows + r]));
        data.push_back(Json{{"data", std::move(column)}});
    }
    dtu["data"] = std::move(data);
    return dtu.dump();
}

/// Axis-like doubles with 3 decimals (what CNC positions look like).
std::vector<SampleValue> doubles_case(std::mt19937_64& rng) {
    std::normal_distribution<double> noise(0, 0.5);
    std::vector<SampleValue> values;
    for (std::size_t p = 0; p < kPoints; ++p)
        for (std::size_t r = 0; r < kRows; ++r) {
            const double x = 400.0 * std::sin(0.01 * static_cast<double>(r) + static_cast<double>(p)) + noise(rng);
            values.push_back(SampleValue::float64(std::round(x * 1000) / 1000));
        }
    return values;
}

/// Full-precision doubles (e.g. computed values): every value takes the
/// general shortest-digits path of std::to_chars.
std::vector<SampleValue> full_precision_case(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> dist(-1000.0, 1000.0);
    std::vector<SampleValue> values;
    for (std::size_t i = 0; i < kPoints * kRows; ++i) values.push_back(SampleValue::float64(dist(rng)));
    return values;
}

/// Mixed: 4 double, 2 int, 1 bool, 1 double with missed reads, 1 string (STATUS), 1 big counter.
std::vector<SampleValue> mixed_case(std::mt19937_64& rng) {
    static const char* const kStatus[] = {"RUN", "IDLE", "ALARM", "FEED HOLD"};
    std::vector<SampleValue> values;
    for (std::size_t p = 0; p < kPoints; ++p)
        for (std::size_t r = 0; r < kRows; ++r) {
            switch (p) {
                case 4:
                case 5: values.push_back(SampleValue::int64(static_cast<std::int64_t>(rng() % 24000))); break;
                case 6: values.push_back(SampleValue::boolean(rng() & 1)); break;
                case 7:
                    values.push_back(r % 7 == 0 ? SampleValue::null()
                                                : SampleValue::float64(static_cast<double>(rng() % 100000) / 100));
                    break;
                case 8: values.push_back(SampleValue::text(kStatus[(r / 25) % 4])); break;
                case 9:
                    values.push_back(SampleValue::int64(static_cast<std::int64_t>(1e12) + static_cast<std::int64_t>(r)));
                    break;
                default: values.push_back(SampleValue::float64(static_cast<double>(rng() % 1000000) / 1000));
            }
        }
    return values;
}

void run_case(const char* name, const std::vector<SampleValue>& values, int runs, std::size_t iterations) {
    SampleDtuHeader header;
    header.guid = "0f3c2a6e-4b1d-4c7a-9d2e-5a8b7c6d1e0f";
    header.channel_id = "cn1";
    header.begin_time_ms = 1700000000123;
    SampleEncoder encoder;
    const SampleBlock block{values.data(), kPoints, kRows};

    // Same value, both ways (sanity, and the byte counts for MB/s).
    const std::string ours_text(encoder.encode(header, block));
    const std::string theirs_text = nlohmann_encode(header, values);
    if (Json::parse(ours_text) != Json::parse(theirs_text)) {
        std::fprintf(stderr, "%s: encoders disagree\n", name);
        std::exit(1);
    }

    std::vector<double> ours_ns, theirs_ns;
    for (int run = 0; run < runs; ++run) {  // interleaved, so both see the same noise
        ours_ns.push_back(bench::time_per_iteration(iterations, [&] {
            const auto text = encoder.encode(header, block);
            bench::do_not_optimize(text.data());
        }));
        theirs_ns.push_back(bench::time_per_iteration(iterations, [&] {
            const auto text = nlohmann_encode(header, values);
            bench::do_not_optimize(text.data());
        }));
    }
    const double ours = bench::median(ours_ns);
    const double theirs = bench::median(theirs_ns);
    auto mbps = [](std::size_t bytes, double ns) { return static_cast<double>(bytes) / ns * 1e3; };
    std::printf("%-8s %zux%zu  %6zu B  nclink   %8.0f ns/msg [%.0f-%.0f]  %6.1f MB/s\n", name, kPoints, kRows, ours_text.size(),
                ours, bench::minimum(ours_ns), bench::maximum(ours_ns), mbps(ours_text.size(), ours));
    std::printf("%-8s %zux%zu  %6zu B  nlohmann %8.0f ns/msg [%.0f-%.0f]  %6.1f MB/s\n", name, kPoints, kRows, theirs_text.size(),
                theirs, bench::minimum(theirs_ns), bench::maximum(theirs_ns), mbps(theirs_text.size(), theirs));
    std::printf("%-8s ratio nlohmann/nclink = %.2fx (median of %d runs x %zu messages)\n\n", name, theirs / ours, runs, iterations);
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::max(7, std::atoi(argv[1])) : 9;
    const std::size_t iterations = argc > 2 ? static_cast<std::size_t>(std::atol(argv[2])) : 2000;
    std::mt19937_64 rng(41970);
    run_case("doubles", doubles_case(rng), runs, iterations);
    run_case("mixed", mixed_case(rng), runs, iterations);
    run_case("full", full_precision_case(rng), runs, iterations);
    return 0;
}
