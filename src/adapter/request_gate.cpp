#include "adapter/request_gate.hpp"

namespace nclink::adapter_detail {

RequestGate::RequestGate(std::size_t max_pending, std::size_t max_bytes, Logger logger)
    : max_pending_(max_pending == 0 ? 1 : max_pending), max_bytes_(max_bytes), logger_(std::move(logger)) {}

RequestGate::Admission RequestGate::admit(std::size_t payload_bytes) {
    Admission out;
    if (max_bytes_ != 0 && payload_bytes > max_bytes_) {
        ++oversized_;
        logger_.warn("request of {} bytes refused (404): larger than max_request_bytes {}", payload_bytes, max_bytes_);
        out.verdict = Verdict::oversized;
        return out;
    }
    std::size_t now = pending_.load();
    while (now < max_pending_ && !pending_.compare_exchange_weak(now, now + 1)) {
    }
    if (now >= max_pending_) {
        const std::uint64_t total = ++shed_;
        std::lock_guard<std::mutex> lock(burst_mutex_);
        if (!shedding_) {  // once per burst, not once per request
            shedding_ = true;
            shed_at_burst_start_ = total - 1;
            logger_.warn("{} requests pending: shedding requests until the adapter catches up (counted as 'shed')", max_pending_);
        }
        out.verdict = Verdict::shed;
        return out;
    }
    if (shedding_) {  // racy peek; decided under the lock
        std::lock_guard<std::mutex> lock(burst_mutex_);
        if (shedding_) {
            shedding_ = false;
            logger_.warn("request burst over: {} request(s) shed", shed_.load() - shed_at_burst_start_);
        }
    }
    out.verdict = Verdict::admitted;
    out.ticket = std::make_shared<Ticket>(shared_from_this());
    return out;
}

void RequestGate::release() { --pending_; }

}  // namespace nclink::adapter_detail
