// The blocking form of an asynchronous client call: start it, wait for its
// completion. Shared by the per-feature client APIs (events, sampling,
// methods), whose blocking calls are this around their async ones.
#pragma once

#include <nclink/client.hpp>
#include <nclink/result.hpp>

#include <future>
#include <memory>

namespace nclink::client_detail {

/// True on the client's dispatch thread (implemented in client.cpp).
bool on_dispatch_thread(const Client::Impl& impl);

/// Runs `start(done)` and waits until `done(Result<T>)` was called. Refused on
/// the dispatch thread: the completion would come from the thread that waits.
template <class T, class Start>
Result<T> wait_for(const Client::Impl& impl, Start&& start) {
    if (on_dispatch_thread(impl)) return make_error(ErrorCode::unavailable, "blocking client call from a client callback");
    auto promise = std::make_shared<std::promise<Result<T>>>();
    auto future = promise->get_future();
    start([promise](Result<T> result) { promise->set_value(std::move(result)); });
    return future.get();
}

}  // namespace nclink::client_detail
