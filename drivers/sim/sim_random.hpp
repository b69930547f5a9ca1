// Deterministic randomness for the simulator. std::*_distribution results
// differ between standard libraries, so everything here is hand-rolled on
// splitmix64: the same seed gives the same values everywhere.
#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

namespace nclink::sim {

inline std::uint64_t mix64(std::uint64_t x) noexcept {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

/// FNV-1a: stable across runs (std::hash is not guaranteed to be).
inline std::uint64_t hash_text(std::string_view text) noexcept {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    for (unsigned char c : text) {
        h ^= c;
        h *= 0x100000001b3ULL;
    }
    return h;
}

inline std::uint64_t hash_pair(std::uint64_t a, std::uint64_t b) noexcept { return mix64(a ^ mix64(b)); }

/// Uniform in [0, 1) from a hash.
inline double unit(std::uint64_t h) noexcept { return static_cast<double>(h >> 11) * 0x1.0p-53; }

/// Uniform in [0, 1) for lattice point k of a stream.
inline double lattice(std::uint64_t stream, std::int64_t k) noexcept {
    return unit(hash_pair(stream, static_cast<std::uint64_t>(k)));
}

/// Smooth value noise in [0, 1]: random lattice values every `period`
/// seconds, eased in between. A pure function of (stream, t): reading at any
/// cadence gives the same curve.
inline double value_noise(std::uint64_t stream, double t, double period) noexcept {
    const double x = t / period;
    const double k = std::floor(x);
    const double f = x - k;
    const double eased = f * f * (3.0 - 2.0 * f);
    const auto ki = static_cast<std::int64_t>(k);
    const double a = lattice(stream, ki);
    const double b = lattice(stream, ki + 1);
    return a + (b - a) * eased;
}

/// Two octaves of value noise, still in [0, 1].
inline double drift(std::uint64_t stream, double t, double period) noexcept {
    return 0.75 * value_noise(stream, t, period) + 0.25 * value_noise(mix64(stream), t, period / 7.0);
}

/// A small sequential generator for building tables.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() noexcept { return mix64(state_++); }
    double uniform(double lo, double hi) noexcept { return lo + (hi - lo) * unit(next()); }
    /// Integer in [lo, hi].
    std::int64_t integer(std::int64_t lo, std::int64_t hi) noexcept {
        return lo + static_cast<std::int64_t>(next() % static_cast<std::uint64_t>(hi - lo + 1));
    }

private:
    std::uint64_t state_;
};

}  // namespace nclink::sim
