// The publishes a libmosquitto connection has taken and not yet confirmed
// (its on_publish callback: PUBACK at QoS 1, the write at QoS 0), by message
// id, with the outbox's attempt each answers. The confirmation may come
// before mosquitto_publish() has returned the id to the sender: it is then
// kept as "early" until the sender records the id.
//
// Flat vectors reserved up front, not node containers: a node per message
// was one heap allocation per Sample DTU (docs/footprint.md). The outbox
// never has more than max_in_flight messages unconfirmed, so the searches
// stay short; a larger count only grows the vectors once.
//
// Threading: none of its own; the transport holds its lock around every call.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace nclink::transport_detail {

class InFlightIds {
public:
    explicit InFlightIds(std::size_t expected = 0) {
        entries_.reserve(expected);
        early_.reserve(expected);
    }

    /// The sender got `mid` for `attempt`. True when its confirmation came
    /// first (and is consumed): the attempt is delivered now.
    bool record(int mid, std::uint64_t attempt) {
        if (const auto e = std::find(early_.begin(), early_.end(), mid); e != early_.end()) {
            *e = early_.back();
            early_.pop_back();
            return true;
        }
        entries_.emplace_back(mid, attempt);
        return false;
    }

    /// `mid` was confirmed: the attempt it answers, removed; none when the
    /// sender has not recorded it yet (kept for record()).
    std::optional<std::uint64_t> confirm(int mid) {
        const auto e = std::find_if(entries_.begin(), entries_.end(), [mid](const auto& x) { return x.first == mid; });
        if (e == entries_.end()) {
            early_.push_back(mid);
            return std::nullopt;
        }
        const std::uint64_t attempt = e->second;
        *e = entries_.back();
        entries_.pop_back();
        return attempt;
    }

    /// The connection is gone: nothing it took will be confirmed.
    void clear() noexcept {
        entries_.clear();
        early_.clear();
    }

    std::size_t size() const noexcept { return entries_.size(); }
    std::size_t early() const noexcept { return early_.size(); }

private:
    std::vector<std::pair<int, std::uint64_t>> entries_;
    std::vector<int> early_;
};

}  // namespace nclink::transport_detail
