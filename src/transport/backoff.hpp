// The wait before the next connect attempt. Exponential (the caller doubles
// `delay` up to its maximum) and jittered: a broker restart drops every
// terminal of a plant at the same instant, and without jitter they all retry
// in lockstep (1,000 gateway machines timed out together round after round).
// The wait is spread over [delay/2, delay].
#pragma once

#include <chrono>
#include <random>

namespace nclink::transport_detail {

inline std::chrono::milliseconds jittered(std::chrono::milliseconds delay, std::mt19937& rng) {
    if (delay.count() <= 1) return delay;
    std::uniform_int_distribution<std::chrono::milliseconds::rep> spread(delay.count() / 2, delay.count());
    return std::chrono::milliseconds(spread(rng));
}

}  // namespace nclink::transport_detail
