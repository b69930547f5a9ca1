// The I/O loop a gateway's connections share: every call on its one thread,
// wake-ups folded, a watched socket reported, and a removed member never
// called again once remove() has returned.
#include "transport/mqtt_loop.hpp"

#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

using namespace nclink;
using namespace std::chrono_literals;

namespace {

struct Recorder : transport_detail::LoopMember {
    explicit Recorder(transport_detail::MqttLoop& l) : loop(l) {}
    transport_detail::MqttLoop& loop;
    std::atomic<int> wakes{0}, ticks{0}, reads{0}, writes{0};
    std::atomic<bool> off_thread{false};
    std::atomic<int> fd{-1};              // set by the test thread, read on the loop
    std::atomic<bool> want_write{false};  // set by the test thread, read on the loop
    std::atomic<bool> after_remove{false};
    std::atomic<bool> close_first{false};  // on_wake() closes fd before watching

    void note() {
        if (!loop.in_loop_thread()) off_thread = true;
        if (removed) after_remove = true;
    }
    void on_io(bool readable, bool writable) override {
        note();
        if (readable) {
            ++reads;
            char buf[64];
            while (::read(fd, buf, sizeof buf) > 0) {
            }
        }
        if (writable) {
            ++writes;
            want_write = false;  // one write-readiness report asked for, one taken
        }
        loop.watch(this, fd, want_write);
    }
    void on_wake() override {
        note();
        // As the MQTT library does on an error: the socket closed on the
        // loop thread, unwatched only afterwards.
        if (close_first.exchange(false)) {
            ::close(fd);
            fd = -1;
        }
        ++wakes;
        loop.watch(this, fd, want_write);
    }
    void on_tick(std::chrono::steady_clock::time_point) override {
        note();
        ++ticks;
    }
    std::atomic<bool> removed{false};
};

// A connected socket pair: the watched end turns readable when the other
// end writes, and is writable (as a broker connection is) while its buffer has room.
struct Pipe {
    int r = -1, w = -1;
    Pipe() {
        int fds[2];
        REQUIRE(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, fds) == 0);
        r = fds[0];
        w = fds[1];
    }
    ~Pipe() {
        ::close(r);
        ::close(w);
    }
};

}  // namespace

TEST_CASE("mqtt loop: wake-ups and ticks on the loop thread and a watched socket reported") {
    transport_detail::MqttLoop loop(Logger(), 10ms);
    Pipe pipe;
    Recorder member(loop);
    member.fd = pipe.r;
    loop.add(&member);
    loop.wake(&member);  // its first on_wake() watches the pipe
    REQUIRE(test::eventually([&] { return member.wakes >= 1; }, 2s));
    REQUIRE(test::eventually([&] { return member.ticks >= 3; }, 2s));

    REQUIRE(::write(pipe.w, "x", 1) == 1);
    REQUIRE(test::eventually([&] { return member.reads >= 1; }, 2s));

    // Write-readiness only while asked for: once reported, not again.
    member.want_write = true;
    loop.wake(&member);
    REQUIRE(test::eventually([&] { return member.writes >= 1; }, 2s));
    std::this_thread::sleep_for(50ms);
    CHECK(member.writes == 1);

    // A burst of wake-ups from other threads: taken on the loop thread, none lost.
    const int before = member.wakes;
    std::vector<std::thread> wakers;
    for (int t = 0; t < 4; ++t)
        wakers.emplace_back([&] {
            for (int i = 0; i < 1000; ++i) loop.wake(&member);
        });
    for (auto& t : wakers) t.join();
    REQUIRE(test::eventually([&] { return member.wakes > before; }, 2s));
    CHECK_FALSE(member.off_thread);

    loop.remove(&member);
    member.removed = true;
    loop.wake(&member);
    REQUIRE(::write(pipe.w, "y", 1) == 1);
    std::this_thread::sleep_for(100ms);  // ten ticks
    CHECK_FALSE(member.after_remove);
}

TEST_CASE("mqtt loop: an idle loop sleeps between ticks") {
    transport_detail::MqttLoop loop(Logger(), 50ms);
    std::this_thread::sleep_for(20ms);
    const auto first = loop.iterations();
    std::this_thread::sleep_for(500ms);
    // About one iteration per tick (50 ms): not a spin.
    CHECK(loop.iterations() - first <= 20);
}

TEST_CASE("mqtt loop: a socket kept open elsewhere after its member closed it reaches nobody and does not spin the loop") {
    // A child process the program starts inherits its sockets (fork): the
    // member's close then leaves the socket open in the child, and the
    // kernel keeps its epoll registration, which no fd of this process can
    // remove any more. Here a dup() stands for the child's copy.
    transport_detail::MqttLoop loop(Logger(), 50ms);
    int fds[2];
    REQUIRE(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, fds) == 0);
    Recorder member(loop);
    member.fd = fds[0];
    loop.add(&member);
    loop.wake(&member);
    REQUIRE(test::eventually([&] { return member.wakes >= 1; }, 2s));
    const int child_copy = ::dup(fds[0]);
    REQUIRE(child_copy >= 0);
    // The MQTT library closes the socket on an error; the member unwatches
    // only afterwards.
    member.close_first = true;
    loop.wake(&member);
    REQUIRE(test::eventually([&] { return member.wakes >= 2; }, 2s));
    loop.remove(&member);
    member.removed = true;

    // The left-behind registration turns readable and stays so.
    REQUIRE(::write(fds[1], "x", 1) == 1);
    const auto first = loop.iterations();
    std::this_thread::sleep_for(500ms);
    CHECK_FALSE(member.after_remove);        // before: called through a pointer to a member that had left
    CHECK(loop.iterations() - first <= 40);  // about ten ticks; before: a spin
    ::close(child_copy);
    ::close(fds[1]);
}
