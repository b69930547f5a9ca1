#include "sampling/uploader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

namespace nclink::sampling_detail {

namespace {
// Distinct texts remembered per channel; beyond it a text is parsed every
// time (a driver whose texts never repeat must not grow the map forever).
constexpr std::size_t kMaxVerdicts = 65536;
}  // namespace

void Uploader::refresh(Clock::Steady now) {
    const auto version = shared_.version.load(std::memory_order_acquire);
    if (version == seen_version_) return;
    std::lock_guard<std::mutex> lock(shared_.mutex);
    seen_version_ = shared_.version.load(std::memory_order_acquire);
    std::vector<Lane> next;
    for (const auto& core : shared_.channels) {
        auto found = std::find_if(lanes_.begin(), lanes_.end(), [&](const Lane& l) { return l.core == core; });
        if (found != lanes_.end()) {
            next.push_back(std::move(*found));
            continue;
        }
        Lane lane;
        lane.core = core;
        const auto upload = std::chrono::nanoseconds(core->upload_interval_ns());
        // Drain at least 4 times per ring's worth of rows, so the ring only
        // fills when this thread is starved.
        const auto ring_time =
            std::chrono::nanoseconds(core->sample_interval_ns() * static_cast<std::int64_t>(core->ring().capacity()));
        lane.drain_period = std::max(std::chrono::nanoseconds(std::chrono::microseconds(100)), std::min(upload, ring_time / 4));
        lane.next_publish = now + upload;
        lane.next_drain = now + lane.drain_period;
        next.push_back(std::move(lane));
    }
    lanes_ = std::move(next);
}

Clock::Steady Uploader::poll(bool final_flush) {
    const auto& clock = *shared_.deps.clock;
    const auto now = clock.now();
    refresh(now);
    Clock::Steady earliest = now + std::chrono::hours(1);
    bool finished_any = false;
    for (auto& lane : lanes_) {
        ChannelCore& core = *lane.core;
        const bool last = core.removed.load(std::memory_order_acquire) && core.producer_done.load(std::memory_order_acquire);
        if (final_flush || last || now >= lane.next_drain || now >= lane.next_publish) {
            drain(lane);
            lane.next_drain = now + lane.drain_period;
        }
        if (final_flush || last || now >= lane.next_publish) {
            publish(lane);
            const auto upload = std::chrono::nanoseconds(core.upload_interval_ns());
            lane.next_publish += upload;
            if (lane.next_publish <= now) lane.next_publish = now + upload;  // fell behind: re-anchor
        }
        if (last) {
            finished_any = true;
            continue;
        }
        earliest = std::min({earliest, lane.next_drain, lane.next_publish});
    }
    if (finished_any) {
        // Removed channels whose last rows are out leave the engine.
        std::lock_guard<std::mutex> lock(shared_.mutex);
        auto& list = shared_.channels;
        list.erase(std::remove_if(list.begin(), list.end(),
                                  [](const std::shared_ptr<ChannelCore>& c) {
                                      return c->removed.load(std::memory_order_acquire) &&
                                             c->producer_done.load(std::memory_order_acquire);
                                  }),
                   list.end());
        lanes_.erase(std::remove_if(lanes_.begin(), lanes_.end(),
                                    [](const Lane& l) {
                                        return l.core->removed.load(std::memory_order_acquire) &&
                                               l.core->producer_done.load(std::memory_order_acquire);
                                    }),
                     lanes_.end());
        // Not marked seen: a channel added since this pass's refresh (e.g. by
        // the sink above) bumped the version too, and must get its lane at
        // the next refresh rather than be skipped over.
        shared_.version.fetch_add(1, std::memory_order_acq_rel);
    }
    return earliest;
}

void Uploader::drain(Lane& lane) {
    ChannelCore& core = *lane.core;
    SpscRowRing& ring = core.ring();
    const std::size_t width = ring.width();
    const std::size_t before = lane.times.size();
    const std::size_t n = ring.claim();
    // Each row is screened right after its copy, while it is in the cache,
    // rather than in a second pass over the whole batch (at 1 x 5,000
    // points a batch is megabytes).
    const bool screening = n > 0 && prepare_screen(lane);
    for (std::size_t i = 0; i < n; ++i) {
        const SampleValue* row = ring.row(i);
        lane.values.insert(lane.values.end(), row, row + width);
        if (screening) screen_row(lane, lane.values.data() + lane.values.size() - width);
        lane.times.push_back(ring.time_ns(i));
        lane.seqs.push_back(ring.seq(i));
    }
    ring.release(n);
    feature_detail::SampleTap* tap = shared_.deps.tap;
    if (tap != nullptr && n > 0 && tap->active()) {
        for (std::size_t r = before; r < lane.times.size(); ++r)
            tap->deliver(core.ids(), lane.values.data() + r * width, lane.times[r] / 1'000'000);
    }
}

bool Uploader::prepare_screen(Lane& lane) {
    feature_detail::ValueGuard* guard = shared_.deps.values;
    if (guard == nullptr || !guard->enabled()) return false;
    ChannelCore& core = *lane.core;
    const std::size_t width = core.ring().width();
    const auto version = shared_.model_version.load(std::memory_order_acquire);
    if (lane.rules_version != version) {
        lane.rules_version = version;
        lane.model = shared_.current_model();
        lane.rules.assign(width, nullptr);
        lane.verdicts.clear();
        // A rule that is not a single-valued number range admits no float
        // inline: its values take the full check.
        constexpr double inf = std::numeric_limits<double>::infinity();
        lane.lo.assign(width, -inf);
        lane.hi.assign(width, inf);
        lane.any_rule = false;
        if (lane.model && lane.model->rules) {
            for (std::size_t p = 0; p < width && p < core.spec().points.size(); ++p) {
                const ValueRule* rule = lane.model->rules->find(core.id(p));
                lane.rules[p] = rule;
                if (rule == nullptr) continue;
                double min = 0, max = 0;
                const bool number = rule->number_bounds(min, max);
                lane.lo[p] = number ? min : inf;
                lane.hi[p] = number ? max : -inf;
                lane.any_rule = true;
            }
        }
    }
    return lane.any_rule && width > 0;
}

void Uploader::screen_row(Lane& lane, SampleValue* row) {
    const bool stable_text = !lane.core->spec().push;
    const double* lo = lane.lo.data();
    const double* hi = lane.hi.data();
    const std::size_t width = lane.lo.size();
    for (std::size_t p = 0; p < width; ++p) {
        const SampleValue& value = row[p];
        if (value.kind() == SampleValue::Kind::float64 && value.as_double() >= lo[p] && value.as_double() <= hi[p])
            continue;  // the bulk: a number inside its range, or no rule
        screen_value(lane, p, row[p], stable_text);
    }
}

void Uploader::screen_value(Lane& lane, std::size_t p, SampleValue& value, bool stable_text) {
    const ValueRule* rule = lane.rules[p];
    if (rule == nullptr) return;
    const double lo = lane.lo[p], hi = lane.hi[p];
    ValueFault fault;
    if (lo <= hi && value.kind() == SampleValue::Kind::float64) {  // a number range
        const double v = value.as_double();
        if (!(v < lo || v > hi)) return;  // NaN: encoded as null, not refused
        fault = ValueFault::range;
    } else {
        fault = check(lane, p, value, stable_text);
        if (fault == ValueFault::none) return;
    }
    refuse(lane, *rule, fault, value);
}

ValueFault Uploader::check(Lane& lane, std::size_t column, const SampleValue& value, bool stable_text) {
    const ValueRule& rule = *lane.rules[column];
    ValueFault fault = rule.check(value);
    if (fault != ValueFault::none || !rule.needs_parse(value)) return fault;
    // Pre-serialized JSON (an object, a list): parsed once per distinct
    // interned text of a pull channel, every time for a push channel (its
    // text is the pusher's).
    auto& verdicts = lane.verdicts;
    const Lane::VerdictKey key{column, value.as_text().data()};
    auto cached = stable_text ? verdicts.find(key) : verdicts.end();
    if (cached != verdicts.end()) return cached->second;
    const Json parsed = Json::parse(value.as_text(), nullptr, false);
    fault = parsed.is_discarded() ? ValueFault::type : rule.check(parsed);
    if (stable_text && verdicts.size() < kMaxVerdicts) verdicts.emplace(key, fault);
    return fault;
}

void Uploader::refuse(Lane& lane, const ValueRule& rule, ValueFault fault, SampleValue& value) {
    ChannelCore& core = *lane.core;
    std::string shown;
    switch (value.kind()) {
        case SampleValue::Kind::text:
            shown = Json(std::string(value.as_text())).dump(-1, ' ', false, Json::error_handler_t::replace);
            break;
        case SampleValue::Kind::json: shown = std::string(value.as_text()); break;
        case SampleValue::Kind::boolean: shown = value.as_bool() ? "true" : "false"; break;
        case SampleValue::Kind::int64: shown = std::to_string(value.as_int64()); break;
        case SampleValue::Kind::uint64: shown = std::to_string(value.as_uint64()); break;
        case SampleValue::Kind::float64: shown = fmt::format("{}", value.as_double()); break;
        default: break;
    }
    shared_.deps.values->refuse(rule, fault, "sample channel " + core.spec().id, shown);
    value = SampleValue::null();
    core.refused_values.add();
}

void Uploader::publish(Lane& lane) {
    const std::size_t rows = lane.times.size();
    if (rows == 0) return;
    std::size_t max_rows = std::max<std::size_t>(1, 2 * lane.core->rows_per_upload());
    const std::size_t max_bytes = shared_.deps.config.max_dtu_bytes;
    if (max_bytes > 0) {
        // Before the channel's first DTU, assume the longest double text
        // (24 characters) per value: a first DTU too small is harmless.
        const double per_row =
            lane.bytes_per_row > 0 ? lane.bytes_per_row : 24.0 * static_cast<double>(lane.core->ring().width()) + 16.0;
        max_rows = std::clamp<std::size_t>(static_cast<std::size_t>(static_cast<double>(max_bytes) / per_row), 1, max_rows);
    }
    std::size_t first = 0;
    for (std::size_t r = 1; r <= rows; ++r) {
        const bool gap = r < rows && lane.seqs[r] != lane.seqs[r - 1] + 1;
        if (r == rows || gap || r - first >= max_rows) {
            publish_segment(lane, first, r - first);
            first = r;
        }
    }
    lane.values.clear();
    lane.times.clear();
    lane.seqs.clear();
}

void Uploader::publish_segment(Lane& lane, std::size_t first, std::size_t count) {
    ChannelCore& core = *lane.core;
    const std::size_t width = core.ring().width();
    SampleDtuHeader header;
    header.guid = shared_.deps.dev;
    header.channel_id = core.spec().id;
    const std::int64_t t = lane.times[first];
    header.begin_time_ms = t >= 0 ? t / 1'000'000 : -((-t + 999'999) / 1'000'000);
    const std::string_view payload = encoder_.encode(header, SampleRows{lane.values.data() + first * width, width, count});
    lane.bytes_per_row = static_cast<double>(payload.size()) / static_cast<double>(count);
    Message message{core.spec().topic, std::string(payload), core.spec().qos, false};
    if (shared_.deps.sink) {
        try {
            shared_.deps.sink(std::move(message));
        } catch (const std::exception& e) {
            shared_.deps.logger.error("sampling {}: the DTU sink threw: {}", core.spec().id, e.what());
        }
    }
    core.rows_published.add(count);
    core.dtus_published.add();
}

}  // namespace nclink::sampling_detail
