// Methods on the client side (8.2.22-8.2.26): what the client's engine
// routes to client_methods.cpp.
#pragma once

#include "client/pending_requests.hpp"

#include <nclink/client.hpp>

#include <string>

namespace nclink::client_detail {

// ---- implemented in client_methods.cpp, called by client.cpp (dispatch thread)

/// A Method/Status: handed to the on_status of the call with its @id (if it
/// is still pending), whose silence timeout it restarts. Others are dropped.
/// (The pending table may hold the call's responder wrapped: the Status goes
/// through Responder::decode(), which a call's responder recognizes.)
void handle_method_status(PendingRequests& pending, const std::string& payload, const Logger& log);

}  // namespace nclink::client_detail
