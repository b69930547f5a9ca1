#include "client/request_ids.hpp"

#include <fmt/format.h>

#include <chrono>
#include <random>

namespace nclink::client_detail {

RequestIds::RequestIds(std::string ex) : ex_(std::move(ex)) {
    std::random_device device;
    // random_device may be deterministic on odd platforms: mix in the clock.
    const auto now = static_cast<std::uint64_t>(std::chrono::high_resolution_clock::now().time_since_epoch().count());
    std::mt19937_64 rng((static_cast<std::uint64_t>(device()) << 32) ^ device() ^ now);
    salt_ = fmt::format("{:08x}", static_cast<std::uint32_t>(rng()));
}

std::string RequestIds::next() { return fmt::format("{}-{}-{}", ex_, ++counter_, salt_); }

}  // namespace nclink::client_detail
