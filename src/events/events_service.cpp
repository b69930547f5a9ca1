#include "events/events_service.hpp"
#include "core/serial_work.hpp"

#include "events/event_engine.hpp"
#include "events/value_inbox.hpp"

#include <nclink/dtu.hpp>
#include <nclink/topics.hpp>

#include <atomic>
#include <condition_variable>
#include <future>
#include <mutex>
#include <random>
#include <thread>

namespace nclink::events_detail {
namespace {

// While only the manual test clock moves, the events engine must look at it
// again now and then: this bounds how long it sleeps while polling is due.
constexpr std::chrono::milliseconds kMaxSleep{20};

// The causes of the statistics' "drops" (docs/delivery.md, "Counted drops").
constexpr std::string_view kValuesQueueFull = "event_values_queue_full";
constexpr std::string_view kPublishRefused = "events_publish_refused";

class EventsServiceImpl final : public feature_detail::Feature {
public:
    EventsServiceImpl(feature_detail::FeatureHost& host, EventsConfig config)
        : host_(host),
          config_(std::move(config)),
          engine_(config_.max_events, fmt::format("{:x}", std::random_device{}() & 0xffffffu)) {}

    ~EventsServiceImpl() override { stop(); }

    std::string_view name() const override { return "events"; }

    bool handles(TopicKind kind) const override {
        return kind == TopicKind::event_register_request || kind == TopicKind::event_unregister_request;
    }

    void handle(const ParsedTopic& topic, const std::string& payload) override {
        if (topic.kind == TopicKind::event_register_request) register_event(topic, payload);
        else unregister_event(topic, payload);
    }

    // The engine is serial work (core/serial_work.hpp): a pollable of the
    // gateway's shared work threads, or of a host of one thread of its own,
    // woken by the inbox; one turn at a time, so values are evaluated in the
    // order they were queued, as on a thread of its own.
    Result<void> start() override {
        // Started before the inbox may wake it (a driver's push can come
        // from any thread at any time); what was queued before the waker
        // was set is taken by the wake-up after it.
        engine_work_.start(host_.work, "nclink-events", [this](core_detail::PollHost::Time) { return turn(); });
        inbox_->set_waker([this] { engine_work_.wake(); });
        engine_work_.wake();
        return ok_result();
    }

    void stop() override {
        inbox_->close();
        engine_work_.stop();
        std::lock_guard<std::mutex> lock(engine_mutex_);
        set_tap(false);
    }

    // A registration whose item the new model lost (or retyped) no longer
    // resolves: it is released and its owner told so with the answer a new
    // registration of it would get, 401 Node not exists (table 19), as an
    // unsolicited Register/Event/Response carrying the event id (docs/wire.md).
    void on_model(std::shared_ptr<const feature_detail::ModelState> state) override {
        std::vector<std::pair<std::string, std::optional<std::string>>> released;
        {
            std::lock_guard<std::mutex> lock(engine_mutex_);
            std::vector<std::optional<std::string>> owners;
            const auto ids = engine_.retain_items(
                [&](const EventSpec& spec) {
                    const DataObject* item = state->item(spec.item);
                    return item != nullptr && item->kind == spec.kind;
                },
                &owners);
            for (std::size_t i = 0; i < ids.size(); ++i) released.emplace_back(ids[i], owners[i]);
            watched_changed();
        }
        for (const auto& [id, owner] : released) {
            host_.logger.info(
                "event {} released: its item is gone from the new model (or changed datatype); "
                "told {} (401)",
                id, owner.value_or("every application"));
            EventRegisterResponse response;
            response.guid = host_.dev;
            response.id = id;
            response.status = ResponseStatus::failure(ErrorCode::node_not_exists);
            ParsedTopic request;
            request.kind = TopicKind::event_register_request;
            request.dev = host_.dev;
            request.ex = owner;
            host_.respond(request, to_json(response));
        }
    }

    void on_application_gone(const std::string& ex) override {
        std::vector<std::string> released;
        {
            std::lock_guard<std::mutex> lock(engine_mutex_);
            released = engine_.remove_owner(ex);
            watched_changed();
        }
        if (!released.empty()) host_.logger.info("released {} event(s) of application {}", released.size(), ex);
    }

    void on_value(const std::string& id, const Json& value) override { inbox_->push_value(id, value, host_.clock->wall_ms()); }

    Json stats() const override {
        std::lock_guard<std::mutex> lock(engine_mutex_);
        return Json{{"registered", engine_.size()},
                    {"fired", engine_.fired()},
                    {"released", engine_.released()},
                    {"polls", polls_.load()},
                    {"publish_errors", publish_errors_.load()},
                    {"dropped_values", inbox_->dropped()}};
    }
    void add_drops(feature_detail::DropCounts& out) const override {
        out.add(kValuesQueueFull, inbox_->dropped());
        out.add(kPublishRefused, publish_errors_.load());
    }

private:
    // ------------------------------------------------------- requests

    // Thread: request worker.
    void register_event(const ParsedTopic& topic, const std::string& payload) {
        auto request = decode<EventRegisterRequest>(payload);
        if (!request) {
            host_.logger.info("malformed Register/Event answered NG: {}", request.error().describe());
            if (auto reply = make_error_reply(topic.kind, peek_message_id(payload), host_.dev, request.error()))
                host_.respond(topic, *reply);
            return;
        }
        auto response = make_reply<EventRegisterResponse>(*request, host_.dev);
        const auto state = host_.model.current();
        auto spec = validate_registration(*request, state->item(request->id));
        if (!spec) {
            refuse(topic, response, spec.error());
            return;
        }
        std::string event_id;
        {
            std::lock_guard<std::mutex> lock(engine_mutex_);
            auto added = engine_.add(topic.ex, *spec);
            if (!added) {
                refuse(topic, response, added.error());
                return;
            }
            event_id = std::move(added).value();
            watched_changed();
        }
        // The current value, so the registration can fire at once when it
        // already matches; a key/index it does not have is refused now.
        const std::int64_t read_at = host_.clock->wall_ms();
        const auto registered_at = host_.clock->now();
        std::optional<Json> current = read_current(*state, *spec);
        if (current) {
            if (auto element = extract_element(*spec, *current); !element && element.error().code != ErrorCode::unavailable) {
                {
                    std::lock_guard<std::mutex> lock(engine_mutex_);
                    (void)engine_.remove(event_id, topic.ex);
                    watched_changed();
                }
                refuse(topic, response, element.error());
                return;
            }
        }
        response.id = event_id;
        host_.logger.debug("event {} registered by {} on {}", event_id, topic.ex.value_or("(no terminal id)"), spec->item);
        // The activation is queued before the response goes out: a value
        // pushed by anyone who has seen the response (notify_value from the
        // application's side, a sample row) queues behind it and is
        // evaluated, where queued the other way round it came before the
        // activation and was not seen (a change lost). The events engine
        // holds this registration's events until the response is published,
        // so the application knows the event id first. A response that throws
        // breaks the promise, which releases the wait too.
        std::promise<void> responded;
        inbox_->push_activation(event_id, std::move(current), read_at, registered_at, responded.get_future().share());
        host_.respond(topic, to_json(response));
        responded.set_value();
    }

    // Thread: request worker.
    void unregister_event(const ParsedTopic& topic, const std::string& payload) {
        auto request = decode<EventUnregisterRequest>(payload);
        if (!request) {
            host_.logger.info("malformed Unregister/Event answered NG: {}", request.error().describe());
            if (auto reply = make_error_reply(topic.kind, peek_message_id(payload), host_.dev, request.error()))
                host_.respond(topic, *reply);
            return;
        }
        auto response = make_reply<EventUnregisterResponse>(*request, host_.dev);
        Result<void> removed = ok_result();
        {
            std::lock_guard<std::mutex> lock(engine_mutex_);
            removed = engine_.remove(request->id, topic.ex);
            watched_changed();
        }
        if (!removed) {
            host_.logger.info("Unregister/Event {} refused: {}", request->id, removed.error().describe());
            response.status = ResponseStatus(removed.error());
        }
        host_.respond(topic, to_json(response));
    }

    template <class Response>
    void refuse(const ParsedTopic& topic, Response& response, const Error& error) {
        host_.logger.info("Register/Event refused: {}", error.describe());
        response.status = ResponseStatus(error);
        host_.respond(topic, to_json(response));
    }

    // The whole value now: the store for SDK-held items, else the driver.
    std::optional<Json> read_current(const feature_detail::ModelState& state, const EventSpec& spec) {
        if (state.sdk_held(spec.item)) {
            auto value = state.store->get(spec.item);
            if (value) return std::move(value).value();
            return std::nullopt;
        }
        PointRef point = state.point(spec.item, spec.kind);
        if (point.handle == not_served) return std::nullopt;  // the driver does not serve it
        auto read = host_.driver.read({std::move(point)}, state.generation());
        if (!read.empty()) host_.values.screen(state, spec.item, read.front(), "event read");
        if (!read.empty() && read.front().ok()) return std::move(read.front()).value();
        return std::nullopt;
    }

    // ------------------------------------------------------- the engine's turns

    // Polls run on a grid of poll_interval that starts one interval after
    // the registration that ended an idle spell (not after the moment a
    // turn noticed it), so a test's manual clock and a real one agree.
    // While no event exists nothing is due: the next push wakes it.
    core_detail::PollHost::Time turn() {
        auto work = inbox_->take();
        if (work.closed) return core_detail::PollHost::Time::max();
        const bool poll_enabled = config_.poll_interval.count() > 0;
        for (auto& item : work.items) {
            process(item);
            if (item.activation && poll_enabled && !polling_) {
                polling_ = true;
                next_poll_ = item.at + config_.poll_interval;
            }
        }
        if (polling_ && !has_active()) polling_ = false;
        if (!polling_) return core_detail::PollHost::Time::max();
        const auto now = host_.clock->now();
        if (now >= next_poll_) {
            poll();
            next_poll_ += config_.poll_interval;
            if (next_poll_ <= now) next_poll_ = now + config_.poll_interval;  // fell behind: skip, do not burst
        }
        return std::chrono::steady_clock::now() + sleep_until(next_poll_);
    }

    std::chrono::milliseconds sleep_until(Clock::Steady deadline) const {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - host_.clock->now());
        if (left.count() <= 0) return std::chrono::milliseconds(0);
        return std::min(left, kMaxSleep);
    }

    bool has_active() const {
        std::lock_guard<std::mutex> lock(engine_mutex_);
        return engine_.size() > 0;
    }

    void process(ValueInbox::Item& item) {
        // Not under engine_mutex_: the worker publishing the response takes
        // no lock of this service between queueing and publishing.
        if (item.activation && item.responded.valid()) item.responded.wait();
        std::vector<FiredEvent> fired;
        {
            std::lock_guard<std::mutex> lock(engine_mutex_);
            const auto before = engine_.size();
            if (item.activation) {
                fired = engine_.activate(item.id, item.value, item.time_ms);
                // The poll plan lists active events only: an activation
                // changes what a poll must read.
                watched_changed();
            } else if (item.value) {
                fired = engine_.observe(item.id, *item.value, item.time_ms);
            }
            if (engine_.size() != before) watched_changed();  // a once trigger released its event
        }
        publish(fired);
    }

    // What a poll reads, resolved to the driver's handles once per model and
    // per change of the watched items (never per poll). Events thread only.
    struct PollPlan {
        std::shared_ptr<const feature_detail::ModelState> state;
        std::uint64_t watched_version = 0;
        std::vector<PointRef> driver_points;  // with their handles; not_served left out
        std::vector<std::string> store_ids;
    };

    void refresh_poll_plan(const std::shared_ptr<const feature_detail::ModelState>& state) {
        const std::uint64_t version = watched_version_.load(std::memory_order_acquire);
        if (plan_.state == state && plan_.watched_version == version) return;
        std::map<std::string, DataKind> items;
        {
            std::lock_guard<std::mutex> lock(engine_mutex_);
            items = engine_.active_items();
        }
        plan_ = PollPlan{state, version, {}, {}};
        for (const auto& [id, kind] : items) {
            if (state->sdk_held(id)) {
                plan_.store_ids.push_back(id);
                continue;
            }
            PointRef point = state->point(id, kind);
            if (point.handle != not_served) plan_.driver_points.push_back(std::move(point));
        }
    }

    // One poll round: every watched item that the sample stream does not bring.
    void poll() {
        const auto state = host_.model.current();
        refresh_poll_plan(state);
        std::vector<PointRef> points;
        std::vector<std::pair<std::string, Json>> values;
        const std::int64_t now_ms = host_.clock->wall_ms();
        for (const auto& id : plan_.store_ids) {
            if (host_.sample_tap.sampled(id)) continue;
            if (auto value = state->store->get(id)) values.emplace_back(id, std::move(value).value());
        }
        for (const auto& point : plan_.driver_points)
            if (!host_.sample_tap.sampled(point.id)) points.push_back(point);
        if (!points.empty()) {
            auto read = host_.driver.read(points, host_.driver_timeout, state->generation());
            for (std::size_t i = 0; i < points.size() && i < read.size(); ++i) {
                host_.values.screen(*state, points[i].id, read[i], "event poll");  // chapter 7
                if (read[i].ok()) values.emplace_back(points[i].id, std::move(read[i]).value());
            }
        }
        if (points.empty() && values.empty()) return;
        std::vector<FiredEvent> fired;
        {
            std::lock_guard<std::mutex> lock(engine_mutex_);
            const auto before = engine_.size();
            for (const auto& [id, value] : values) {
                auto more = engine_.observe(id, value, now_ms);
                fired.insert(fired.end(), std::make_move_iterator(more.begin()), std::make_move_iterator(more.end()));
            }
            if (engine_.size() != before) watched_changed();
        }
        publish(fired);
        ++polls_;  // after publishing: a test that saw the count also sees the round's events sent
    }

    void publish(std::vector<FiredEvent>& fired) {
        for (auto& event : fired) {
            event.dtu.msg_id = Json(host_.next_msg_id());
            event.dtu.guid = host_.dev;
            const auto topic = topics::event(host_.dev, event.owner ? std::optional<std::string_view>(*event.owner) : std::nullopt);
            if (auto sent = host_.transport.publish(Message{topic, encode(event.dtu), config_.qos, false}); !sent) {
                // Logged once per burst: the first refusal after a success.
                if (publish_errors_++ == publish_errors_at_last_success_)
                    host_.logger.warn("event {} not published: {} (further refusals counted in events.publish_errors)",
                                      event.dtu.id, sent.error().describe());
            } else {
                publish_errors_at_last_success_ = publish_errors_.load();
            }
        }
    }

    // ------------------------------------------------------- the sample stream

    // Caller holds engine_mutex_. The inbox learns which items to pick from
    // the stream; the tap is only watched while some event exists, so an
    // adapter without events costs the sampling path nothing.
    void watched_changed() {
        watched_version_.fetch_add(1, std::memory_order_acq_rel);
        auto items = engine_.watched_items();
        set_tap(!items.empty());
        inbox_->set_watched(std::move(items));
    }

    void set_tap(bool on) {
        if (on && !tap_handle_) {
            // The observer holds the inbox, not the service: a row delivered
            // while the tap is being left finds a live (closed) inbox.
            tap_handle_ = host_.sample_tap.add([inbox = inbox_](const std::vector<std::string>& ids, const SampleValue* values,
                                                                std::int64_t time_ms) { inbox->push_row(ids, values, time_ms); });
        } else if (!on && tap_handle_) {
            host_.sample_tap.remove(*tap_handle_);
            tap_handle_.reset();
        }
    }

    feature_detail::FeatureHost& host_;
    const EventsConfig config_;
    std::shared_ptr<ValueInbox> inbox_ = std::make_shared<ValueInbox>(config_.max_queued_values);
    mutable std::mutex engine_mutex_;
    EventEngine engine_;                       // engine_mutex_
    std::optional<std::uint64_t> tap_handle_;  // engine_mutex_
    std::atomic<std::uint64_t> polls_{0};
    std::atomic<std::uint64_t> publish_errors_{0};
    std::atomic<std::uint64_t> publish_errors_at_last_success_{0};  // refused by the transport (after stop, larger than its buffer)
    std::atomic<std::uint64_t> watched_version_{1};                 // bumped by watched_changed()
    PollPlan plan_;                                                 // the engine's turns only
    // (A flag beside the time rather than std::optional: g++ 12 -O2 warns
    // maybe-uninitialized on optional<time_point> here.)
    bool polling_ = false;                 // the engine's turns only; false while idle
    Clock::Steady next_poll_{};            // the engine's turns only
    core_detail::SerialWork engine_work_;  // last: stopped before the rest goes
};

}  // namespace

std::unique_ptr<feature_detail::Feature> make_events_service(feature_detail::FeatureHost& host, const EventsConfig& config) {
    return std::make_unique<EventsServiceImpl>(host, config);
}

void events_drops_from_stats(const Json& stats, feature_detail::DropCounts& out) {
    const auto count = [&](const char* key) -> std::uint64_t {
        if (!stats.is_object()) return 0;
        const auto it = stats.find(key);
        return it != stats.end() && (it->is_number_unsigned() || it->is_number_integer()) ? it->get<std::uint64_t>() : 0;
    };
    out.add(kValuesQueueFull, count("dropped_values"));
    out.add(kPublishRefused, count("publish_errors"));
}

}  // namespace nclink::events_detail
