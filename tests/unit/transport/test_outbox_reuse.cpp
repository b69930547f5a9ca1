// The outbox reuses a delivered message's shared state for the next push()
// when its link copies what it is handed (libmosquitto, the loopback), and
// never while anyone else may still hold it (paho keeps a reference).
// Counted by support/counting_new.hpp (the only file of test_transport that
// includes it).
#include "transport/outbox.hpp"

#include "support/counting_new.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

using namespace nclink;

namespace {

constexpr int kMessages = 1000;

// Messages built before counting starts: what is counted is the outbox's own.
std::vector<Message> messages(const std::string& text) {
    std::vector<Message> out;
    out.reserve(kMessages);
    for (int i = 0; i < kMessages; ++i) out.push_back(Message{"Sample/machine-with-a-long-id/ch_fast", text, 1, false});
    return out;
}

// A link acknowledging every message as it is handed over (as a QoS 0
// publish completes); `keep` holds on to the last one, as paho does.
struct AckingLink {
    transport_detail::Outbox* outbox = nullptr;
    bool keep = false;
    std::shared_ptr<const Message> kept;
    std::vector<std::string> payloads;
    bool send(const std::shared_ptr<const Message>& m, std::uint64_t attempt) {
        if (keep) kept = m;
        payloads.push_back(m->payload);
        outbox->delivered(attempt);
        return true;
    }
};

// An outbox on an AckingLink, its link up.
struct Rig {
    Rig(bool keep, bool link_copies)
        : outbox(
              OutboxLimits{}, [this](const std::shared_ptr<const Message>& m, std::uint64_t a) { return link.send(m, a); },
              Logger(), nullptr, link_copies) {
        link.keep = keep;
        link.outbox = &outbox;
        link.payloads.reserve(3 * kMessages);
        // The sender's first turn comes unasked, when it is added to its
        // thread. Counted before link_up(), that turn could be taken for the
        // one link_up() asks for, which would then still be pending and race
        // the first push below for the link (seen under qemu on armhf).
        REQUIRE(test::eventually([&] { return outbox.sender_wakeups() >= 1; }));
        const auto before = outbox.sender_wakeups();
        outbox.link_up();
        // link_up() wakes the sender thread: after that turn every push below
        // is handed over on this thread (nothing waits ahead of it), so the
        // link is only ever called from here. The count is read under the
        // lock the sender holds for its whole turn when nothing waits, so
        // seeing it means that turn is over.
        REQUIRE(test::eventually([&] { return outbox.sender_wakeups() > before; }));
    }
    ~Rig() { outbox.stop(); }
    AckingLink link;
    transport_detail::Outbox outbox;
};

std::uint64_t allocations_pushing(std::vector<Message>& batch, transport_detail::Outbox& outbox) {
    g_allocations.store(0);
    g_counting.store(true);
    for (auto& m : batch) (void)outbox.push(std::move(m));
    g_counting.store(false);
    return g_allocations.load();
}

}  // namespace

TEST_CASE("a link that copies: pushing a message allocates nothing of the outbox's once warm, and loses nothing") {
    Rig rig(false, true);
    auto& [link, outbox] = rig;
    auto warm = messages("{\"warm\":1}");
    auto batch = messages("{\"v\":[1.5,2.5]}");
    (void)allocations_pushing(warm, outbox);
    const std::uint64_t allocations = allocations_pushing(batch, outbox);
    // The entries' queue takes a block now and then (std::deque); before the
    // reuse each message added one allocation of its own (its shared state).
    if (NCLINK_TEST_COUNTS_ALLOCATIONS) CHECK(allocations < kMessages / 10);
    else WARN("allocations not counted under a sanitizer");
    REQUIRE(link.payloads.size() == 2 * static_cast<std::size_t>(kMessages));
    CHECK(link.payloads.back() == "{\"v\":[1.5,2.5]}");  // a reused message carries the new text
    CHECK(outbox.wait_drained(std::chrono::milliseconds(100)));
}

TEST_CASE("a link that keeps a reference: the message it holds is never reused under it") {
    Rig rig(true, true);
    auto& [link, outbox] = rig;
    REQUIRE(outbox.push(Message{"t", "first", 1, false}).ok());
    REQUIRE(link.kept);
    const Message* first = link.kept.get();
    REQUIRE(outbox.push(Message{"t", "second", 1, false}).ok());
    // The link let go of the first only when handed the second: the outbox
    // was done with it before, while the link still held it.
    CHECK(link.kept.get() != first);
    CHECK(link.kept->payload == "second");
}

TEST_CASE("a link that may keep references (paho): every message gets shared state of its own") {
    Rig rig(false, false);
    auto& [link, outbox] = rig;
    auto warm = messages("w");
    auto batch = messages("b");
    (void)allocations_pushing(warm, outbox);
    const std::uint64_t allocations = allocations_pushing(batch, outbox);
    if (NCLINK_TEST_COUNTS_ALLOCATIONS) CHECK(allocations >= kMessages);
    else WARN("allocations not counted under a sanitizer");
    CHECK(link.payloads.size() == 2 * static_cast<std::size_t>(kMessages));
}
