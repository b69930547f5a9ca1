// The responder of Client::discover(): Discovery/Response -> the device list.
#pragma once

#include "client/pending_requests.hpp"

#include <nclink/client.hpp>

#include <memory>

namespace nclink::client_detail {

std::shared_ptr<Responder> discovery_responder(Completion<std::vector<DeviceListEntry>> done);

}  // namespace nclink::client_detail
