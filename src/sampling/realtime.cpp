#include "sampling/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace nclink::sampling_detail {

namespace {

// struct sched_attr of sched_setattr(2), declared here because glibc 2.36
// has neither the struct nor a wrapper (and <linux/sched/types.h> clashes
// with <sched.h>). Layout of SCHED_ATTR_SIZE_VER1 (56 bytes).
struct SchedAttr {
    std::uint32_t size = sizeof(SchedAttr);
    std::uint32_t policy = 0;
    std::uint64_t flags = 0;
    std::int32_t nice = 0;
    std::uint32_t priority = 0;
    std::uint64_t runtime = 0;
    std::uint64_t deadline = 0;
    std::uint64_t period = 0;
    std::uint32_t util_min = 0;
    std::uint32_t util_max = 0;
};

bool get_attr(SchedAttr& attr) { return syscall(SYS_sched_getattr, 0, &attr, sizeof(attr), 0) == 0; }

// EEVDF (Linux 6.6) gives every fair task a virtual deadline one slice after
// it becomes eligible; since 6.12 a task may ask for its own slice through
// sched_runtime, and a waking task with a shorter slice preempts the running
// one instead of waiting for it to use up its own. The sampling thread runs
// microseconds per tick, so a short slice costs it nothing and keeps a tick
// from starting a millisecond late behind the broker or the uploader. Policy
// and nice value are kept as they are; older kernels ignore sched_runtime for
// fair tasks, which the read-back shows.
bool set_slice(int slice_us) {
    SchedAttr attr;
    if (!get_attr(attr)) return false;
    if (attr.policy != SCHED_OTHER && attr.policy != SCHED_BATCH) return false;
    const std::uint64_t wanted = static_cast<std::uint64_t>(slice_us) * 1000;
    SchedAttr next;
    next.policy = attr.policy;
    next.nice = attr.nice;
    next.runtime = wanted;
    if (syscall(SYS_sched_setattr, 0, &next, 0) != 0) return false;
    return thread_slice_ns() == wanted;
}

}  // namespace

std::uint64_t thread_slice_ns() {
    SchedAttr attr;
    return get_attr(attr) ? attr.runtime : 0;
}

RealtimeStatus apply_realtime(const SamplingConfig& config, const Logger& logger) {
    RealtimeStatus status;
    status.fifo_priority = config.rt_priority;
    status.timer_slack_ns = config.timer_slack_ns;
    status.cpu = config.cpu;
    if (config.timer_slack_ns > 0) {
        status.timer_slack_granted = prctl(PR_SET_TIMERSLACK, static_cast<unsigned long>(config.timer_slack_ns), 0, 0, 0) == 0;
        if (status.timer_slack_granted) logger.info("sampling thread: timer slack {} ns", config.timer_slack_ns);
        else logger.warn("sampling thread: timer slack {} ns refused: {}", config.timer_slack_ns, std::strerror(errno));
    }
    if (config.cpu >= 0) {
        cpu_set_t set;
        CPU_ZERO(&set);
        CPU_SET(config.cpu, &set);
        const int rc = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
        status.cpu_granted = rc == 0;
        if (status.cpu_granted) logger.info("sampling thread: pinned to CPU {}", config.cpu);
        else logger.warn("sampling thread: pinning to CPU {} refused: {}", config.cpu, std::strerror(rc));
    }
    if (config.rt_priority > 0) {
        sched_param param{};
        param.sched_priority = config.rt_priority;
        const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
        status.fifo_granted = rc == 0;
        if (status.fifo_granted) logger.info("sampling thread: SCHED_FIFO priority {}", config.rt_priority);
        else
            logger.warn("sampling thread: SCHED_FIFO priority {} refused: {} (needs CAP_SYS_NICE or RLIMIT_RTPRIO)",
                        config.rt_priority, std::strerror(rc));
    }
    // Under SCHED_FIFO the slice means nothing: the thread runs until it sleeps.
    if (config.slice_us > 0 && !status.fifo_granted) {
        status.slice_us = config.slice_us;
        status.slice_granted = set_slice(config.slice_us);
        if (status.slice_granted) logger.debug("sampling thread: time slice {} us", config.slice_us);
        else logger.info("sampling thread: time slice {} us not set (needs Linux >= 6.12 and a fair policy)", config.slice_us);
    }
    return status;
}

}  // namespace nclink::sampling_detail
