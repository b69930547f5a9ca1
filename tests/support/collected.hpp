// What a callback delivered on another thread (a client's dispatch thread, an
// MQTT callback), kept for the test thread to read.
#pragma once

#include <cstddef>
#include <functional>
#include <mutex>
#include <vector>

namespace nclink::test {

template <typename T>
class Collected {
public:
    void add(const T& item) {
        std::lock_guard<std::mutex> lock(mutex_);
        items_.push_back(item);
    }
    /// A callback that appends what it is given; it refers to this object,
    /// which must outlive the subscription.
    std::function<void(const T&)> handler() {
        return [this](const T& item) { add(item); };
    }
    std::size_t size() {
        std::lock_guard<std::mutex> lock(mutex_);
        return items_.size();
    }
    /// A copy: the callback may append while the test reads it.
    T at(std::size_t i) {
        std::lock_guard<std::mutex> lock(mutex_);
        return items_.at(i);
    }

private:
    std::mutex mutex_;
    std::vector<T> items_;
};

}  // namespace nclink::test
