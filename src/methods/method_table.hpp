// The runs of one adapter's methods: admission (max_running, 417), one
// method thread per run, the status ticker (Method/Status every
// status_period on the injected clock), and the Status/Result DTUs.
//
// Lifetime: held by shared_ptr, also by every method thread, so a thread
// abandoned in a stuck driver at shutdown never touches freed memory. After
// shutdown() the table publishes nothing (the transport and the adapter may
// be gone), whatever a late thread does.
//
// Threads: start()/running()/answer()/stats() from request workers (any
// thread); the ticker (start_ticker()) publishes periodic statuses and joins
// finished method threads: serial work (core/serial_work.hpp), a pollable of
// the gateway's shared work threads or of a host of one thread of its own,
// one turn at a time; shutdown() from the adapter's owner thread.
#pragma once

#include "core/serial_work.hpp"
#include "methods/method_run.hpp"

#include <nclink/clock.hpp>
#include <nclink/driver.hpp>
#include <nclink/dtu.hpp>
#include <nclink/feature_config.hpp>
#include <nclink/log.hpp>
#include <nclink/transport.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace nclink::methods_detail {

class MethodTable : public std::enable_shared_from_this<MethodTable> {
public:
    struct Outlet {
        std::string dev;
        Transport* transport = nullptr;  ///< Method/Status
        /// Method/Result and Method/Control/Response, mirroring the request topic.
        std::function<void(const ParsedTopic& request, const Json& reply)> respond;
    };

    /// `work`: the shared work threads the ticker runs on (gateway mode), or
    /// null for a ticker thread of its own.
    static std::shared_ptr<MethodTable> create(MethodsConfig config, Outlet outlet, Logger logger,
                                               std::shared_ptr<const Clock> clock, core_detail::PollHost* work = nullptr);
    ~MethodTable();

    /// Admits an accepted call: 417 when max_running runs are under way, 202
    /// once shutting down. Publishes Method/Status "waiting" (the acceptance,
    /// 8.2.22.3), then starts the method thread, which calls the driver.
    /// `method` carries the handle the driver's bind() gave the METHOD.
    Result<std::shared_ptr<MethodRun>> start(const PointRef& method, const ParsedTopic& call_topic, const MessageId& call_id,
                                             Json args, std::shared_ptr<Driver> driver);
    /// The runs of `method_id` not finished yet, oldest first.
    std::vector<std::shared_ptr<MethodRun>> running(const std::string& method_id) const;
    std::vector<std::shared_ptr<MethodRun>> running() const;

    /// Publishes a reply through the outlet (nothing after shutdown()).
    void answer(const ParsedTopic& request, const Json& reply);

    void start_ticker();
    /// Cancels every run, waits up to `grace` for the method threads, answers
    /// runs still stuck in the driver with Result error 202, stops publishing,
    /// joins what finished and abandons (detaches) what did not.
    void shutdown(std::chrono::milliseconds grace);

    Json stats() const;

private:
    struct Entry {
        std::shared_ptr<MethodRun> run;
        std::thread thread;
        bool done = false;
        Clock::Steady next_status{};
    };

    MethodTable(MethodsConfig config, Outlet outlet, Logger logger, std::shared_ptr<const Clock> clock,
                core_detail::PollHost* work);

    void execute(const std::shared_ptr<MethodRun>& run, const PointRef& method, Driver& driver);
    MethodResult result_of(const MethodRun& run, const Result<Json>& outcome) const;
    void finish(std::uint64_t serial);
    /// One turn of the ticker; returns when it must look again.
    core_detail::PollHost::Time tick();
    void publish_status(MethodRun& run);
    void publish_result(MethodRun& run, const MethodResult& result);

    const MethodsConfig config_;
    const Logger logger_;
    const std::shared_ptr<const Clock> clock_;
    core_detail::PollHost* const work_;

    // Publishing: once `closed_`, nothing goes out (the outlet may dangle).
    std::mutex gate_mutex_;
    bool closed_ = false;
    Outlet outlet_;

    mutable std::mutex mutex_;
    std::condition_variable finished_;  ///< a run finished (shutdown waits)
    std::map<std::uint64_t, Entry> entries_;
    std::size_t active_ = 0;
    std::uint64_t serial_ = 0;
    bool closing_ = false;
    bool ticker_stop_ = false;
    bool ticker_started_ = false;

    std::atomic<std::uint64_t> accepted_{0}, finished_count_{0}, canceled_{0}, errors_{0}, statuses_{0};
    // Started and woken under mutex_ only; last, so it stops first.
    core_detail::SerialWork ticker_;
};

}  // namespace nclink::methods_detail
