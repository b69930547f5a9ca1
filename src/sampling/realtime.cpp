#include "sampling/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>

#include <cerrno>
#include <cstring>

namespace nclink::detail {

RealtimeStatus apply_realtime(const SamplingConfig& config, const Logger& logger) {
    RealtimeStatus status;
    status.fifo_priority = config.rt_priority;
    status.timer_slack_ns = config.timer_slack_ns;
    status.cpu = config.cpu;
    if (config.timer_slack_ns > 0) {
        status.timer_slack_granted = prctl(PR_SET_TIMERSLACK, static_cast<unsigned long>(config.timer_slack_ns), 0, 0, 0) == 0;
        if (status.timer_slack_granted)
            logger.info("sampling thread: timer slack {} ns", config.timer_slack_ns);
        else
            logger.warn("sampling thread: timer slack {} ns refused: {}", config.timer_slack_ns, std::strerror(errno));
    }
    if (config.cpu >= 0) {
        cpu_set_t set;
        CPU_ZERO(&set);
        CPU_SET(config.cpu, &set);
        const int rc = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
        status.cpu_granted = rc == 0;
        if (status.cpu_granted)
            logger.info("sampling thread: pinned to CPU {}", config.cpu);
        else
            logger.warn("sampling thread: pinning to CPU {} refused: {}", config.cpu, std::strerror(rc));
    }
    if (config.rt_priority > 0) {
        sched_param param{};
        param.sched_priority = config.rt_priority;
        const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
        status.fifo_granted = rc == 0;
        if (status.fifo_granted)
            logger.info("sampling thread: SCHED_FIFO priority {}", config.rt_priority);
        else
            logger.warn("sampling thread: SCHED_FIFO priority {} refused: {} (needs CAP_SYS_NICE or RLIMIT_RTPRIO)",
                        config.rt_priority, std::strerror(rc));
    }
    return status;
}

}  // namespace nclink::detail
