// Collects what a transport delivers (messages and link states), for tests.
#pragma once

#include <nclink/transport.hpp>

#include <chrono>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::test {

struct Inbox {
    std::mutex mutex;
    std::vector<Message> messages;
    std::vector<LinkState> states;
    Transport* attached = nullptr;

    Inbox() = default;
    Inbox(const Inbox&) = delete;
    Inbox& operator=(const Inbox&) = delete;
    // The transport's handlers write into this inbox: stop the transport (it
    // waits for a running callback) before the inbox goes, whatever the
    // declaration order in the test. stop() is idempotent.
    ~Inbox() {
        if (attached) attached->stop(std::chrono::milliseconds(0));
    }

    void attach(Transport& t) {
        attached = &t;
        t.set_message_handler([this](const Message& m) {
            std::lock_guard<std::mutex> lock(mutex);
            messages.push_back(m);
        });
        t.set_state_handler([this](LinkState s, std::string_view) {
            std::lock_guard<std::mutex> lock(mutex);
            states.push_back(s);
        });
    }
    std::size_t count() {
        std::lock_guard<std::mutex> lock(mutex);
        return messages.size();
    }
    std::vector<std::string> payloads() {
        std::lock_guard<std::mutex> lock(mutex);
        std::vector<std::string> out;
        for (const auto& m : messages) out.push_back(m.payload);
        return out;
    }
};

}  // namespace nclink::test
