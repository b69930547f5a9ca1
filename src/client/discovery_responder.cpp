#include "client/discovery_responder.hpp"

#include "client/responders.hpp"  // error_from_status

#include <optional>

namespace nclink::client_detail {
namespace {

class DiscoveryResponder final : public Responder {
public:
    explicit DiscoveryResponder(Completion<std::vector<DeviceListEntry>> done) : done_(std::move(done)) {}
    bool decode(std::string_view payload) override {
        auto decoded = nclink::decode<DiscoveryResponse>(payload);
        if (!decoded) return false;
        response_ = std::move(decoded).value();
        return true;
    }
    void complete() override {
        if (!done_ || !response_) return;
        if (!response_->status.ok) return done_(error_from_status(response_->status));
        done_(response_->device_list.value_or(std::vector<DeviceListEntry>{}));
    }
    void fail(Error error) override {
        if (done_) done_(std::move(error));
    }

private:
    Completion<std::vector<DeviceListEntry>> done_;
    std::optional<DiscoveryResponse> response_;
};

}  // namespace

std::shared_ptr<Responder> discovery_responder(Completion<std::vector<DeviceListEntry>> done) {
    return std::make_shared<DiscoveryResponder>(std::move(done));
}

}  // namespace nclink::client_detail
