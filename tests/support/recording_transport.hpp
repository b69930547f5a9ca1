// A Transport that goes nowhere: it keeps what is published and subscribed
// to, and the test sets its link state and its reported backlog. For unit tests of the pieces that
// publish (spool, events service) without a broker or a loopback hub.
#pragma once

#include <nclink/json.hpp>
#include <nclink/transport.hpp>

#include <atomic>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace nclink::test {

class RecordingTransport : public Transport {
public:
    void set_message_handler(MessageHandler) override {}
    void set_state_handler(LinkStateHandler) override {}
    Result<void> start() override { return ok_result(); }
    void stop(std::chrono::milliseconds) override {}
    Result<void> publish(Message message) override {
        std::lock_guard<std::mutex> lock(mutex_);
        sent_.push_back(std::move(message));
        return ok_result();
    }
    Result<void> subscribe(std::vector<std::string> filters, int qos) override {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& f : filters) subscribed_.emplace_back(std::move(f), qos);
        return ok_result();
    }
    Result<void> unsubscribe(std::vector<std::string>) override { return ok_result(); }
    LinkState state() const override { return link; }
    TransportStats stats() const override {
        TransportStats s;
        s.buffered = backlog;
        return s;
    }
    bool flush(std::chrono::milliseconds) override { return true; }

    std::vector<Message> messages() {
        std::lock_guard<std::mutex> lock(mutex_);
        return sent_;
    }
    /// Every filter subscribed to, with its QoS, in order.
    std::vector<std::pair<std::string, int>> subscriptions() {
        std::lock_guard<std::mutex> lock(mutex_);
        return subscribed_;
    }
    std::size_t count() {
        std::lock_guard<std::mutex> lock(mutex_);
        return sent_.size();
    }
    /// The payloads published on one topic, parsed.
    std::vector<Json> on(const std::string& topic) {
        std::lock_guard<std::mutex> lock(mutex_);
        std::vector<Json> out;
        for (const auto& m : sent_)
            if (m.topic == topic) out.push_back(Json::parse(m.payload));
        return out;
    }

    std::atomic<LinkState> link{LinkState::connected};
    std::atomic<std::size_t> backlog{0};  ///< reported as stats().buffered

private:
    std::mutex mutex_;
    std::vector<Message> sent_;
    std::vector<std::pair<std::string, int>> subscribed_;
};

}  // namespace nclink::test
