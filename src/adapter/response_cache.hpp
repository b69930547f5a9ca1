// Responses the adapter keeps while the link will not take them (the state-machine text
// items 75, 79: "cache the response DTU"; 76, 81: "send the cached
// responses"). Bounded by bytes, the same budget as the transport's offline
// buffer (AdapterConfig::offline_buffer_bytes): past it the oldest go first
// and are counted. Not thread-safe: the adapter holds its state mutex around
// every call, so keeping and taking happen in one order with the state.
#pragma once

#include <nclink/transport.hpp>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace nclink::adapter_detail {

class ResponseCache {
public:
    explicit ResponseCache(std::size_t max_bytes) : max_bytes_(max_bytes) {}

    void keep(Message message) {
        bytes_ += size_of(message);
        messages_.push_back(std::move(message));
        while (bytes_ > max_bytes_ && !messages_.empty()) {
            bytes_ -= size_of(messages_.front());
            messages_.pop_front();
            ++dropped_;
        }
    }

    /// Everything kept, oldest first; the cache is empty afterwards.
    std::vector<Message> take_all() {
        std::vector<Message> out(std::make_move_iterator(messages_.begin()), std::make_move_iterator(messages_.end()));
        messages_.clear();
        bytes_ = 0;
        return out;
    }

    std::size_t size() const noexcept { return messages_.size(); }
    std::uint64_t dropped() const noexcept { return dropped_; }

private:
    static std::size_t size_of(const Message& m) { return m.topic.size() + m.payload.size(); }

    std::size_t max_bytes_;
    std::size_t bytes_ = 0;
    std::uint64_t dropped_ = 0;
    std::deque<Message> messages_;
};

}  // namespace nclink::adapter_detail
