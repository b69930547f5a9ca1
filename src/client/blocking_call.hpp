// The blocking form of an asynchronous client call: start it, wait for its
// completion. Every blocking call of the client (core requests, events,
// sampling, methods) is this around its asynchronous form.
#pragma once

#include "client/client_impl.hpp"

#include <nclink/client.hpp>
#include <nclink/result.hpp>

#include <future>
#include <memory>

namespace nclink::client_detail {

/// Runs `start(done)` and waits until `done(Result<T>)` was called. Refused on
/// the dispatch thread: the completion would come from the thread that waits.
template <class T, class Start>
Result<T> wait_for(const Client::Impl& impl, Start&& start) {
    if (impl.dispatcher.on_dispatch_thread())
        return make_error(ErrorCode::unavailable, "blocking client call from a client callback");
    auto promise = std::make_shared<std::promise<Result<T>>>();
    auto future = promise->get_future();
    start([promise](Result<T> result) { promise->set_value(std::move(result)); });
    return future.get();
}

}  // namespace nclink::client_detail
