#include "methods/method_table.hpp"
#include "protocol/driver_failure.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <system_error>

namespace nclink::methods_detail {
namespace {

// The ticker re-reads the injected clock at least this often (a ManualClock
// moves without waking anyone).
constexpr auto kTickerPoll = std::chrono::milliseconds(10);

topics::OptEx ex_of(const ParsedTopic& topic) { return topic.ex ? topics::OptEx(*topic.ex) : std::nullopt; }

}  // namespace

std::shared_ptr<MethodTable> MethodTable::create(MethodsConfig config, Outlet outlet, Logger logger,
                                                 std::shared_ptr<const Clock> clock, core_detail::PollHost* work) {
    return std::shared_ptr<MethodTable>(
        new MethodTable(std::move(config), std::move(outlet), std::move(logger), std::move(clock), work));
}

MethodTable::MethodTable(MethodsConfig config, Outlet outlet, Logger logger, std::shared_ptr<const Clock> clock,
                         core_detail::PollHost* work)
    : config_(std::move(config)), logger_(std::move(logger)), clock_(std::move(clock)), work_(work), outlet_(std::move(outlet)) {}

MethodTable::~MethodTable() {
    // shutdown() joined or detached every thread; a table destroyed without it
    // (a failed start) has none running but may hold joinable handles.
    ticker_.stop();
    for (auto& [serial, entry] : entries_)
        if (entry.thread.joinable()) entry.thread.detach();
}

Result<std::shared_ptr<MethodRun>> MethodTable::start(const PointRef& method, const ParsedTopic& call_topic,
                                                      const MessageId& call_id, Json args, std::shared_ptr<Driver> driver) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closing_) return make_error(ErrorCode::unavailable, "the adapter is stopping");
    if (active_ >= config_.max_running)
        return make_error(ErrorCode::insufficient_method,
                          fmt::format("{} method run(s) under way, the limit (methods.max_running)", active_));
    const std::uint64_t serial = ++serial_;
    const std::string& method_id = method.id;
    auto run = std::make_shared<MethodRun>(serial, method_id, call_topic, call_id, std::move(args));
    run->set_phase_listener([weak = weak_from_this()](MethodRun& r) {
        if (auto table = weak.lock()) table->publish_status(r);
    });
    Entry& entry = entries_[serial];
    entry.run = run;
    entry.next_status = clock_->now() + config_.status_period;
    ++active_;
    ++accepted_;
    ticker_.wake();        // an idle ticker has a run to watch now
    publish_status(*run);  // "waiting": the call is accepted (8.2.22.3)
    try {
        entry.thread = std::thread(
            [self = shared_from_this(), run, method, driver = std::move(driver)] { self->execute(run, method, *driver); });
    } catch (const std::system_error& e) {
        // No thread for it: the run never starts. It was announced, so it is
        // answered like a run that failed.
        logger_.error("method {}: cannot start a method thread: {}", method_id, e.what());
        publish_result(*run, result_of(*run, make_error(ErrorCode::insufficient_method, "no method thread")));
        entry.done = true;
        --active_;
    }
    return run;
}

void MethodTable::execute(const std::shared_ptr<MethodRun>& run, const PointRef& method, Driver& driver) {
    Result<Json> outcome = make_error(ErrorCode::unavailable);
    if (!run->begin()) {
        // Cancelled before the driver was called: Status "sleep" went out,
        // the Result says canceled with nothing returned.
        publish_result(*run, result_of(*run, Json(nullptr)));
        finish(run->serial);
        return;
    }
    try {
        outcome = driver.run_method(method, run->args, *run);
    } catch (const std::exception& e) {
        outcome = make_error(ErrorCode::unavailable, std::string("driver threw: ") + e.what());
    } catch (...) {
        outcome = make_error(ErrorCode::unavailable, "driver threw");
    }
    publish_result(*run, result_of(*run, outcome));
    finish(run->serial);
}

MethodResult MethodTable::result_of(const MethodRun& run, const Result<Json>& outcome) const {
    MethodResult result;
    result.msg_id = run.call_id;
    result.guid = outlet_.dev;
    result.id = run.method_id;
    if (run.cancelled()) {
        // Whatever the driver returned once told to cancel (driver.hpp).
        result.result = "canceled";
        if (outcome.ok() && !outcome.value().is_null()) result.return_value = outcome.value();
    } else if (outcome.ok()) {
        result.result = "finished";
        if (!outcome.value().is_null()) result.return_value = outcome.value();
    } else {
        result.result = "error";
        // The reason stays the table-19 string; the driver's own words go in
        // privateInfo, the implementation's part of the DTU (table 45); a
        // vendor code follows docs/wire.md, "Vendor errors".
        auto failure = protocol_detail::driver_failure(outcome.error());
        result.status = std::move(failure.status);
        result.private_info = std::move(failure.private_info);
    }
    return result;
}

void MethodTable::finish(std::uint64_t serial) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = entries_.find(serial);
        if (it != entries_.end() && !it->second.done) {
            it->second.done = true;
            --active_;
        }
        ticker_.wake();  // the ticker joins the thread
    }
    finished_.notify_all();
}

std::vector<std::shared_ptr<MethodRun>> MethodTable::running(const std::string& method_id) const {
    auto out = running();
    out.erase(std::remove_if(out.begin(), out.end(), [&](const auto& run) { return run->method_id != method_id; }), out.end());
    return out;
}

std::vector<std::shared_ptr<MethodRun>> MethodTable::running() const {
    std::vector<std::shared_ptr<MethodRun>> out;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& [serial, entry] : entries_)
            if (!entry.done) out.push_back(entry.run);
    }
    // A run whose Method/Result (8.2.24) is out is over, though its thread
    // has not reached finish() yet: a control after the Result answers "not
    // running" (202), never OK. Checked outside mutex_: publish_mutex is
    // never taken under it.
    out.erase(std::remove_if(out.begin(), out.end(), [](const auto& run) { return run->answered(); }), out.end());
    return out;
}

void MethodTable::publish_status(MethodRun& run) {
    std::lock_guard<std::mutex> order(run.publish_mutex);
    if (run.result_published) return;
    const auto state = run.snapshot();
    MethodStatus status;
    status.msg_id = run.call_id;
    status.guid = outlet_.dev;
    status.id = run.method_id;
    status.status = to_string(state.phase);
    status.progress = state.progress;
    std::lock_guard<std::mutex> gate(gate_mutex_);
    if (closed_) return;
    ++statuses_;
    (void)outlet_.transport->publish(Message{topics::method_status(outlet_.dev, ex_of(run.call_topic)), encode(status), 1, false});
}

void MethodTable::publish_result(MethodRun& run, const MethodResult& result) {
    std::lock_guard<std::mutex> order(run.publish_mutex);
    if (run.result_published) return;
    run.result_published = true;
    if (result.result == "finished") ++finished_count_;
    else if (result.result == "canceled") ++canceled_;
    else ++errors_;
    logger_.debug("method {} {}: {}", run.method_id, run.call_id ? run.call_id->dump() : "(no @id)", result.result);
    std::lock_guard<std::mutex> gate(gate_mutex_);
    if (closed_) return;
    outlet_.respond(run.call_topic, to_json(result));
}

void MethodTable::answer(const ParsedTopic& request, const Json& reply) {
    std::lock_guard<std::mutex> gate(gate_mutex_);
    if (closed_) return;
    outlet_.respond(request, reply);
}

void MethodTable::start_ticker() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (ticker_started_) return;
    ticker_started_ = true;
    // "nclink-method-0" on a host of its own: 15 characters, the most a
    // thread's name keeps.
    ticker_.start(work_, "nclink-method", [this](core_detail::PollHost::Time) { return tick(); });
}

core_detail::PollHost::Time MethodTable::tick() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (ticker_stop_) return core_detail::PollHost::Time::max();
    const auto now = clock_->now();
    std::vector<std::shared_ptr<MethodRun>> due;
    std::vector<std::thread> finished;
    for (auto it = entries_.begin(); it != entries_.end();) {
        Entry& entry = it->second;
        if (entry.done) {
            if (entry.thread.joinable()) finished.push_back(std::move(entry.thread));
            it = entries_.erase(it);
            continue;
        }
        if (now >= entry.next_status) {
            due.push_back(entry.run);
            // One Status per period; periods the clock jumped over are skipped.
            while (entry.next_status <= now) entry.next_status += config_.status_period;
        }
        ++it;
    }
    if (!due.empty() || !finished.empty()) {
        lock.unlock();
        for (auto& run : due) publish_status(*run);
        for (auto& thread : finished) thread.join();
        return std::chrono::steady_clock::now();  // look again at once
    }
    // Idle (no run under way): nothing is due until start() or a finishing
    // run wakes it, so a gateway of many idle machines costs no wake-ups.
    // With runs, poll the injected clock (tests drive it by hand).
    if (entries_.empty()) return core_detail::PollHost::Time::max();
    return std::chrono::steady_clock::now() + kTickerPoll;
}

void MethodTable::shutdown(std::chrono::milliseconds grace) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (closing_ && ticker_stop_) return;
    closing_ = true;
    for (auto& [serial, entry] : entries_)
        if (!entry.done) entry.run->request_cancel();
    const bool all_done = finished_.wait_for(lock, grace, [&] { return active_ == 0; });
    std::vector<std::shared_ptr<MethodRun>> stuck;
    if (!all_done)
        for (auto& [serial, entry] : entries_)
            if (!entry.done) stuck.push_back(entry.run);
    ticker_stop_ = true;
    lock.unlock();
    ticker_.stop();  // returns once no turn of the ticker runs or will

    for (auto& run : stuck) {
        logger_.error("method {} did not return within {} ms of shutdown; its thread is abandoned", run->method_id, grace.count());
        MethodResult result = result_of(*run, make_error(ErrorCode::unavailable, "the adapter stopped"));
        result.result = "error";  // not "canceled": the driver never confirmed
        result.status = ResponseStatus(make_error(ErrorCode::unavailable));
        result.return_value.reset();
        result.private_info = Json{{"message", "the adapter stopped while the method was running"}};
        publish_result(*run, result);
    }
    {
        std::lock_guard<std::mutex> gate(gate_mutex_);
        closed_ = true;
    }
    lock.lock();
    std::vector<std::thread> to_join;
    for (auto& [serial, entry] : entries_) {
        if (!entry.thread.joinable()) continue;
        if (entry.done) to_join.push_back(std::move(entry.thread));
        else entry.thread.detach();  // stuck in the driver; it holds the table alive
    }
    lock.unlock();
    for (auto& thread : to_join) thread.join();
}

Json MethodTable::stats() const {
    std::size_t running_now = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        running_now = active_;
    }
    return Json{{"running", running_now},         {"max_running", config_.max_running},
                {"accepted", accepted_.load()},   {"finished", finished_count_.load()},
                {"canceled", canceled_.load()},   {"errors", errors_.load()},
                {"status_dtus", statuses_.load()}};
}

}  // namespace nclink::methods_detail
