// Push path: ns per PushChannel::push() of a 6-value row while the engine's
// uploader drains the ring concurrently, against the same loop copying the
// row into a plain array (baseline, same run). Target: median < 100 ns.
//
//   bench_push [--rounds N]      (N rounds of 1000 pushes, 1 ms apart; default 2000)
#include "bench_util.hpp"

#include "sampling/sampling_engine.hpp"
#include "sampling/sleeper.hpp"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

using namespace nclink;
using namespace nclink::bench;

int main(int argc, char** argv) {
    int rounds = 2000;
    if (argc == 3 && std::string(argv[1]) == "--rounds") rounds = std::atoi(argv[2]);
    constexpr std::size_t kBatch = 1000;
    constexpr std::size_t kWidth = 6;

    std::atomic<std::uint64_t> rows_out{0};
    sampling_detail::EngineDeps deps;
    deps.clock = std::make_shared<SystemClock>();
    deps.sleeper = std::make_shared<sampling_detail::NanosleepSleeper>();
    deps.dev = "bench";
    deps.sink = [&](Message m) { rows_out += m.payload.size() > 0 ? 1 : 0; };
    sampling_detail::SamplingEngine engine(std::move(deps));
    sampling_detail::ChannelSpec spec;
    spec.id = "servo";
    for (std::size_t i = 0; i < kWidth; ++i) spec.points.push_back(PointRef{"p" + std::to_string(i), DataKind::single});
    spec.sample_interval_ms = 0.001;  // a ring for 10 ms of 1 MHz pushes
    spec.upload_interval_ms = 10;
    spec.topic = "Sample/bench/servo";
    spec.push = true;
    if (!engine.add_channel(spec).ok()) return 1;
    PushChannel ch = engine.push_channel("servo").value();
    engine.start();

    SampleValue row[kWidth];
    std::vector<SampleValue> plain(kBatch * kWidth);
    std::vector<double> push_batch_ns, copy_batch_ns, push_call_ns, clock_call_ns;
    push_call_ns.reserve(static_cast<std::size_t>(rounds) * 50);
    clock_call_ns.reserve(static_cast<std::size_t>(rounds) * 50);
    std::uint64_t refused = 0;
    for (int r = 0; r < rounds; ++r) {
        // batch means (the clock read amortized over 1000 calls)
        auto t0 = now_ns();
        for (std::size_t i = 0; i < kBatch; ++i) {
            row[0] = SampleValue::float64(static_cast<double>(i));
            std::memcpy(plain.data() + i * kWidth, row, sizeof(row));
        }
        do_not_optimize(plain[7]);
        copy_batch_ns.push_back(static_cast<double>(now_ns() - t0) / kBatch);
        t0 = now_ns();
        for (std::size_t i = 0; i < kBatch; ++i) {
            row[0] = SampleValue::float64(static_cast<double>(i));
            if (!ch.push(row, kWidth)) ++refused;
        }
        push_batch_ns.push_back(static_cast<double>(now_ns() - t0) / kBatch);
        // single calls, for the tail (minus the cost of reading the clock twice)
        for (int i = 0; i < 50; ++i) {
            const auto a = now_ns();
            if (!ch.push(row, kWidth)) ++refused;
            const auto b = now_ns();
            const auto c = now_ns();
            push_call_ns.push_back(static_cast<double>(b - a));
            clock_call_ns.push_back(static_cast<double>(c - b));
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    engine.stop();
    const auto s = engine.stats().at(0);
    std::printf("push of a %zu-value row, %d rounds x %zu (+50 timed singly), uploader draining concurrently\n", kWidth, rounds,
                kBatch);
    std::printf("baseline copy into an array: median %.1f ns/row\n", median(copy_batch_ns));
    std::printf("push():                      median %.1f ns/row (batch mean), ratio %.2fx the copy\n", median(push_batch_ns),
                median(push_batch_ns) / median(copy_batch_ns));
    std::printf(
        "push() timed singly:         p50 %.0f ns, p99 %.0f ns, p99.9 %.0f ns, max %.0f ns (clock read itself: p50 %.0f ns, "
        "subtracted: p50 %.0f, p99.9 %.0f)\n",
        median(push_call_ns), percentile(push_call_ns, 99), percentile(push_call_ns, 99.9), maximum(push_call_ns),
        median(clock_call_ns), median(push_call_ns) - median(clock_call_ns),
        percentile(push_call_ns, 99.9) - median(clock_call_ns));
    std::printf("rows pushed %llu, published %llu, drops %llu, refused %llu\n", static_cast<unsigned long long>(s.rows_sampled),
                static_cast<unsigned long long>(s.rows_published), static_cast<unsigned long long>(s.drops),
                static_cast<unsigned long long>(refused));
    return 0;
}
