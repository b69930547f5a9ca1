// At-least-once delivery (QoS 1) repeats a DTU when a link breaks before its
// acknowledgement: the adapter sends it again after reconnecting. The client
// hands each Sample DTU (key: topic and beginTime) and each Event DTU (key:
// device and @id) to the application once; docs/delivery.md. A bounded
// memory per stream: the newest `capacity` keys are remembered (replayed
// spool DTUs arrive out of order, so an ordered "newer than the last" test
// would not do).
// Thread: the dispatch thread only (not synchronized).
#pragma once

#include <cstddef>
#include <deque>
#include <set>
#include <string>
#include <unordered_map>

namespace nclink::client_detail {

class DuplicateFilter {
public:
    explicit DuplicateFilter(std::size_t capacity = 4096) : capacity_(capacity) {}

    /// True the first time `key` is seen on `stream` (within the memory).
    bool first(const std::string& stream, const std::string& key) {
        if (capacity_ == 0) return true;
        auto& s = streams_[stream];
        if (!s.keys.insert(key).second) return false;
        s.order.push_back(key);
        if (s.order.size() > capacity_) {
            s.keys.erase(s.order.front());
            s.order.pop_front();
        }
        return true;
    }

private:
    struct Stream {
        std::set<std::string> keys;
        std::deque<std::string> order;
    };
    std::size_t capacity_;
    std::unordered_map<std::string, Stream> streams_;
};

}  // namespace nclink::client_detail
