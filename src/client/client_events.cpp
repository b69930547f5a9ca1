// Client: event registrations and the delivery of Event DTUs (docs/events.md).
#include "client/blocking_call.hpp"
#include "client/client_impl.hpp"
#include "client/client_events.hpp"

#include "client/responders.hpp"

#include <nclink/topics.hpp>

#include <cctype>
#include <exception>

namespace nclink {
namespace client_detail {

void EventRoutes::add(const std::string& dev, const std::string& event_id, Client::EventHandler handler, bool once) {
    std::lock_guard<std::mutex> lock(mutex_);
    routes_[{dev, event_id}] = Route{std::make_shared<const Client::EventHandler>(std::move(handler)), once};
}

bool EventRoutes::remove(const std::string& dev, const std::string& event_id) {
    std::lock_guard<std::mutex> lock(mutex_);
    return routes_.erase({dev, event_id}) != 0;
}

std::size_t EventRoutes::size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return routes_.size();
}

EventRoutes::Delivery EventRoutes::deliver(const std::string& dev, const std::string& payload, const Logger& log) {
    auto dtu = decode<EventData>(std::string_view(payload));
    if (!dtu) return Delivery::malformed;
    if (dtu->guid.empty()) dtu->guid = dev;
    std::shared_ptr<const Client::EventHandler> handler;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = routes_.find({dev, dtu->id});
        if (it == routes_.end()) return Delivery::unknown_event;
        handler = it->second.handler;
        if (it->second.once) routes_.erase(it);
    }
    if (handler && *handler) {
        try {
            (*handler)(*dtu);
        } catch (const std::exception& e) {
            log.error("client: an event callback threw: {}", e.what());
        } catch (...) {
            log.error("client: an event callback threw");
        }
    }
    return Delivery::delivered;
}

namespace {

// Register/Event/Response: on OK the route is in place before `done` runs,
// and before any Event of the registration is handled (same thread, in order).
class RegisterEventResponder final : public Responder {
public:
    RegisterEventResponder(EventRoutes& routes, std::string dev, bool once, Client::EventHandler handler,
                           Completion<std::string> done)
        : routes_(routes), dev_(std::move(dev)), once_(once), handler_(std::move(handler)), done_(std::move(done)) {}

    bool decode(std::string_view payload) override {
        auto decoded = nclink::decode<EventRegisterResponse>(payload);
        if (!decoded) return false;
        response_ = std::move(decoded).value();
        return true;
    }
    void complete() override {
        if (!response_) return;
        Result<std::string> result = make_error(ErrorCode::parameter_missing, "Register/Event response without an event id");
        if (!response_->status.ok) result = error_from_status(response_->status);
        else if (!response_->id.empty()) {
            routes_.add(dev_, response_->id, std::move(handler_), once_);
            result = response_->id;
        }
        if (done_) done_(std::move(result));
    }
    void fail(Error error) override {
        if (done_) done_(std::move(error));
    }

private:
    EventRoutes& routes_;
    const std::string dev_;
    const bool once_;
    Client::EventHandler handler_;
    Completion<std::string> done_;
    std::optional<EventRegisterResponse> response_;
};

class UnregisterEventResponder final : public Responder {
public:
    explicit UnregisterEventResponder(Completion<void> done) : done_(std::move(done)) {}
    bool decode(std::string_view payload) override {
        auto decoded = nclink::decode<EventUnregisterResponse>(payload);
        if (!decoded) return false;
        status_ = decoded->status;
        return true;
    }
    void complete() override {
        if (!done_ || !status_) return;
        if (status_->ok) done_(ok_result());
        else done_(error_from_status(*status_));
    }
    void fail(Error error) override {
        if (done_) done_(std::move(error));
    }

private:
    Completion<void> done_;
    std::optional<ResponseStatus> status_;
};

}  // namespace
}  // namespace client_detail

void Client::register_event_async(const std::string& dev, EventRegistration registration, EventHandler on_event,
                                  Completion<std::string> done, RequestOptions options) {
    done = impl_->stand_event(dev, registration, on_event, options, std::move(done));  // client_model_cache.cpp
    EventRegisterRequest request;
    request.guid = dev;
    request.id = std::move(registration.id);
    request.key = std::move(registration.key);
    request.index = registration.index;
    if (!registration.filters.empty()) request.filters = std::move(registration.filters);
    request.trigger_type = std::move(registration.trigger);
    std::string trigger = request.trigger_type;
    for (auto& c : trigger) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const bool once = trigger == "once";  // the adapter releases it after its first event
    // On OK the registration is kept alive (client_liveness.cpp) by querying its item.
    Completion<std::string> kept = [impl = impl_.get(), dev, item = request.id, done = std::move(done)](Result<std::string> id) {
        if (id) impl->keep_alive.hold(dev, "event:" + id.value(), item, client_detail::KeepAlive::Clock::now());
        if (done) done(std::move(id));
    };
    auto responder = std::make_shared<client_detail::RegisterEventResponder>(impl_->event_routes, dev, once, std::move(on_event),
                                                                             std::move(kept));
    impl_->send(TopicKind::event_register_response, topics::event_register_request(dev, ex_cid()), std::move(request),
                std::move(responder), options);
}

Result<std::string> Client::register_event(const std::string& dev, EventRegistration registration, EventHandler on_event,
                                           RequestOptions options) {
    return client_detail::wait_for<std::string>(*impl_, [&](auto done) {
        register_event_async(dev, std::move(registration), std::move(on_event), std::move(done), options);
    });
}

void Client::unregister_event_async(const std::string& dev, const std::string& given_id, Completion<void> done,
                                    RequestOptions options) {
    const std::string event_id = impl_->unstand_event(dev, given_id);  // the id after a re-registration
    // No callback after this call, whatever the adapter answers.
    impl_->event_routes.remove(dev, event_id);
    impl_->keep_alive.release(dev, "event:" + event_id);
    EventUnregisterRequest request;
    request.guid = dev;
    request.id = event_id;
    impl_->send(TopicKind::event_unregister_response, topics::event_unregister_request(dev, ex_cid()), std::move(request),
                std::make_shared<client_detail::UnregisterEventResponder>(std::move(done)), options);
}

Result<void> Client::unregister_event(const std::string& dev, const std::string& event_id, RequestOptions options) {
    return client_detail::wait_for<void>(*impl_,
                                         [&](auto done) { unregister_event_async(dev, event_id, std::move(done), options); });
}

std::size_t Client::event_registrations() const { return impl_->event_routes.size(); }

}  // namespace nclink
