#include "sampling/scheduler.hpp"

#include <algorithm>

namespace nclink::sampling_detail {

SampleValue to_sample_value(const Json& value, ChannelCore& channel) {
    switch (value.type()) {
        case Json::value_t::boolean: return SampleValue::boolean(value.get<bool>());
        case Json::value_t::number_integer: return SampleValue::int64(value.get<std::int64_t>());
        case Json::value_t::number_unsigned: return SampleValue::uint64(value.get<std::uint64_t>());
        case Json::value_t::number_float: return SampleValue::float64(value.get<double>());
        case Json::value_t::string: return channel.intern_text(value.get_ref<const std::string&>(), false);
        case Json::value_t::array:
        case Json::value_t::object: return channel.intern_text(value.dump(-1, ' ', false, Json::error_handler_t::replace), true);
        default: return SampleValue::null();
    }
}

void Scheduler::reset() {
    for (auto& lane : lanes_) lane.core->producer_done.store(true, std::memory_order_release);
    lanes_.clear();
    seen_version_ = 0;
}

std::int64_t Scheduler::fastest_driver_interval_ns() const {
    std::int64_t fastest = 0;
    for (const auto& lane : lanes_) {
        if (lane.driver_points.empty()) continue;
        const std::int64_t interval = lane.core->sample_interval_ns();
        if (fastest == 0 || interval < fastest) fastest = interval;
    }
    return fastest;
}

void Scheduler::refresh(Clock::Steady now) {
    const auto version = shared_.version.load(std::memory_order_acquire);
    if (version == seen_version_) return;
    std::lock_guard<std::mutex> lock(shared_.mutex);
    seen_version_ = shared_.version.load(std::memory_order_acquire);
    std::vector<Lane> next;
    bool released = false;
    for (const auto& core : shared_.channels) {
        if (core->removed.load(std::memory_order_acquire)) {
            // We never write to a removed channel again: the uploader may
            // publish its last rows (wake it to do so).
            if (!core->producer_done.exchange(true, std::memory_order_acq_rel)) released = true;
            continue;
        }
        if (core->spec().push) continue;
        auto found = std::find_if(lanes_.begin(), lanes_.end(), [&](const Lane& l) { return l.core == core; });
        if (found != lanes_.end()) {
            next.push_back(std::move(*found));
            continue;
        }
        Lane lane;
        lane.core = core;
        // Timelines start on the monotonic clock's grid of their interval:
        // channels of one interval (or of multiples of it) then come due
        // together and share one wake-up, where start-up order would spread
        // their phases over the period (a wake-up per channel per tick). The
        // grid of intervals over a second is the second: their wake-ups are
        // rare anyway, and the first row should not wait minutes. The grid is
        // shifted by the engine's phase (EngineDeps::phase: other adapters of
        // a gateway sit elsewhere in the period).
        const std::int64_t grid = std::min<std::int64_t>(core->sample_interval_ns(), 1'000'000'000);
        const auto shift = static_cast<std::int64_t>(shared_.deps.phase * static_cast<double>(grid));
        const std::int64_t since = std::chrono::duration_cast<std::chrono::nanoseconds>(now.time_since_epoch()).count() - shift;
        const std::int64_t phase = ((since % grid) + grid) % grid;
        const std::int64_t delay = phase == 0 ? 0 : grid - phase;
        lane.t0 = now + std::chrono::nanoseconds(delay);
        lane.wall0_ns = shared_.deps.clock->wall_ms() * 1'000'000 + delay;
        next.push_back(std::move(lane));
    }
    lanes_ = std::move(next);
    if (released) shared_.deps.sleeper->wake();
}

void Scheduler::plan(Lane& lane, const std::shared_ptr<const feature_detail::ModelState>& model, std::uint64_t version) {
    lane.model = model;
    lane.model_version = version;
    lane.driver_points.clear();
    lane.driver_columns.clear();
    lane.store_ids.clear();
    lane.store_columns.clear();
    lane.null_columns.clear();
    lane.typed = true;  // a new model may come with a new driver behaviour: ask again
    // Ids are resolved to the driver's handles here, once per model.
    lane.generation = model ? model->generation() : driver_detail::unbound;
    const auto& points = lane.core->spec().points;
    // Sized once (clear() keeps it): grown by doubling, a 300-point lane
    // held room for 512 (docs/performance.md, "Memory per machine").
    lane.driver_points.reserve(points.size());
    lane.driver_columns.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (model && model->sdk_held(points[i].id)) {
            lane.store_ids.push_back(points[i].id);
            lane.store_columns.push_back(i);
            continue;
        }
        PointRef point = model ? model->point(points[i].id, points[i].kind) : points[i];
        if (point.handle == not_served) {
            lane.null_columns.push_back(i);
            continue;
        }
        lane.driver_points.push_back(std::move(point));
        lane.driver_columns.push_back(i);
    }
    lane.identity_columns = lane.store_ids.empty() && lane.null_columns.empty();
}

Clock::Steady Scheduler::poll() {
    const auto& clock = *shared_.deps.clock;
    refresh(clock.now());
    const auto model_version = shared_.model_version.load(std::memory_order_acquire);
    std::shared_ptr<const feature_detail::ModelState> model;
    Clock::Steady earliest = clock.now() + std::chrono::hours(1);
    for (auto& lane : lanes_) {
        if (lane.model_version != model_version) {
            if (!model) model = shared_.current_model();
            plan(lane, model, model_version);
        }
        earliest = std::min(earliest, serve(lane, clock.now()));
    }
    return earliest;
}

Clock::Steady Scheduler::serve(Lane& lane, Clock::Steady now) {
    ChannelCore& core = *lane.core;
    const std::int64_t interval = core.sample_interval_ns();
    const auto deadline = [&](std::uint64_t k) {
        return lane.t0 + std::chrono::nanoseconds(static_cast<std::int64_t>(k) * interval);
    };
    if (deadline(lane.next_k) > now) return deadline(lane.next_k);

    // The newest due tick; older due ticks are overruns.
    const auto elapsed = std::chrono::duration_cast<std::chrono::nanoseconds>(now - lane.t0).count();
    const std::uint64_t newest = static_cast<std::uint64_t>(elapsed / interval);
    const auto late_of = [&](std::uint64_t k) {
        return std::chrono::duration_cast<std::chrono::nanoseconds>(now - deadline(k)).count();
    };
    core.record_lateness(late_of(lane.next_k));  // how late the pass came for the oldest due tick
    const auto& observer = shared_.deps.tick_observer;

    std::uint64_t missed = newest - lane.next_k;
    if (missed > 0) {
        const std::uint64_t keep = core.rows_per_upload();
        if (missed > keep) {
            // A long stall: null rows for the last upload period only.
            core.skipped_ticks.add(missed - keep);
            lane.next_k += missed - keep;
            missed = keep;
        }
        if (!lane.in_burst) {
            report_burst(core, missed, std::chrono::duration_cast<std::chrono::microseconds>(now - deadline(lane.next_k)), now);
            lane.in_burst = true;
            lane.burst_overruns = 0;
        }
        while (lane.next_k < newest) {
            if (!produce_null_row(lane, lane.next_k))
                return now + std::chrono::nanoseconds(std::min<std::int64_t>(interval, 1'000'000));
            if (observer) observer(core.spec().id, late_of(lane.next_k));
            core.overruns.add();
            lane.burst_overruns++;
            lane.next_k++;
        }
    } else if (lane.in_burst) {
        shared_.deps.logger.debug("sampling {}: on time again after {} missed tick(s)", core.spec().id, lane.burst_overruns);
        lane.in_burst = false;
    }
    if (!produce_read_row(lane, newest)) return now + std::chrono::nanoseconds(std::min<std::int64_t>(interval, 1'000'000));
    if (observer) observer(core.spec().id, late_of(newest));
    lane.next_k = newest + 1;
    return deadline(lane.next_k);
}

// Both return false only under the block policy while the ring is full: the
// tick stays due and is served when the uploader made room.
bool Scheduler::produce_null_row(Lane& lane, std::uint64_t k) {
    ChannelCore& core = *lane.core;
    SampleValue* row = core.ring().try_begin();
    if (row == nullptr) return core.ring().policy() != FullPolicy::block;  // drop_oldest refused: counted as a drop
    const std::size_t width = core.ring().width();
    for (std::size_t i = 0; i < width; ++i) row[i] = SampleValue::null();
    core.ring().commit(row_time_ns(lane, k), k);
    core.rows_sampled.add();
    core.null_values.add(width);
    return true;
}

bool Scheduler::produce_read_row(Lane& lane, std::uint64_t k) {
    ChannelCore& core = *lane.core;
    SampleValue* row = core.ring().try_begin();
    if (row == nullptr) return core.ring().policy() != FullPolicy::block;
    std::uint64_t nulls = lane.null_columns.size();
    for (const std::size_t column : lane.null_columns) row[column] = SampleValue::null();
    if (!lane.driver_points.empty()) nulls += read_driver_columns(lane, row);
    for (std::size_t i = 0; i < lane.store_ids.size(); ++i) {
        SampleValue& slot = row[lane.store_columns[i]];
        auto value = lane.model && lane.model->store ? lane.model->store->get(lane.store_ids[i])
                                                     : Result<Json>(make_error(ErrorCode::unavailable));
        slot = value ? to_sample_value(value.value(), core) : SampleValue::null();
        if (slot.is_null()) ++nulls;
    }
    core.ring().commit(row_time_ns(lane, k), k);
    core.rows_sampled.add();
    if (nulls) core.null_values.add(nulls);
    return true;
}

void Scheduler::report_burst(const ChannelCore& core, std::uint64_t missed, std::chrono::microseconds late, Clock::Steady now) {
    // One line per burst would be one line per channel per hiccup of a
    // loaded host: report the first burst, then at most one line per
    // interval, summing up the bursts in between (nclink stats has counts).
    const auto interval = shared_.deps.config.overrun_log_interval;
    if (reported_burst_ && now - last_burst_report_ < interval) {
        ++quiet_bursts_;
        quiet_channels_.insert(core.spec().id);
        return;
    }
    std::string since;
    if (quiet_bursts_ > 0)
        since = fmt::format("; {} more burst(s) on {} channel(s) since the last report", quiet_bursts_, quiet_channels_.size());
    shared_.deps.logger.warn("sampling {}: {} tick(s) of {} ms missed (late by {} us); their rows are sent as null{}",
                             core.spec().id, missed, core.spec().sample_interval_ms, late.count(), since);
    reported_burst_ = true;
    last_burst_report_ = now;
    quiet_bursts_ = 0;
    quiet_channels_.clear();
}

std::uint64_t Scheduler::read_driver_columns(Lane& lane, SampleValue* row) {
    ChannelCore& core = *lane.core;
    driver_detail::DriverRunner* driver = shared_.deps.driver;
    const std::size_t n = lane.driver_points.size();
    std::uint64_t nulls = 0;
    if (driver == nullptr) {
        for (std::size_t i = 0; i < n; ++i) row[lane.driver_columns[i]] = SampleValue::null();
        return n;
    }
    // Waiting longer than one period for a busy driver only turns one late
    // row into several missed ones.
    const auto wait = std::chrono::nanoseconds(core.sample_interval_ns());
    const bool direct = shared_.deps.config.direct_reads;
    if (direct && lane.typed) {
        // Typed read straight into the ring slot when the driver's columns
        // are the whole row in order, else through the lane's scratch row.
        SampleValue* out = row;
        if (!lane.identity_columns) {
            lane.samples.resize(n);
            out = lane.samples.data();
        }
        const auto outcome = driver->read_samples_direct(lane.driver_points, out, wait, lane.generation);
        if (outcome == driver_detail::DriverRunner::TypedRead::unsupported) {
            lane.typed = false;  // asked once per plan; read() from now on
        } else {
            // Borrowed text lives in the driver until its next call: copy it.
            const auto own = [&core](SampleValue& value) {
                const auto kind = value.kind();
                if (kind == SampleValue::Kind::text || kind == SampleValue::Kind::json)
                    value = core.intern_text(value.as_text(), kind == SampleValue::Kind::json);
            };
            if (out == row) {
                // Already in place: only texts are rewritten (numbers, the
                // bulk, are read once and left alone; rewriting every slot
                // through the column map was 40 % of the sampler at 10 x 700).
                for (std::size_t i = 0; i < n; ++i) {
                    own(row[i]);
                    if (row[i].is_null()) ++nulls;
                }
                return nulls;
            }
            for (std::size_t i = 0; i < n; ++i) {
                SampleValue value = out[i];
                own(value);
                row[lane.driver_columns[i]] = value;
                if (value.is_null()) ++nulls;
            }
            return nulls;
        }
    }
    if (direct) {
        driver->read_direct(lane.driver_points, lane.results, wait, lane.generation);
    } else {
        lane.results = driver->read(
            lane.driver_points,
            std::max(std::chrono::milliseconds(1), std::chrono::duration_cast<std::chrono::milliseconds>(wait)), lane.generation);
    }
    for (std::size_t i = 0; i < n; ++i) {
        SampleValue& slot = row[lane.driver_columns[i]];
        slot = i < lane.results.size() && lane.results[i] ? to_sample_value(lane.results[i].value(), core) : SampleValue::null();
        if (slot.is_null()) ++nulls;
    }
    return nulls;
}

}  // namespace nclink::sampling_detail
