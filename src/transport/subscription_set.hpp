// The filters a transport has subscribed to, kept so that every
// (re)connection subscribes to all of them again: a clean session
// (MQTT 3.1.2.4) starts with none at the broker. Thread-safe: subscribe()
// and unsubscribe() come from any thread, the replay from the transport's
// own connection thread.
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace nclink::transport_detail {

class SubscriptionSet {
public:
    void add(const std::vector<std::string>& filters, int qos) {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& f : filters) qos_of_[f] = qos;
    }
    void remove(const std::vector<std::string>& filters) {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& f : filters) qos_of_.erase(f);
    }
    /// The filters grouped by QoS: one SUBSCRIBE per group on a reconnection.
    std::map<int, std::vector<std::string>> by_qos() const {
        std::map<int, std::vector<std::string>> out;
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& [filter, qos] : qos_of_) out[qos].push_back(filter);
        return out;
    }

private:
    mutable std::mutex mutex_;
    std::map<std::string, int> qos_of_;
};

}  // namespace nclink::transport_detail
