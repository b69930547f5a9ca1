// Admission of requests: how many may wait or run at once, and how large one
// may be. A flood of requests (a broken or hostile application) must not
// queue without bound, starve sampling or leave the adapter answering a
// backlog for seconds after the flood ends: beyond `max_pending` requests
// are shed (dropped and counted; the standard gives no answer for "busy",
// and an answer would cost what shedding saves), and a payload above
// `max_bytes` is refused before it is parsed (answered 404, table 19:
// "no memory can be allotted to the function"). docs/security.md, "Floods".
#pragma once

#include <nclink/log.hpp>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>

namespace nclink::adapter_detail {

class RequestGate : public std::enable_shared_from_this<RequestGate> {
public:
    RequestGate(std::size_t max_pending, std::size_t max_bytes, Logger logger);

    /// Holds one pending slot until destroyed (shared by the tasks that may
    /// answer the request; the last one releases it). It keeps the gate
    /// alive: a task abandoned in a stuck driver may outlive the adapter.
    class Ticket {
    public:
        explicit Ticket(std::shared_ptr<RequestGate> gate) : gate_(std::move(gate)) {}
        ~Ticket() { gate_->release(); }
        Ticket(const Ticket&) = delete;
        Ticket& operator=(const Ticket&) = delete;

    private:
        std::shared_ptr<RequestGate> gate_;
    };

    enum class Verdict { admitted, oversized, shed };
    struct Admission {
        Verdict verdict = Verdict::shed;
        std::shared_ptr<Ticket> ticket;  ///< set when admitted
    };

    /// Thread: the transport callback (cheap: no parsing, no allocation but
    /// the ticket). The gate must be owned by a std::shared_ptr.
    Admission admit(std::size_t payload_bytes);

    std::uint64_t shed() const { return shed_; }
    std::uint64_t oversized() const { return oversized_; }
    std::size_t pending() const { return pending_; }
    std::size_t max_pending() const { return max_pending_; }

private:
    void release();

    const std::size_t max_pending_;
    const std::size_t max_bytes_;
    const Logger logger_;
    std::atomic<std::size_t> pending_{0};
    std::atomic<std::uint64_t> shed_{0}, oversized_{0};
    std::mutex burst_mutex_;             // the burst log below
    std::atomic<bool> shedding_{false};  // in a burst: its first shed request was logged
    std::uint64_t shed_at_burst_start_ = 0;
};

}  // namespace nclink::adapter_detail
