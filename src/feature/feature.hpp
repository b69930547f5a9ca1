// The feature contract: what a feature that runs beside Query/Set/Probe
// (sampling, events, methods) needs from the terminal that hosts it, and what
// the host may ask of the feature. Features stand on this contract only and
// never include adapter/: the adapter implements FeatureHost and composes the
// features (docs/architecture.md).
//
// Threads (who calls what):
// - start()/stop(): the host's owner thread, in Adapter::start()/stop()
//   (stop in reverse order of start). stop() joins every thread it started.
// - handle(): a request worker (several may run at once: be thread-safe).
// - on_model(): the request worker that installed a Probe/Set model.
// - on_link(): the transport's callback thread: never block there.
// - on_application_gone(): the host's housekeeping thread, or the transport
//   callback thread for a Notify/State offline: do not block long.
// - on_value(): the thread of whoever called Adapter::notify_value (a driver
//   thread, firmware): never block there.
// - stats(): any thread.
#pragma once

#include "core/poll_host.hpp"
#include "driver/driver_runner.hpp"
#include "feature/model_state.hpp"
#include "feature/sample_tap.hpp"
#include "feature/value_guard.hpp"

#include <nclink/clock.hpp>
#include <nclink/dtu.hpp>
#include <nclink/log.hpp>
#include <nclink/topics.hpp>
#include <nclink/transport.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nclink::feature_detail {

/// What the host lends its features. Every member outlives the features.
struct FeatureHost {
    const std::string& dev;  ///< the terminal id of the host (dev_uuid)
    const Logger& logger;
    std::shared_ptr<const Clock> clock;   ///< injected in tests (ManualClock)
    Transport& transport;                 ///< publish() is thread-safe; buffered while offline
    driver_detail::DriverRunner& driver;  ///< deadlines, serialization
    const ModelSource& model;             ///< model.current(): the snapshot to serve
    SampleTap& sample_tap;                ///< sampled rows, for events watching the sample stream
    ValueGuard& values;                   ///< chapter 7 checks of every value a driver returns
    /// Publishes a reply on the response topic(s) mirroring `request` (both
    /// spellings where docs/wire.md says so) and updates the host's state.
    std::function<void(const ParsedTopic& request, const Json& reply)> respond;
    /// A fresh @id for DTUs the host originates.
    std::function<std::string()> next_msg_id;

    // --- settings the host shares with every feature. A feature's own
    // section of the configuration (SamplingConfig, ...) is handed to its
    // factory by whoever composes the features, never held here: adding a
    // feature does not touch the host.
    const std::string& persistence_dir;  ///< "" = nothing persisted
    std::chrono::milliseconds driver_timeout;
    /// Gateway mode: shared timer threads for periodic work (e.g. the
    /// sampling scheduler and uploader); null: each feature runs its own threads.
    core_detail::PollHost* timers = nullptr;
    /// Gateway mode: where in their interval's grid this adapter's periodic
    /// ticks fall, a fraction in [0, 1) (EngineDeps::phase); 0 on its own.
    double timer_phase = 0;
    /// Where a feature's serial background work runs (core/serial_work.hpp:
    /// the events engine, the method status ticker, the sample spool, and
    /// without `timers` the sample uploader): the shared work threads of a
    /// gateway, or a single adapter's own background threads; null (unit
    /// tests): a thread of its own each.
    core_detail::PollHost* work = nullptr;
};

/// The losses the features count, by cause (the names of the statistics'
/// "drops" object, docs/delivery.md): plain counters the adapter's
/// housekeeping reads once a second without building the statistics. Each
/// feature names its own causes; a cause added twice sums.
class DropCounts {
public:
    /// Adds `n` to `cause` (0 too: a feature adds every cause it has, so
    /// the statistics list each one from the start).
    void add(std::string_view cause, std::uint64_t n) {
        for (auto& [name, count] : causes_)
            if (name == cause) {
                count += n;
                return;
            }
        causes_.emplace_back(std::string(cause), n);
    }
    /// Cause -> count, in the order first added.
    const std::vector<std::pair<std::string, std::uint64_t>>& causes() const { return causes_; }
    /// Every count back to 0, the causes kept: a DropCounts filled again
    /// and again (the housekeeping's once-a-second look) allocates only the
    /// first time.
    void zero() noexcept {
        for (auto& cause : causes_) cause.second = 0;
    }

private:
    std::vector<std::pair<std::string, std::uint64_t>> causes_;  // a handful: a scan beats a map
};

class Feature {
public:
    virtual ~Feature() = default;
    virtual std::string_view name() const = 0;
    /// True for the request kinds this feature answers.
    virtual bool handles(TopicKind kind) const = 0;
    /// One request (already filtered: not retained, not a repeated @id, for
    /// this device). Must answer through host.respond (or the DTU the standard
    /// names, e.g. Method/Result for a rejected call), never stay silent.
    virtual void handle(const ParsedTopic& topic, const std::string& payload) = 0;

    virtual Result<void> start() { return ok_result(); }
    virtual void stop() {}
    /// A Probe/Set installed a new model: restart what runs from the model.
    virtual void on_model(std::shared_ptr<const ModelState> /*state*/) {}
    virtual void on_link(LinkState /*link*/) {}
    /// Application `ex_cid` is gone (Notify/State offline, or silent for the
    /// lease): release what it registered (8.2.18.3).
    virtual void on_application_gone(const std::string& /*ex_cid*/) {}
    /// A driver pushed the current whole value of item `id` (Adapter::notify_value).
    virtual void on_value(const std::string& /*id*/, const Json& /*value*/) {}
    /// Counters for AdapterStats/`nclink stats` (a JSON object).
    virtual Json stats() const { return Json::object(); }
    /// Adds this feature's losses to `out`, every cause it has (the same
    /// counts stats() shows; a free function beside the feature reads them
    /// back from that JSON for a statistics snapshot).
    virtual void add_drops(DropCounts& /*out*/) const {}
};

}  // namespace nclink::feature_detail
