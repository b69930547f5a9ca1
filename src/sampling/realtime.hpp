// Real-time options of the sampling thread (SamplingConfig rt_priority,
// timer_slack_ns, cpu, slice_us): applied by the thread to itself, each one
// reported as granted or not (logged, and in the statistics).
#pragma once

#include <nclink/feature_config.hpp>
#include <nclink/log.hpp>
#include <nclink/sampling.hpp>

#include <cstdint>

namespace nclink::sampling_detail {

/// Applies the options to the calling thread. Never fails: what the system
/// refuses (EPERM without CAP_SYS_NICE or an RLIMIT_RTPRIO) is reported.
RealtimeStatus apply_realtime(const SamplingConfig& config, const Logger& logger);

/// The calling thread's time slice under a fair policy (sched_getattr's
/// sched_runtime), 0 where the kernel does not report one (before 6.12).
std::uint64_t thread_slice_ns();

}  // namespace nclink::sampling_detail
