// Client: Method/Call with progress and result, Method/Control. A call is a
// pending request answered by its Method/Result (@id); every Method/Status
// of it reaches on_status and restarts its timeout, so a method running for
// minutes keeps its call alive while the adapter reports it.
#include "client/blocking_call.hpp"
#include "client/client_impl.hpp"
#include "client/client_methods.hpp"

#include "client/responders.hpp"

#include <nclink/topics.hpp>

#include <utility>

namespace nclink {
namespace client_detail {
namespace {

template <class F>
void guarded(const Logger& log, F&& f) noexcept {
    try {
        f();
    } catch (const std::exception& e) {
        log.error("client: a method callback threw: {}", e.what());
    } catch (...) {
        log.error("client: a method callback threw");
    }
}

// Answered by the Method/Result; a Method/Status of the call reaches it
// through decode() too (a Status has no "result"): it goes to on_status, the
// call's deadline moves to now + timeout, and decode() says "not the answer".
class MethodCallResponder final : public Responder {
public:
    MethodCallResponder(std::function<void(const MethodStatus&)> on_status, Completion<MethodResult> done,
                        std::chrono::milliseconds timeout, PendingRequests& pending)
        : on_status_(std::move(on_status)), done_(std::move(done)), timeout_(timeout), pending_(pending) {}

    bool decode(std::string_view payload) override {
        if (auto result = nclink::decode<MethodResult>(payload)) {
            result_ = std::move(result).value();
            return true;
        }
        if (auto status = nclink::decode<MethodStatus>(payload)) {
            restart_timeout(*status);
            if (on_status_) on_status_(*status);
        }
        return false;
    }
    void complete() override {
        if (done_ && result_) done_(std::move(*result_));
    }
    void fail(Error error) override {
        if (done_) done_(std::move(error));
    }

private:
    // Re-files the pending call with a new deadline. Safe: answers and
    // expiries are handled on this (the dispatch) thread only.
    void restart_timeout(const MethodStatus& status) {
        if (!status.msg_id) return;
        const std::string key = status.msg_id->is_string() ? status.msg_id->get<std::string>() : status.msg_id->dump();
        if (auto taken = pending_.take(key)) {
            taken->deadline = Clock::now() + timeout_;
            (void)pending_.add(std::move(*taken));  // false: stopping; the client's fail-all answers the call
        }
    }

    std::function<void(const MethodStatus&)> on_status_;
    Completion<MethodResult> done_;
    const std::chrono::milliseconds timeout_;
    PendingRequests& pending_;
    std::optional<MethodResult> result_;
};

class ControlResponder final : public Responder {
public:
    explicit ControlResponder(Completion<void> done) : done_(std::move(done)) {}
    bool decode(std::string_view payload) override {
        auto decoded = nclink::decode<MethodControlResponse>(payload);
        if (!decoded) return false;
        response_ = std::move(decoded).value();
        return true;
    }
    void complete() override {
        if (!done_ || !response_) return;
        if (response_->status.ok) {
            done_(ok_result());
            return;
        }
        Error error = error_from_status(response_->status);
        const auto& info = response_->private_info;  // the adapter's detail (docs/methods.md)
        if (info && info->is_object() && info->contains("message") && (*info)["message"].is_string())
            error.message += " (" + (*info)["message"].get<std::string>() + ")";
        done_(std::move(error));
    }
    void fail(Error error) override {
        if (done_) done_(std::move(error));
    }

private:
    Completion<void> done_;
    std::optional<MethodControlResponse> response_;
};

}  // namespace

void handle_method_status(PendingRequests& pending, const std::string& payload, const Logger& log) {
    const MessageId msg_id = peek_message_id(payload);
    if (!msg_id) return;
    const std::string key = msg_id->is_string() ? msg_id->get<std::string>() : msg_id->dump();
    TopicKind kind = TopicKind::method_result;
    const auto responder = pending.peek(key, &kind);
    if (!responder || kind != TopicKind::method_result) return;  // not a call of ours, or already answered
    guarded(log, [&] { (void)responder->decode(payload); });
}

}  // namespace client_detail

std::string_view Client::method_action_name(MethodAction action) noexcept {
    switch (action) {
        case Client::MethodAction::stop: return "stop";
        case Client::MethodAction::resume: return "resume";
        case Client::MethodAction::cancel: return "cancel";
    }
    return "?";
}

void Client::call_method_async(const std::string& dev, const std::string& method_id, Json args,
                               std::function<void(const MethodStatus&)> on_status, Completion<MethodResult> done,
                               RequestOptions options) {
    MethodCall request;
    request.guid = dev;
    request.id = method_id;
    if (!args.is_null()) request.args = std::move(args);
    const auto timeout = options.timeout.value_or(impl_->options.default_timeout);
    auto responder =
        std::make_shared<client_detail::MethodCallResponder>(std::move(on_status), std::move(done), timeout, impl_->pending);
    impl_->send(TopicKind::method_result, topics::method_call(dev, ex_cid()), std::move(request), std::move(responder), options);
}

Result<MethodResult> Client::call_method(const std::string& dev, const std::string& method_id, Json args,
                                         std::function<void(const MethodStatus&)> on_status, RequestOptions options) {
    return client_detail::wait_for<MethodResult>(*impl_, [&](auto done) {
        call_method_async(dev, method_id, std::move(args), std::move(on_status), std::move(done), options);
    });
}

void Client::control_method_async(const std::string& dev, const std::string& method_id, MethodAction action,
                                  Completion<void> done, RequestOptions options) {
    MethodControlRequest request;
    request.guid = dev;
    request.id = method_id;
    request.action = std::string(method_action_name(action));
    impl_->send(TopicKind::method_control_response, topics::method_control_request(dev, ex_cid()), std::move(request),
                std::make_shared<client_detail::ControlResponder>(std::move(done)), options);
}

Result<void> Client::control_method(const std::string& dev, const std::string& method_id, MethodAction action,
                                    RequestOptions options) {
    return client_detail::wait_for<void>(
        *impl_, [&](auto done) { control_method_async(dev, method_id, action, std::move(done), options); });
}

}  // namespace nclink
