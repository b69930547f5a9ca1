#include "transport/dtu_counting_transport.hpp"

namespace nclink::transport_detail {

std::size_t DtuCounter::slot(std::string_view topic) noexcept {
    if (const auto kind = topic_kind(topic)) return static_cast<std::size_t>(*kind);
    return kTopicKindCount;
}

std::map<std::string, std::uint64_t> DtuCounter::snapshot(const Counters& counters) {
    std::map<std::string, std::uint64_t> out;
    for (std::size_t i = 0; i < counters.size(); ++i) {
        const auto n = counters[i].load(std::memory_order_relaxed);
        if (n == 0) continue;
        out[i == kTopicKindCount ? std::string("unparsed") : std::string(to_string(static_cast<TopicKind>(i)))] = n;
    }
    return out;
}

namespace {

class CountingTransport final : public Transport {
public:
    CountingTransport(std::unique_ptr<Transport> inner, std::shared_ptr<DtuCounter> counter)
        : inner_(std::move(inner)), counter_(std::move(counter)) {}

    void set_message_handler(MessageHandler handler) override {
        inner_->set_message_handler([counter = counter_, handler = std::move(handler)](const Message& m) {
            counter->count_in(DtuCounter::slot(m.topic));
            if (handler) handler(m);
        });
    }
    void set_state_handler(LinkStateHandler handler) override { inner_->set_state_handler(std::move(handler)); }
    Result<void> start() override { return inner_->start(); }
    void stop(std::chrono::milliseconds flush_timeout) override { inner_->stop(flush_timeout); }
    Result<void> publish(Message message) override {
        // Classified before the move; counted only when the transport took it.
        const std::size_t slot = DtuCounter::slot(message.topic);
        auto published = inner_->publish(std::move(message));
        if (published) counter_->count_out(slot);
        return published;
    }
    Result<void> subscribe(std::vector<std::string> filters, int qos) override {
        return inner_->subscribe(std::move(filters), qos);
    }
    Result<void> unsubscribe(std::vector<std::string> filters) override { return inner_->unsubscribe(std::move(filters)); }
    LinkState state() const override { return inner_->state(); }
    TransportStats stats() const override { return inner_->stats(); }
    bool flush(std::chrono::milliseconds timeout) override { return inner_->flush(timeout); }

private:
    std::unique_ptr<Transport> inner_;
    std::shared_ptr<DtuCounter> counter_;
};

}  // namespace

std::unique_ptr<Transport> count_dtus(std::unique_ptr<Transport> inner, std::shared_ptr<DtuCounter> counter) {
    if (!inner || !counter) return inner;
    return std::make_unique<CountingTransport>(std::move(inner), std::move(counter));
}

}  // namespace nclink::transport_detail
