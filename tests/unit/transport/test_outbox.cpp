// The outbox's sender thread: woken when the window holds messages back,
// not by every acknowledgement (in a gateway those come on the one receive
// thread all machines share).
#include "transport/outbox.hpp"

#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

using namespace nclink;
using namespace std::chrono_literals;

namespace {

// A link that records what it was handed; acknowledgements are the test's.
struct FakeLink {
    std::mutex mutex;
    std::vector<std::pair<std::string, std::uint64_t>> sent;  // payload, attempt
    std::size_t count() {
        std::lock_guard<std::mutex> lock(mutex);
        return sent.size();
    }
    std::uint64_t attempt(std::size_t i) {
        std::lock_guard<std::mutex> lock(mutex);
        return sent.at(i).second;
    }
};

}  // namespace

TEST_CASE("acknowledgements wake the outbox's sender only when messages wait behind the window") {
    FakeLink link;
    OutboxLimits limits;
    limits.max_in_flight = 2;
    transport_detail::Outbox outbox(
        limits,
        [&](const std::shared_ptr<const Message>& m, std::uint64_t attempt) {
            std::lock_guard<std::mutex> lock(link.mutex);
            link.sent.emplace_back(m->payload, attempt);
            return true;
        },
        Logger());
    outbox.link_up();
    std::this_thread::sleep_for(20ms);  // link_up's wake-up, if the sender was already asleep
    const auto settled = outbox.sender_wakeups();

    SECTION("nothing waiting: sent on the publishing thread, acknowledged without waking the sender") {
        for (int i = 0; i < 50; ++i) {
            REQUIRE(outbox.push(Message{"t", std::to_string(i), 1, false}).ok());
            REQUIRE(link.count() == static_cast<std::size_t>(i + 1));
            outbox.delivered(link.attempt(static_cast<std::size_t>(i)));
            std::this_thread::sleep_for(200us);  // room for a woken sender to run and count
        }
        REQUIRE(outbox.wait_drained(1s));
        CHECK(outbox.sender_wakeups() == settled);
    }
    SECTION("a full window: the acknowledgement wakes the sender, which sends the next in order") {
        for (int i = 0; i < 3; ++i) REQUIRE(outbox.push(Message{"t", std::to_string(i), 1, false}).ok());
        REQUIRE(test::eventually([&] { return link.count() == 2; }));
        std::this_thread::sleep_for(20ms);
        CHECK(link.count() == 2);  // the third waits behind the window of 2
        outbox.delivered(link.attempt(0));
        REQUIRE(test::eventually([&] { return link.count() == 3; }));
        CHECK(outbox.sender_wakeups() > settled);
        {
            std::lock_guard<std::mutex> lock(link.mutex);
            CHECK(link.sent[2].first == "2");
        }
        outbox.delivered(link.attempt(1));
        outbox.delivered(link.attempt(2));
        CHECK(outbox.wait_drained(1s));
    }
}
