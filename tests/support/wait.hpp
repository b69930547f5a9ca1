// Waiting for something asynchronous in a test. The timeout is generous and
// only bounds a failing test; no test asserts how fast anything happens.
#pragma once

#include <chrono>
#include <thread>

namespace nclink::test {

template <class Predicate>
bool eventually(Predicate&& done, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!done()) {
        if (std::chrono::steady_clock::now() > deadline) return done();
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
}

}  // namespace nclink::test
