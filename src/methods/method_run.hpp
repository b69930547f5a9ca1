// One accepted Method/Call while it runs: the MethodControl the driver gets
// (progress, cancellation, the pause checkpoint) and the state Method/Status
// reports. Thread-safe: the method thread calls the MethodControl side,
// request workers the control side, the status ticker snapshot().
//
// Phases (8.2.23 `status`): waiting (accepted, the driver not called yet) ->
// executing -> stopped (only while the method thread is blocked in
// checkpoint() after a "stop"; a driver that never calls checkpoint() keeps
// executing) -> executing after "resume". "cancel" wakes a paused method:
// checkpoint() returns false and cancelled() is true from then on. A run
// cancelled while still waiting is never called: it goes to sleep ("not
// called", 8.2.23), and its Result says canceled.
#pragma once

#include <nclink/driver.hpp>
#include <nclink/dtu_common.hpp>
#include <nclink/topics.hpp>

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>

namespace nclink::methods_detail {

enum class RunPhase { waiting, executing, stopped, sleep };

/// "waiting", "executing", "stopped", "sleep" (8.2.23).
const char* to_string(RunPhase phase) noexcept;

class MethodRun final : public MethodControl {
public:
    struct Snapshot {
        RunPhase phase = RunPhase::waiting;
        std::optional<double> progress;  ///< percent, once the driver reported some
        bool pause_requested = false;
        bool cancel_requested = false;
    };
    /// Called (outside the run's lock) on every phase change, on the thread
    /// that made it: the method thread for executing/stopped.
    using PhaseListener = std::function<void(MethodRun&)>;

    MethodRun(std::uint64_t serial, std::string method_id, ParsedTopic call_topic, MessageId call_id, Json args);

    void set_phase_listener(PhaseListener listener) { listener_ = std::move(listener); }

    // ---- MethodControl (the method thread)
    void progress(double percent) override;
    bool cancelled() const override;
    bool checkpoint() override;

    // ---- lifecycle (the method thread)
    /// The driver is about to be called: waiting -> executing, true. A run
    /// cancelled while waiting goes to sleep instead and answers false: the
    /// driver is not called.
    bool begin();

    // ---- control (any thread). Idempotent: stopping a paused run, resuming
    // a running one, cancelling twice change nothing and are not errors.
    void request_stop();
    void request_resume();
    void request_cancel();

    Snapshot snapshot() const;

    const std::uint64_t serial;
    const std::string method_id;
    const ParsedTopic call_topic;  ///< the Method/Call topic (dev, ex) the answers mirror
    const MessageId call_id;       ///< the call's @id, echoed by Status and Result
    const Json args;               ///< as checked (defaults filled in)
    /// Orders this run's Status and Result DTUs: a Status is never published
    /// after the Result. Held while publishing.
    std::mutex publish_mutex;
    bool result_published = false;  ///< guarded by publish_mutex
    /// Whether the Result is out: the run is over for the applications even
    /// while its thread is still being wound down.
    bool answered() {
        std::lock_guard<std::mutex> lock(publish_mutex);
        return result_published;
    }

private:
    void changed();

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    Snapshot state_;
    PhaseListener listener_;
};

}  // namespace nclink::methods_detail
