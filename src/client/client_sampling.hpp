// Dynamic sampling on the client side (8.2.17-8.2.21): the core services
// client_sampling.cpp borrows from client.cpp (which alone sees Client::Impl).
#pragma once

#include "client/pending_requests.hpp"

#include <nclink/client.hpp>

#include <memory>
#include <string>

namespace nclink::client_detail {

// ---- implemented in client.cpp, called by client_sampling.cpp (any thread)

/// Publishes a Register/Sample (resp. Unregister/Sample) request through the
/// client core, which sets @id and privateInfo and tracks the answer.
void send_sample_register(Client::Impl& impl, std::string topic, SampleRegisterRequest request,
                          std::shared_ptr<Responder> responder, const RequestOptions& options);
void send_sample_unregister(Client::Impl& impl, std::string topic, SampleUnregisterRequest request,
                            std::shared_ptr<Responder> responder, const RequestOptions& options);
/// Subscribes a sample handler to any topic filter (Sample/{dev}/{ex}/+).
Result<SubscriptionId> subscribe_sample_filter(Client::Impl& impl, std::string filter, SampleHandler handler);

}  // namespace nclink::client_detail
