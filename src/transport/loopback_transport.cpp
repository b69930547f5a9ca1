#include <nclink/testing/loopback_transport.hpp>

#include "transport/outbox.hpp"
#include "transport/subscription_set.hpp"

#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <thread>
#include <variant>

namespace nclink {

class LoopbackTransport;

// What a client looks like to the broker.
struct LoopbackClient {
    virtual ~LoopbackClient() = default;
    virtual const std::string& id() const = 0;
    virtual const std::optional<Message>& will() const = 0;
    // Called on the broker's delivery thread only.
    virtual void on_link(LinkState state, std::string_view detail) = 0;
    virtual void on_message(const Message& message) = 0;
};

struct NCLINK_LOCAL LoopbackBroker::Impl {
    struct Deliver {
        std::string client;
        Message message;
    };
    struct Link {
        std::string client;
        LinkState state;
        std::string detail;
    };
    using Event = std::variant<Deliver, Link>;

    struct Session {
        LoopbackClient* client = nullptr;
        bool connected = false;
        std::map<std::string, int> subscriptions;
    };

    mutable std::mutex mutex;  // sessions, retained, events, online
    std::condition_variable wake;
    std::map<std::string, Session> sessions;
    std::map<std::string, Message> retained;
    std::deque<Event> events;
    bool online = true;
    bool stopping = false;
    std::uint64_t routed = 0;

    // Held while a handler runs, so detach() can wait for a running callback.
    std::mutex dispatch;
    std::thread thread;

    Impl() {
        thread = std::thread([this] { run(); });
    }
    ~Impl() {
        {
            std::lock_guard<std::mutex> lock(mutex);
            stopping = true;
        }
        wake.notify_all();
        thread.join();
    }

    void push_locked(Event e) {
        events.push_back(std::move(e));
        wake.notify_one();
    }

    void connect_locked(Session& s) {
        s.connected = true;
        push_locked(Link{s.client->id(), LinkState::connected, "loopback"});
    }

    void lose_locked(Session& s, std::string detail, bool publish_will) {
        if (!s.connected) return;
        s.connected = false;
        s.subscriptions.clear();
        push_locked(Link{s.client->id(), LinkState::disconnected, std::move(detail)});
        if (publish_will && s.client->will()) route_locked(*s.client->will());
    }

    void attach(LoopbackClient* client) {
        std::lock_guard<std::mutex> lock(mutex);
        auto& s = sessions[client->id()];
        if (s.client && s.client != client) lose_locked(s, "client id taken over", true);  // MQTT: newest wins
        s.client = client;
        s.connected = false;
        if (online) connect_locked(s);
    }

    void detach(LoopbackClient* client) {
        {
            std::lock_guard<std::mutex> lock(mutex);
            auto it = sessions.find(client->id());
            if (it != sessions.end() && it->second.client == client) sessions.erase(it);
            for (auto& e : events) {
                if (auto* d = std::get_if<Deliver>(&e); d && d->client == client->id()) d->client.clear();
                if (auto* l = std::get_if<Link>(&e); l && l->client == client->id()) l->client.clear();
            }
        }
        std::lock_guard<std::mutex> wait_for_running_callback(dispatch);
    }

    void route_locked(const Message& m) {
        ++routed;
        if (m.retained) {
            if (m.payload.empty()) retained.erase(m.topic);
            else retained[m.topic] = m;
        }
        for (auto& [id, s] : sessions) {
            if (!s.connected) continue;
            int best = -1;
            for (const auto& [filter, qos] : s.subscriptions)
                if (topic_matches(filter, m.topic)) best = std::max(best, qos);
            if (best < 0) continue;
            Message copy = m;
            copy.retained = false;  // live delivery, as MQTT does
            copy.qos = std::min(m.qos, best);
            push_locked(Deliver{id, std::move(copy)});
        }
    }

    bool publish(const std::string& from, const Message& m) {
        std::lock_guard<std::mutex> lock(mutex);
        auto it = sessions.find(from);
        if (!online || it == sessions.end() || !it->second.connected) return false;
        route_locked(m);
        return true;
    }

    void subscribe(const std::string& from, const std::vector<std::string>& filters, int qos) {
        std::lock_guard<std::mutex> lock(mutex);
        auto it = sessions.find(from);
        if (it == sessions.end() || !it->second.connected) return;
        for (const auto& f : filters) {
            it->second.subscriptions[f] = qos;
            for (const auto& [topic, m] : retained)
                if (topic_matches(f, topic)) {
                    Message copy = m;
                    copy.qos = std::min(m.qos, qos);
                    push_locked(Deliver{from, std::move(copy)});  // retained flag kept
                }
        }
    }

    void unsubscribe(const std::string& from, const std::vector<std::string>& filters) {
        std::lock_guard<std::mutex> lock(mutex);
        auto it = sessions.find(from);
        if (it == sessions.end()) return;
        for (const auto& f : filters) it->second.subscriptions.erase(f);
    }

    // Lock order everywhere: dispatch before mutex (a handler running under
    // dispatch may call subscribe()/publish(), which take mutex).
    void run() {
        for (;;) {
            Event e;
            {
                std::unique_lock<std::mutex> lock(mutex);
                wake.wait(lock, [this] { return stopping || !events.empty(); });
                if (stopping) return;
                e = std::move(events.front());
                events.pop_front();
            }
            std::lock_guard<std::mutex> running(dispatch);
            LoopbackClient* target = nullptr;
            {
                std::lock_guard<std::mutex> lock(mutex);
                const std::string& id = std::visit([](auto& ev) -> const std::string& { return ev.client; }, e);
                if (auto it = sessions.find(id); !id.empty() && it != sessions.end()) target = it->second.client;
            }
            if (!target) continue;
            if (auto* d = std::get_if<Deliver>(&e)) target->on_message(d->message);
            else if (auto* l = std::get_if<Link>(&e)) target->on_link(l->state, l->detail);
        }
    }
};

class LoopbackAccess {
public:
    static LoopbackBroker::Impl& impl(LoopbackBroker& b) { return *b.impl_; }
};

LoopbackBroker::LoopbackBroker() : impl_(std::make_shared<Impl>()) {}
LoopbackBroker::~LoopbackBroker() = default;

void LoopbackBroker::set_online(bool online) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (impl_->online == online) return;
    impl_->online = online;
    for (auto& [id, s] : impl_->sessions) {
        if (online) impl_->connect_locked(s);
        else impl_->lose_locked(s, "broker went away", true);
    }
}

bool LoopbackBroker::online() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->online;
}

bool LoopbackBroker::drop_client(const std::string& client_id) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    auto it = impl_->sessions.find(client_id);
    if (it == impl_->sessions.end()) return false;
    impl_->lose_locked(it->second, "dropped by test", true);
    if (impl_->online) impl_->connect_locked(it->second);
    return true;
}

std::optional<Message> LoopbackBroker::retained(const std::string& topic) const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    auto it = impl_->retained.find(topic);
    if (it == impl_->retained.end()) return std::nullopt;
    return it->second;
}

std::uint64_t LoopbackBroker::routed() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->routed;
}

class LoopbackTransport final : public Transport, private LoopbackClient {
public:
    LoopbackTransport(LoopbackBroker::Impl& broker, LoopbackOptions options, Logger logger)
        : broker_(broker),
          options_(std::move(options)),
          logger_(std::move(logger)),
          outbox_(
              options_.outbox, [this](const std::shared_ptr<const Message>& m, std::uint64_t attempt) { return send(*m, attempt); },
              logger_, nullptr, true) {}

    ~LoopbackTransport() override { stop(std::chrono::milliseconds(0)); }

    void set_message_handler(MessageHandler h) override { on_message_ = std::move(h); }
    void set_state_handler(LinkStateHandler h) override { on_state_ = std::move(h); }

    Result<void> start() override {
        if (started_.exchange(true)) return make_error(ErrorCode::unavailable, "transport already started");
        broker_.attach(this);
        return ok_result();
    }

    void stop(std::chrono::milliseconds flush_timeout) override {
        if (!started_ || stopped_.exchange(true)) return;
        if (state_ == LinkState::connected && flush_timeout.count() > 0) outbox_.wait_drained(flush_timeout);
        outbox_.stop();
        broker_.detach(this);
        state_ = LinkState::disconnected;
    }

    Result<void> publish(Message message) override { return outbox_.push(std::move(message)); }

    Result<void> subscribe(std::vector<std::string> filters, int qos) override {
        subscriptions_.add(filters, qos);
        broker_.subscribe(options_.client_id, filters, qos);
        return ok_result();
    }

    Result<void> unsubscribe(std::vector<std::string> filters) override {
        subscriptions_.remove(filters);
        broker_.unsubscribe(options_.client_id, filters);
        return ok_result();
    }

    LinkState state() const override { return state_; }

    TransportStats stats() const override {
        TransportStats s;
        outbox_.fill_stats(s);
        s.received = received_;
        s.connects = connects_;
        return s;
    }

    bool flush(std::chrono::milliseconds timeout) override { return outbox_.wait_drained(timeout); }

private:
    const std::string& id() const override { return options_.client_id; }
    const std::optional<Message>& will() const override { return options_.last_will; }

    void on_link(LinkState state, std::string_view detail) override {
        if (state == LinkState::connected) {
            for (const auto& [qos, filters] : subscriptions_.by_qos()) broker_.subscribe(options_.client_id, filters, qos);
            ++connects_;
            state_ = state;
            if (on_state_) on_state_(state, detail);
            outbox_.link_up();
        } else {
            outbox_.link_down();
            state_ = state;
            if (on_state_) on_state_(state, detail);
        }
    }

    void on_message(const Message& message) override {
        ++received_;
        if (on_message_) on_message_(message);
    }

    bool send(const Message& m, std::uint64_t attempt) {
        if (!broker_.publish(options_.client_id, m)) return false;
        outbox_.delivered(attempt);
        return true;
    }

    LoopbackBroker::Impl& broker_;
    const LoopbackOptions options_;
    const Logger logger_;
    transport_detail::Outbox outbox_;
    MessageHandler on_message_;
    LinkStateHandler on_state_;
    transport_detail::SubscriptionSet subscriptions_;
    std::atomic<bool> started_{false};
    std::atomic<bool> stopped_{false};
    std::atomic<LinkState> state_{LinkState::disconnected};
    std::atomic<std::uint64_t> received_{0};
    std::atomic<std::uint64_t> connects_{0};
};

std::unique_ptr<Transport> make_loopback_transport(LoopbackBroker& broker, LoopbackOptions options, Logger logger) {
    return std::make_unique<LoopbackTransport>(LoopbackAccess::impl(broker), std::move(options), std::move(logger));
}

}  // namespace nclink
