// The sampling thread's scheduling options, applied to a thread of the test
// as the sampling thread applies them to itself.
#include "sampling/realtime.hpp"

#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <cstdio>
#include <thread>

using namespace nclink;
using namespace nclink::sampling_detail;

namespace {

// The per-task slice of a fair task came with Linux 6.12.
bool kernel_has_slices() {
    utsname u{};
    if (uname(&u) != 0) return false;
    int major = 0, minor = 0;
    if (std::sscanf(u.release, "%d.%d", &major, &minor) != 2) return false;
    return major > 6 || (major == 6 && minor >= 12);
}

int thread_nice() { return getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid))); }

template <typename F>
void on_new_thread(F f) {
    std::thread t(f);
    t.join();
}

}  // namespace

TEST_CASE("the sampling thread asks for a 100 us slice by default and keeps its nice value") {
    on_new_thread([] {
        // Raising one's own nice value needs no privilege.
        REQUIRE(setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 3) == 0);
        const RealtimeStatus status = apply_realtime(SamplingConfig{}, Logger{});
        CHECK(status.slice_us == 100);
        CHECK(thread_nice() == 3);  // sched_setattr also sets nice: it must be carried over
        if (kernel_has_slices()) {
            CHECK(status.slice_granted);
            CHECK(thread_slice_ns() == 100'000);
        } else {
            CHECK_FALSE(status.slice_granted);
        }
    });
}

TEST_CASE("slice_us 0 leaves the kernel's slice alone") {
    on_new_thread([] {
        const auto before = thread_slice_ns();
        SamplingConfig config;
        config.slice_us = 0;
        const RealtimeStatus status = apply_realtime(config, Logger{});
        CHECK(status.slice_us == 0);
        CHECK_FALSE(status.slice_granted);
        CHECK(thread_slice_ns() == before);
        if (kernel_has_slices()) CHECK(before != 100'000);
    });
}

TEST_CASE("a slice is asked for only when SCHED_FIFO was not granted") {
    on_new_thread([] {
        SamplingConfig config;
        config.rt_priority = 1;
        config.slice_us = 200;
        const RealtimeStatus status = apply_realtime(config, Logger{});
        if (status.fifo_granted) {
            // A FIFO thread runs until it sleeps: no slice to ask for.
            CHECK(status.slice_us == 0);
            CHECK_FALSE(status.slice_granted);
        } else {
            CHECK(status.slice_us == 200);
            CHECK(status.slice_granted == kernel_has_slices());
        }
    });
}
