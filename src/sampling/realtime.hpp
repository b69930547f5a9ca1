// Real-time options of the sampling thread (SamplingConfig rt_priority,
// timer_slack_ns, cpu): applied by the thread to itself, each one reported
// as granted or not (logged, and in the statistics).
#pragma once

#include <nclink/feature_config.hpp>
#include <nclink/log.hpp>
#include <nclink/sampling.hpp>

namespace nclink::detail {

/// Applies the options to the calling thread. Never fails: what the system
/// refuses (EPERM without CAP_SYS_NICE or an RLIMIT_RTPRIO) is reported.
RealtimeStatus apply_realtime(const SamplingConfig& config, const Logger& logger);

}  // namespace nclink::detail
