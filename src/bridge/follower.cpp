#include "bridge/follower.hpp"

#include "bridge/mtconnect_documents.hpp"

#include <algorithm>

namespace nclink::bridge {

Follower::Follower(Client& client, BridgeStore& store, FollowerOptions options)
    : client_(client), store_(store), options_(std::move(options)) {
    request_options_.timeout = options_.request_timeout;
}

Follower::~Follower() { stop(); }

Result<void> Follower::start() {
    if (running_.exchange(true)) return ok_result();
    if (options_.devices.empty()) {
        auto sub = client_.subscribe_all_states([this](const NotifyState& s) {
            if (s.state == "online") consider(s.tid);
            on_state(s);
        });
        if (!sub) return std::move(sub).error();
        std::lock_guard<std::mutex> lock(mutex_);
        subscriptions_.push_back(*sub);
    } else {
        for (const auto& dev : options_.devices) follow(dev);
    }
    housekeeper_ = std::thread([this] { housekeeping(); });
    return ok_result();
}

void Follower::stop() {
    if (!running_.exchange(false)) return;
    { std::lock_guard<std::mutex> lock(wake_mutex_); }
    wake_.notify_all();
    if (housekeeper_.joinable()) housekeeper_.join();
}

void Follower::consider(const std::string& tid) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (followed_.count(tid) || probing_.count(tid)) return;
        probing_.insert(tid);
    }
    // A terminal that answers Probe/Query is an adapter; applications do not answer.
    client_.probe_async(
        tid,
        [this, tid](Result<Json> model) {
            {
                std::lock_guard<std::mutex> lock(mutex_);
                probing_.erase(tid);
            }
            if (!model || !running_) return;
            follow(tid);
        },
        request_options_);
}

void Follower::follow(const std::string& dev) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (followed_.count(dev)) return;
        Followed& f = followed_[dev];
        f.poll_interval = options_.poll_interval;
        f.last_heard = std::chrono::steady_clock::now();
    }
    options_.logger.info("bridge: following {}", dev);
    store_.add_device(dev);
    std::vector<SubscriptionId> subs;
    if (auto s = client_.subscribe_samples(dev, [this](const SampleDtu& dtu) { on_sample(dtu); })) subs.push_back(*s);
    if (options_.devices.empty()) {
        // State arrives through the subscription to every terminal.
    } else if (auto s = client_.subscribe_state(dev, [this](const NotifyState& st) { on_state(st); })) {
        subs.push_back(*s);
    }
    if (auto s = client_.subscribe_method_runs(dev, [this](const MethodRun& r) { on_method_run(r); })) subs.push_back(*s);
    if (auto s = client_.subscribe_events(dev, [this](const WatchedEvent& e) { on_event(e); })) subs.push_back(*s);
    if (auto s = client_.subscribe_version(dev, [this](const ProbeVersionRequest& v) {
            std::string version = v.version;
            bool changed = false;
            store_.read([&](const BridgeState& st) {
                const DeviceEntry* d = st.find_device(v.guid);
                changed = d && d->version != version;
                return 0;
            });
            store_.set_version(v.guid, version);
            if (changed) refresh(v.guid);
        }))
        subs.push_back(*s);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        subscriptions_.insert(subscriptions_.end(), subs.begin(), subs.end());
    }
    // The retained state may have come before we followed (discovery): ask for the model now.
    refresh(dev);
}

void Follower::on_state(const NotifyState& state) {
    if (state.tid.empty() || (state.state != "online" && state.state != "offline")) return;
    {
        // Its own word replaces what the liveness check concluded.
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = followed_.find(state.tid);
        if (it == followed_.end()) return;
        (void)it->second.heard_now();
    }
    store_.set_state(state.tid, state.state);
    if (state.state == "online") refresh(state.tid);
}

void Follower::refresh(const std::string& dev) {
    std::uint64_t epoch = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = followed_.find(dev);
        if (it == followed_.end()) return;
        if (it->second.refreshing) {
            it->second.refresh_again = true;
            return;
        }
        it->second.refreshing = true;
        epoch = ++it->second.epoch;
    }
    client_.probe_async(
        dev, [this, dev, epoch](Result<Json> model) { after_probe(dev, epoch, std::move(model)); }, request_options_);
}

void Follower::after_probe(const std::string& dev, std::uint64_t epoch, Result<Json> model) {
    bool again = false;
    auto finish = [&] {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = followed_.find(dev);
        if (it == followed_.end()) return;
        it->second.refreshing = false;
        again = it->second.refresh_again;
        it->second.refresh_again = false;
    };
    if (!model) {
        options_.logger.warn("bridge: Probe/Query of {} failed: {}", dev, model.error().describe());
        finish();
        if (again) refresh(dev);
        return;
    }
    if (auto set = store_.set_model(dev, *model); !set) {
        options_.logger.error("bridge: model of {} cannot be served: {}", dev, set.error().describe());
        finish();
        return;
    }
    // An adapter that answers is online even before its retained state
    // arrived, and again after a liveness check had found it silent.
    bool was_silent = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (auto it = followed_.find(dev); it != followed_.end()) was_silent = it->second.heard_now();
    }
    std::string state;
    std::shared_ptr<const Model> loaded;
    store_.read([&](const BridgeState& st) {
        if (const DeviceEntry* d = st.find_device(dev)) {
            state = d->state;
            loaded = d->model;
        }
        return 0;
    });
    if (state == "unknown" || was_silent) store_.set_state(dev, "online");
    if (!loaded) {
        finish();
        return;
    }
    // Every data object: Query for initial values; the ones in no channel also by event or poll.
    std::set<std::string> in_channel;
    double shortest = 0;
    for (const auto& c : loaded->channels()) {
        in_channel.insert(c.ids.begin(), c.ids.end());
        if (c.sample_interval_ms > 0 && (shortest == 0 || c.sample_interval_ms < shortest)) shortest = c.sample_interval_ms;
    }
    std::vector<std::string> all, unchanneled;
    for (const auto& o : loaded->data_objects()) {
        if (o.value) continue;  // constant
        all.push_back(o.id);
        if (!in_channel.count(o.id)) unchanneled.push_back(o.id);
    }
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = followed_.find(dev);
        if (it != followed_.end() && it->second.epoch == epoch) {
            Followed& f = it->second;
            // Old registrations went with the adapter's restart or the old model; drop ours too.
            for (const auto& id : f.event_ids) client_.unregister_event_async(dev, id, [](Result<void>) {});
            f.event_ids.clear();
            f.model = loaded;
            f.polled.clear();
            f.poll_interval = std::max(options_.poll_interval, std::chrono::milliseconds(static_cast<long long>(shortest)));
            f.next_poll = std::chrono::steady_clock::now() + f.poll_interval;
            f.check_item = all.empty() ? std::string() : all.front();
            for (const auto& id : unchanneled) {
                const DataObject* o = loaded->data_object(id);
                if (!options_.use_events || (o && o->kind != DataKind::single)) f.polled.push_back(id);
            }
        }
    }
    query_items(dev, all);
    if (options_.use_events) register_events(dev, epoch);
    finish();
    if (again) refresh(dev);
}

void Follower::register_events(const std::string& dev, std::uint64_t epoch) {
    std::shared_ptr<const Model> model;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = followed_.find(dev);
        if (it == followed_.end() || it->second.epoch != epoch) return;
        model = it->second.model;
    }
    std::set<std::string> in_channel;
    for (const auto& c : model->channels()) in_channel.insert(c.ids.begin(), c.ids.end());
    for (const auto& o : model->data_objects()) {
        if (o.value || in_channel.count(o.id) || o.kind != DataKind::single) continue;
        Client::EventRegistration registration;
        registration.id = o.id;
        registration.trigger = "always";
        const std::string item = o.id;
        client_.register_event_async(
            dev, registration,
            [this, dev](const EventData& e) {
                heard(dev);
                store_.update(dev, e.event.id, e.event.value, e.time > 0 ? e.time : now_ms());
            },
            [this, dev, item, epoch](Result<std::string> id) {
                std::lock_guard<std::mutex> lock(mutex_);
                auto it = followed_.find(dev);
                if (it == followed_.end()) return;
                if (it->second.epoch != epoch) {
                    if (id) client_.unregister_event_async(dev, *id, [](Result<void>) {});
                    return;
                }
                if (id) {
                    it->second.event_ids.push_back(*id);
                } else {
                    options_.logger.debug("bridge: no event for {}/{} ({}); polling it", dev, item, id.error().describe());
                    it->second.polled.push_back(item);
                }
            },
            request_options_);
    }
}

void Follower::query_items(const std::string& dev, const std::vector<std::string>& ids) {
    if (ids.empty()) return;
    std::vector<QueryItem> items;
    items.reserve(ids.size());
    for (const auto& id : ids) items.push_back(QueryItem{id, std::nullopt});
    client_.query_async(
        dev, std::move(items),
        [this, dev](Result<std::vector<QueryResult>> results) {
            if (!results) return;
            heard(dev);
            store_answers(dev, *results);
        },
        request_options_);
}

void Follower::store_answers(const std::string& dev, const std::vector<QueryResult>& results) {
    const std::int64_t now = now_ms();
    std::vector<BridgeStore::Value> values;
    for (const auto& r : results) {
        if (!r.status.ok) continue;
        // A whole-item Query answers values = [value] (8.2.12).
        Json value;
        if (r.values && r.values->is_array() && r.values->size() == 1) value = (*r.values)[0];
        else if (r.values) value = *r.values;
        values.push_back(BridgeStore::Value{r.id, std::move(value), now});
    }
    store_.update_many(dev, values);
}

// Anything the adapter published or answered: it is there. One that a
// liveness check had found silent is followed anew (online, Probe, Query,
// events: it may have restarted meanwhile and lost its registrations).
void Follower::heard(const std::string& dev) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = followed_.find(dev);
        if (it == followed_.end() || !it->second.heard_now()) return;
    }
    follow_again(dev);
}

void Follower::follow_again(const std::string& dev) {
    options_.logger.info("bridge: {} is heard again", dev);
    store_.set_state(dev, "online");
    refresh(dev);
}

// A followed adapter that has published nothing and answered nothing for
// `liveness`: its state may be stale (a last will that died with its broker
// node, a link that hangs). A Query of one item asks; a Probe/Query where the
// model has no item to query.
void Follower::check_silent(std::chrono::steady_clock::time_point now) {
    std::vector<std::pair<std::string, std::string>> candidates;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& [dev, f] : followed_)
            if (!f.checking && !f.refreshing && now - f.last_heard >= options_.liveness)
                candidates.emplace_back(dev, f.check_item);
    }
    for (auto& [dev, item] : candidates) {
        // Online by its state, or silent and asked again until it answers;
        // one offline by its own Notify/State waits for its online.
        std::string state;
        store_.read([&](const BridgeState& st) {
            if (const DeviceEntry* d = st.find_device(dev)) state = d->state;
            return 0;
        });
        {
            std::lock_guard<std::mutex> lock(mutex_);
            auto it = followed_.find(dev);
            if (it == followed_.end() || it->second.checking) continue;
            if (state != "online" && !it->second.silent) continue;
            it->second.checking = true;
            it->second.last_heard = now;  // the next check one liveness after this one
        }
        // An agent answers for an adapter it has as offline (DEV_UNREACHABLE,
        // 8.3.5): that says nothing of the adapter.
        auto answered = [](const Error& e) { return e.code != ErrorCode::timeout && e.code != ErrorCode::unavailable; };
        if (item.empty()) {
            client_.probe_async(
                dev, [this, dev, answered](Result<Json> r) { checked(dev, r || answered(r.error())); }, request_options_);
        } else {
            client_.query_async(
                dev, {QueryItem{item, std::nullopt}},
                [this, dev, answered](Result<std::vector<QueryResult>> r) {
                    if (r) store_answers(dev, *r);
                    checked(dev, r || answered(r.error()));
                },
                request_options_);
        }
    }
}

// Any answer of the adapter, an NG one too (an item the model lost, 401),
// shows it there; a request that timed out (203) or that an agent answered
// DEV_UNREACHABLE counts as silence.
void Follower::checked(const std::string& dev, bool answered) {
    bool turned_silent = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = followed_.find(dev);
        if (it == followed_.end()) return;
        it->second.checking = false;
        if (!answered && !it->second.silent) turned_silent = it->second.silent = true;
    }
    if (answered) return heard(dev);
    if (!turned_silent) return;
    options_.logger.warn(
        "bridge: {} published nothing for {} ms and did not answer a Query within {} ms: UNAVAILABLE until it is heard again",
        dev, options_.liveness.count(), options_.request_timeout.count());
    store_.set_state(dev, "offline");
}

void Follower::on_sample(const SampleDtu& dtu) {
    std::shared_ptr<const Model> model;
    bool revive = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = followed_.find(dtu.guid);
        if (it == followed_.end()) return;
        model = it->second.model;
        revive = it->second.heard_now();
    }
    if (revive) follow_again(dtu.guid);
    if (!model) return;
    const SampleChannel* channel = model->channel(dtu.id);
    if (!channel) return;
    // One column per item of the channel, in its order; rows sampleInterval apart (8.2.15).
    std::size_t rows = 0;
    std::vector<const Json*> columns;
    for (std::size_t i = 0; i < channel->ids.size() && i < dtu.data.size(); ++i) {
        const Json& entry = dtu.data[i];
        const Json* column = entry.is_object() && entry.contains("data") ? &entry["data"] : &entry;
        if (!column->is_array()) column = nullptr;
        columns.push_back(column);
        if (column) rows = std::max(rows, column->size());
    }
    std::vector<BridgeStore::Value> values;
    values.reserve(rows * columns.size());
    for (std::size_t row = 0; row < rows; ++row) {
        const std::int64_t time =
            dtu.begin_time + static_cast<std::int64_t>(static_cast<double>(row) * channel->sample_interval_ms);
        for (std::size_t i = 0; i < columns.size(); ++i) {
            if (!columns[i] || row >= columns[i]->size()) continue;
            values.push_back(BridgeStore::Value{channel->ids[i], (*columns[i])[row], time});
        }
    }
    store_.update_many(dtu.guid, values);
}

void Follower::on_method_run(const MethodRun& run) {
    auto call_id = [](const MessageId& id) {
        if (!id) return std::string();
        return id->is_string() ? id->get<std::string>() : id->dump();
    };
    BridgeStore::MethodRunUpdate update;
    update.ex = run.ex;
    if (run.status) {
        update.call = call_id(run.status->msg_id);
        update.method = run.status->id;
        update.status = run.status->status;
        update.progress = run.status->progress;
    } else if (run.result) {
        update.call = call_id(run.result->msg_id);
        update.method = run.result->id;
        update.result = run.result->result.empty() ? std::string("error") : run.result->result;
        Json outcome{{"code", run.result->status.ok ? "OK" : "NG"}};
        if (run.result->status.error) outcome["error"] = *run.result->status.error;
        if (run.result->status.reason) outcome["reason"] = *run.result->status.reason;
        if (run.result->return_value) outcome["return"] = *run.result->return_value;
        update.outcome = std::move(outcome);
    }
    heard(run.dev);
    if (update.call.empty()) return;  // without the call's @id a DTU belongs to no run (8.2.23)
    store_.record_method_run(run.dev, std::move(update), now_ms());
}

void Follower::on_event(const WatchedEvent& event) {
    // The bridge's own registrations are its change events: their values
    // are already in the model tree (register_events).
    heard(event.dev);
    if (event.ex == client_.ex_cid()) return;
    EventLogEntry entry;
    entry.ex = event.ex;
    entry.event_id = event.event.id;
    entry.item = event.event.event.id;
    entry.value = event.event.event.value;
    entry.time_ms = event.event.time > 0 ? event.event.time : now_ms();
    store_.record_event(event.dev, std::move(entry));
}

void Follower::housekeeping() {
    auto next_discovery = std::chrono::steady_clock::now();
    while (running_) {
        const auto now = std::chrono::steady_clock::now();
        if (options_.devices.empty() && now >= next_discovery) {
            next_discovery = now + options_.discovery_interval;
            client_.discover_async(
                [this](Result<std::vector<DeviceListEntry>> list) {
                    if (!list) return;  // no agent: states alone tell the adapters
                    for (const auto& entry : *list)
                        if (entry.status == "online") consider(entry.guid);
                },
                request_options_);
        }
        std::vector<std::pair<std::string, std::vector<std::string>>> due;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            for (auto& [dev, f] : followed_) {
                if (f.polled.empty() || now < f.next_poll) continue;
                f.next_poll = now + f.poll_interval;
                due.emplace_back(dev, f.polled);
            }
        }
        for (const auto& [dev, ids] : due) {
            bool online = false;
            store_.read([&](const BridgeState& st) {
                const DeviceEntry* d = st.find_device(dev);
                online = d && d->state == "online";
                return 0;
            });
            if (online) query_items(dev, ids);
        }
        if (options_.liveness.count() > 0) check_silent(now);
        std::unique_lock<std::mutex> lock(wake_mutex_);
        wake_.wait_for(lock, std::chrono::milliseconds(50), [this] { return !running_; });
    }
}

Result<std::vector<SetResult>> Follower::set(const std::string& dev, std::vector<SetItem> items) {
    return client_.set(dev, std::move(items), request_options_);
}

Result<MethodResult> Follower::call(const std::string& dev, const std::string& method, Json args,
                                    std::chrono::milliseconds timeout) {
    // The client's own timeout restarts with every Method/Status (a long run
    // keeps its call alive); `timeout` bounds the whole wait. The completion
    // may come after this returned: it holds the state, not this frame.
    struct Waiting {
        std::mutex mutex;
        std::condition_variable done;
        std::optional<Result<MethodResult>> result;
    };
    auto waiting = std::make_shared<Waiting>();
    client_.call_method_async(
        dev, method, std::move(args), {},
        [waiting](Result<MethodResult> r) {
            std::lock_guard<std::mutex> lock(waiting->mutex);
            waiting->result.emplace(std::move(r));
            waiting->done.notify_all();
        },
        request_options_);
    std::unique_lock<std::mutex> lock(waiting->mutex);
    if (!waiting->done.wait_for(lock, timeout, [&] { return waiting->result.has_value(); }))
        return make_error(ErrorCode::timeout,
                          "no Method/Result of " + method + " within " + std::to_string(timeout.count()) + " ms");
    return std::move(*waiting->result);
}

}  // namespace nclink::bridge
