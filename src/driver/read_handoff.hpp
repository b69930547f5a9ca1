// Requests' reads of a serialized driver handed to the sampling thread.
//
// A serialized driver serves the sampler and the request workers one call at
// a time. The sampler waits at most one interval for it; under normal
// scheduling a request worker that is preempted while it holds the driver
// (a request burst: the broker, the MQTT threads and the other workers on the
// same cores) keeps it for a whole scheduler slice, and every tick due
// meanwhile becomes a null row. With a fast channel (DriverRunner, "serve
// reads") the workers therefore do not take the driver for their reads: they
// queue each read here and the sampling thread runs it after its tick, in the
// time left before the next one. The sampler then never waits for a thread of
// its own process that the scheduler put aside.
//
// A job is a read cut into steps (the chunks of a long Query): whoever holds
// the job runs its steps, so the sampler can run part of it in one gap and the
// rest in the next. A job the sampler has not started within the worker's
// patience (the sampler stopped, or was itself not scheduled) is withdrawn
// and the worker runs it (the rest of it) itself, as without a handoff.
//
// Thread-safe. serve() and close() on the serving thread only.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>

namespace nclink::driver_detail {

class ReadHandoff {
public:
    using Time = std::chrono::steady_clock::time_point;
    /// Runs one step of a job under the driver's lock; true when the job is
    /// complete.
    using Step = std::function<bool()>;

    /// Request worker: hands `step` to the serving thread and waits until the
    /// job is complete (true) or was withdrawn because the serving thread did
    /// not start (or resume) it within the patience given to open() (false:
    /// the caller runs the remaining steps). False at once when nothing
    /// serves. `step` may refer to the caller's stack: it is not run after
    /// run() returned.
    bool run(const Step& step);

    /// Serving thread: from now on run() hands jobs over; a job waits at most
    /// `patience` for the serving thread before its worker takes it back.
    void open(std::chrono::nanoseconds patience);
    /// Serving thread: no more jobs; queued ones go back to their workers.
    void close();
    bool serving() const;
    /// True when a job waits (a cheap check before taking the driver).
    bool has_work() const;
    /// Serving thread, holding the driver's lock: runs queued jobs' steps
    /// while the clock is before `until` (none when it is already past).
    /// A job not complete by then goes back to the front of the queue.
    /// Returns the number of steps run.
    std::size_t serve(Time until);
    /// Serving thread, not holding the driver: waits until a job is queued
    /// (true) or the clock reaches `until` or serving ended (false).
    bool wait_for_work(Time until);
    /// Steps run by the serving thread so far.
    std::uint64_t steps_served() const;

private:
    enum class Stage { queued, running, done, withdrawn };
    struct Job {
        const Step* step = nullptr;
        Stage stage = Stage::queued;        // under mutex_
        std::atomic<bool> complete{false};  // stage done, for the worker's short spin
    };

    mutable std::mutex mutex_;
    std::condition_variable changed_;  // a job's stage moved
    std::condition_variable arrived_;  // a job was queued
    std::deque<std::shared_ptr<Job>> queue_;
    bool serving_ = false;
    std::chrono::nanoseconds patience_{0};
    std::uint64_t steps_served_ = 0;
};

}  // namespace nclink::driver_detail
