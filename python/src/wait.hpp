// The blocking calls of the Python client: start the asynchronous form of a
// client call, then wait for its completion with the GIL released, waking
// every 50 ms to let Python handle signals. Ctrl-C (KeyboardInterrupt)
// therefore ends the wait at once; the request itself stays with the client
// and completes (or times out) there, its answer then dropped.
#pragma once

#include <nclink/result.hpp>

#include <pybind11/pybind11.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>

namespace nclink::python {

namespace py = pybind11;

inline constexpr std::chrono::milliseconds signal_poll{50};

/// Waits (GIL released) until ready() or the Python signal handlers raise.
/// Called with the GIL held. Returns when ready() is true.
template <class Ready>
void wait_until(std::mutex& mutex, std::condition_variable& cv, Ready&& ready) {
    for (;;) {
        bool done = false;
        {
            py::gil_scoped_release nogil;
            std::unique_lock<std::mutex> lock(mutex);
            done = cv.wait_for(lock, signal_poll, ready);
        }
        if (done) return;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
}

template <class T>
struct Pending {
    std::mutex mutex;
    std::condition_variable cv;
    std::optional<Result<T>> result;
};

/// start(done) begins the call; done(Result<T>) may run on any thread, also
/// at once on this one. Called with the GIL held.
template <class T, class Start>
Result<T> wait_for_result(Start&& start) {
    auto pending = std::make_shared<Pending<T>>();
    const auto ready = [&] { return pending->result.has_value(); };
    bool done = false;
    {
        // One release of the GIL for the start and the first wait: a Query
        // round trip is well under signal_poll, and every GIL hand-over and
        // thread wake-up shows in it (docs/python.md, "Performance").
        py::gil_scoped_release nogil;
        start([pending](Result<T> result) {
            {
                std::lock_guard<std::mutex> lock(pending->mutex);
                pending->result.emplace(std::move(result));
            }
            // Notified after unlocking: the waiter wakes to a free mutex.
            pending->cv.notify_all();
        });
        std::unique_lock<std::mutex> lock(pending->mutex);
        done = pending->cv.wait_for(lock, signal_poll, ready);
    }
    if (!done) {
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        wait_until(pending->mutex, pending->cv, ready);
    }
    std::lock_guard<std::mutex> lock(pending->mutex);
    return std::move(*pending->result);
}

}  // namespace nclink::python
