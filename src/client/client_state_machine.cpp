#include "client/client_state_machine.hpp"

namespace nclink::client_detail {
namespace {

class TrackedResponder final : public Responder {
public:
    TrackedResponder(std::shared_ptr<Responder> inner, std::function<void()> on_done)
        : inner_(std::move(inner)), on_done_(std::move(on_done)) {}
    bool decode(std::string_view payload) override { return inner_->decode(payload); }
    // The request is out of the pending table already: the state moves first,
    // so the caller woken by its completion sees the new state.
    void complete() override {
        on_done_();
        inner_->complete();
    }
    void fail(Error error) override {
        on_done_();
        inner_->fail(std::move(error));
    }

private:
    std::shared_ptr<Responder> inner_;
    std::function<void()> on_done_;
};

}  // namespace

std::shared_ptr<Responder> track_completion(std::shared_ptr<Responder> inner, std::function<void()> on_done) {
    return std::make_shared<TrackedResponder>(std::move(inner), std::move(on_done));
}

void ClientStateMachine::apply(ClientEvent event, bool queued, bool outstanding) {
    state_ = client_transition(state_, event, queued, outstanding).next;
}

void ClientStateMachine::prune(std::deque<Entry>& entries) {
    for (auto it = entries.begin(); it != entries.end();) it = hooks_.is_pending(it->id) ? it + 1 : entries.erase(it);
}

Result<ClientStateMachine::Outcome> ClientStateMachine::submit(const std::string& id, const std::string& dev, Message message,
                                                               const std::function<bool()>& add) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto t = client_transition(state_, ClientEvent::request_made);
    if (t.actions & client_action_queue_request) {
        if (queue_.size() >= max_queued_) prune(queue_);
        if (queue_.size() >= max_queued_)
            return make_error(ErrorCode::memory_configured,
                              "too many requests queued while disconnected (" + std::to_string(max_queued_) + ")");
    }
    if (!add()) return make_error(ErrorCode::unavailable, "client stopped");
    state_ = t.next;
    if (t.actions & client_action_queue_request) {
        queue_.push_back(Entry{id, dev, std::move(message)});
        return Outcome::queued;
    }
    // Published under the lock: requests leave in the order they were made,
    // and none overtakes the queue being flushed by link_restored().
    if (auto published = hooks_.publish(std::move(message)); !published) return std::move(published).error();
    return Outcome::sent;
}

std::vector<std::pair<std::string, Error>> ClientStateMachine::link_restored() {
    std::vector<std::pair<std::string, Error>> failed;
    std::lock_guard<std::mutex> lock(mutex_);
    prune(queue_);
    prune(unconfirmed_);
    const auto t = client_transition(state_, ClientEvent::link_restored, !queue_.empty(), hooks_.outstanding());
    state_ = t.next;
    if (t.actions & client_action_send_queued) {
        for (auto& entry : queue_) {
            if (auto published = hooks_.publish(entry.message); !published)
                failed.emplace_back(entry.id, std::move(published).error());
            else unconfirmed_.push_back(std::move(entry));
        }
        queue_.clear();
    }
    return failed;
}

void ClientStateMachine::link_lost() {
    std::lock_guard<std::mutex> lock(mutex_);
    // Unanswered requests from the last flush go out again after this outage
    // too, ahead of what is queued meanwhile (the order they were made).
    prune(unconfirmed_);
    queue_.insert(queue_.begin(), std::make_move_iterator(unconfirmed_.begin()), std::make_move_iterator(unconfirmed_.end()));
    unconfirmed_.clear();
    apply(ClientEvent::link_lost);
}

std::vector<std::pair<std::string, Error>> ClientStateMachine::resend(const std::string& dev, std::size_t& sent) {
    std::vector<std::pair<std::string, Error>> failed;
    sent = 0;
    std::lock_guard<std::mutex> lock(mutex_);
    prune(unconfirmed_);
    for (auto it = unconfirmed_.begin(); it != unconfirmed_.end();) {
        if (it->dev != dev) {
            ++it;
            continue;
        }
        if (auto published = hooks_.publish(it->message); !published) {
            failed.emplace_back(it->id, std::move(published).error());
            it = unconfirmed_.erase(it);
            continue;
        }
        ++sent;
        ++it;
    }
    return failed;
}

void ClientStateMachine::completed() {
    std::lock_guard<std::mutex> lock(mutex_);
    apply(hooks_.outstanding() ? ClientEvent::response_received : ClientEvent::last_response);
}

void ClientStateMachine::stray_response() {
    std::lock_guard<std::mutex> lock(mutex_);
    apply(ClientEvent::stray_response);
}

ClientState ClientStateMachine::state() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_;
}

std::size_t ClientStateMachine::queued() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::size_t n = 0;
    for (const auto& entry : queue_)
        if (hooks_.is_pending(entry.id)) ++n;
    return n;
}

}  // namespace nclink::client_detail
