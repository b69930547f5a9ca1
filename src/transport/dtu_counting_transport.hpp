// Counts the DTUs a terminal sends and receives, by topic kind (table 17), for
// its metrics (docs/metrics.md): a Transport that wraps the real one and
// counts on the way through. Owners wrap their transport once, before
// setting handlers; nothing else changes for them.
//
// Thread-safety: the counters are relaxed atomics, bumped on whichever thread
// publishes or delivers; snapshots may be taken from any thread.
#pragma once

#include <nclink/topics.hpp>
#include <nclink/transport.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>

namespace nclink::transport_detail {

/// Number of TopicKind values (event is the last).
inline constexpr std::size_t kTopicKindCount = static_cast<std::size_t>(TopicKind::event) + 1;

class DtuCounter {
public:
    /// The counter slot of a topic: its TopicKind, or the "unparsed" slot.
    static std::size_t slot(std::string_view topic) noexcept;
    void count_in(std::size_t slot) noexcept { in_[slot].fetch_add(1, std::memory_order_relaxed); }
    void count_out(std::size_t slot) noexcept { out_[slot].fetch_add(1, std::memory_order_relaxed); }
    /// By kind name (to_string(TopicKind)), "unparsed" for other topics;
    /// kinds never seen are left out.
    std::map<std::string, std::uint64_t> in() const { return snapshot(in_); }
    std::map<std::string, std::uint64_t> out() const { return snapshot(out_); }

private:
    using Counters = std::array<std::atomic<std::uint64_t>, kTopicKindCount + 1>;  // last: unparsed
    static std::map<std::string, std::uint64_t> snapshot(const Counters& counters);

    Counters in_{};
    Counters out_{};
};

/// `inner` with every published and delivered message counted in `counter`.
std::unique_ptr<Transport> count_dtus(std::unique_ptr<Transport> inner, std::shared_ptr<DtuCounter> counter);

}  // namespace nclink::transport_detail
