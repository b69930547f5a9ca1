// Client: dynamic sampling (Register/Sample, Unregister/Sample). The data
// handler is subscribed to Sample/{dev}/{ex}/+ before the request goes out,
// so no DTU of the new channel can slip by; it passes on only the DTUs of the
// channel the adapter allocated (known once the response is in; response and
// data arrive in that order on the dispatch thread).
#include "client/blocking_call.hpp"
#include "client/client_impl.hpp"

#include "client/responders.hpp"  // error_from_status

#include <nclink/topics.hpp>

#include <utility>

namespace nclink {
namespace client_detail {
namespace {

class RegisterSamplingResponder final : public Responder {
public:
    explicit RegisterSamplingResponder(std::function<void(Result<std::string>)> done) : done_(std::move(done)) {}
    bool decode(std::string_view payload) override {
        auto decoded = nclink::decode<SampleRegisterResponse>(payload);
        if (!decoded) return false;
        response_ = std::move(decoded).value();
        return true;
    }
    void complete() override {
        if (!done_ || !response_) return;
        if (!response_->status.ok) {
            done_(error_from_status(response_->status));
        } else if (response_->id.empty()) {
            done_(make_error(ErrorCode::parameter_missing, "Register/Sample answered OK without a channel id"));
        } else {
            done_(response_->id);
        }
    }
    void fail(Error error) override {
        if (done_) done_(std::move(error));
    }

private:
    std::function<void(Result<std::string>)> done_;
    std::optional<SampleRegisterResponse> response_;
};

class UnregisterSamplingResponder final : public Responder {
public:
    explicit UnregisterSamplingResponder(Completion<void> done) : done_(std::move(done)) {}
    bool decode(std::string_view payload) override {
        auto decoded = nclink::decode<SampleUnregisterResponse>(payload);
        if (!decoded) return false;
        response_ = std::move(decoded).value();
        return true;
    }
    void complete() override {
        if (!done_ || !response_) return;
        if (response_->status.ok) done_(ok_result());
        else done_(error_from_status(response_->status));
    }
    void fail(Error error) override {
        if (done_) done_(std::move(error));
    }

private:
    Completion<void> done_;
    std::optional<SampleUnregisterResponse> response_;
};

bool valid_level(std::string_view level) {
    if (level.empty()) return false;
    for (char c : level)
        if (c == '/' || c == '+' || c == '#' || c == '\0') return false;
    return true;
}

}  // namespace
}  // namespace client_detail

void Client::register_sampling_async(const std::string& dev, std::vector<std::string> ids,
                                     std::chrono::milliseconds sample_interval, std::chrono::milliseconds upload_interval,
                                     SampleHandler handler, Completion<SamplingChannel> done, RequestOptions options) {
    done = impl_->stand_channel(dev, ids, sample_interval, upload_interval, handler, options,
                                std::move(done));  // client_model_cache.cpp
    if (!client_detail::valid_level(dev)) {
        if (done) done(make_error(ErrorCode::value_type, "register_sampling: bad device id"));
        return;
    }
    // Set on the dispatch thread when the response arrives; read there by
    // the filter (data of the channel comes after its response).
    auto channel = std::make_shared<std::string>();
    SampleHandler filtered = [channel, handler = std::move(handler)](const SampleDtu& dtu) {
        if (!channel->empty() && dtu.id == *channel && handler) handler(dtu);
    };
    auto subscribed = impl_->link.subscribe(topics::dynamic_sample(dev, ex_cid(), "+"), std::move(filtered));
    if (!subscribed) {
        if (done) done(std::move(subscribed).error());
        return;
    }
    const SubscriptionId subscription = subscribed.value();

    SampleRegisterRequest request;
    request.guid = dev;
    request.sample_interval = static_cast<double>(sample_interval.count());
    request.upload_interval = static_cast<double>(upload_interval.count());
    const std::string first_item = ids.empty() ? std::string() : ids.front();
    request.ids = std::move(ids);
    // The client outlives its pending requests (stop() fails them first), so
    // `this` is safe in the completion.
    auto responder = std::make_shared<client_detail::RegisterSamplingResponder>(
        [this, channel, subscription, dev, first_item, done = std::move(done)](Result<std::string> id) {
            if (!id) {
                (void)unsubscribe(subscription);
                if (done) done(std::move(id).error());
                return;
            }
            *channel = id.value();
            // Kept alive from now on (client_liveness.cpp) by querying its first item.
            impl_->keep_alive.hold(dev, "sample:" + id.value(), first_item, client_detail::KeepAlive::Clock::now());
            if (done) done(SamplingChannel{dev, std::move(id).value(), subscription});
        });
    impl_->send(TopicKind::sample_register_response, topics::sample_register_request(dev, ex_cid()), std::move(request),
                std::move(responder), options);
}

Result<Client::SamplingChannel> Client::register_sampling(const std::string& dev, std::vector<std::string> ids,
                                                          std::chrono::milliseconds sample_interval,
                                                          std::chrono::milliseconds upload_interval, SampleHandler handler,
                                                          RequestOptions options) {
    return client_detail::wait_for<SamplingChannel>(*impl_, [&](auto done) {
        register_sampling_async(dev, std::move(ids), sample_interval, upload_interval, std::move(handler), std::move(done),
                                options);
    });
}

void Client::unregister_sampling_async(const SamplingChannel& given, Completion<void> done, RequestOptions options) {
    const SamplingChannel channel = impl_->unstand_channel(given);  // the channel after a re-registration
    if (channel.subscription != 0) (void)unsubscribe(channel.subscription);
    impl_->keep_alive.release(channel.dev, "sample:" + channel.id);
    if (!client_detail::valid_level(channel.dev)) {
        if (done) done(make_error(ErrorCode::value_type, "unregister_sampling: bad device id"));
        return;
    }
    SampleUnregisterRequest request;
    request.guid = channel.dev;
    request.id = channel.id;
    impl_->send(TopicKind::sample_unregister_response, topics::sample_unregister_request(channel.dev, ex_cid()),
                std::move(request), std::make_shared<client_detail::UnregisterSamplingResponder>(std::move(done)), options);
}

Result<void> Client::unregister_sampling(const SamplingChannel& channel, RequestOptions options) {
    return client_detail::wait_for<void>(*impl_, [&](auto done) { unregister_sampling_async(channel, std::move(done), options); });
}

bool Client::is_replayed(const SampleDtu& dtu) noexcept {
    if (!dtu.private_info || !dtu.private_info->is_object()) return false;
    auto flag = dtu.private_info->find("replayed");
    return flag != dtu.private_info->end() && flag->is_boolean() && flag->get<bool>();
}

}  // namespace nclink
