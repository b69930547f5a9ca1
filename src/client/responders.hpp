// Typed responders: decode the response DTU of each request kind and turn it
// into what the caller of Client gets (results, or an Error value).
#pragma once

#include "client/pending_requests.hpp"

#include <nclink/client.hpp>

#include <memory>
#include <optional>
#include <string_view>

namespace nclink::client_detail {

/// The Error of an NG status: DEV_UNREACHABLE -> unavailable, otherwise the
/// table-19 code of `error` (or of `reason`), with the reason in the message.
Error error_from_status(const ResponseStatus& status);

/// An agent's DEV_UNREACHABLE answer (tables 53/54; also any response whose
/// top-level code is NG with that reason). std::nullopt for anything else.
std::optional<Error> unreachable_error(std::string_view payload);

std::shared_ptr<Responder> register_responder(Completion<RegisterOutcome> done);
std::shared_ptr<Responder> probe_responder(Completion<Json> done);
std::shared_ptr<Responder> probe_set_responder(Completion<void> done);
std::shared_ptr<Responder> query_responder(Completion<std::vector<QueryResult>> done);
std::shared_ptr<Responder> set_responder(Completion<std::vector<SetResult>> done);

}  // namespace nclink::client_detail
