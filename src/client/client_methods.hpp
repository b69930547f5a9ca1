// Methods on the client side (8.2.22-8.2.26): what client.cpp routes to
// client_methods.cpp, and the few core services client_methods.cpp borrows
// from client.cpp (which alone sees Client::Impl).
#pragma once

#include "client/pending_requests.hpp"

#include <nclink/client.hpp>

#include <chrono>
#include <memory>
#include <string>

namespace nclink::client_detail {

// ---- implemented in client_methods.cpp, called by client.cpp (dispatch thread)

/// A Method/Status: handed to the on_status of the call with its @id (if it
/// is still pending), whose silence timeout it restarts. Others are dropped.
/// (The pending table may hold the call's responder wrapped: the Status goes
/// through Responder::decode(), which a call's responder recognizes.)
void handle_method_status(PendingRequests& pending, const std::string& payload, const Logger& log);

// ---- implemented in client.cpp, called by client_methods.cpp (any thread)

/// Publishes a Method/Call (answered by Method/Result) or a Method/Control
/// request (answered by Method/Control/Response) through the client core,
/// which sets @id and privateInfo and tracks the answer.
void send_method_call(Client::Impl& impl, std::string topic, MethodCall request, std::shared_ptr<Responder> responder,
                      const RequestOptions& options);
void send_method_control(Client::Impl& impl, std::string topic, MethodControlRequest request,
                         std::shared_ptr<Responder> responder, const RequestOptions& options);
std::chrono::milliseconds default_timeout(const Client::Impl& impl);
PendingRequests& pending_requests(Client::Impl& impl);

}  // namespace nclink::client_detail
