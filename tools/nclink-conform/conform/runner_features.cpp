// The feature items of run_conformance(): sampling (table 58), dynamic sampling (table 60), data set (table 57 item 2) and
// model set (table 56 item 2). Methods (table 62): runner_methods.cpp.
#include "conform/checks_fidelity.hpp"
#include "conform/runner_impl.hpp"

#include <nclink/dtu_common.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <thread>

namespace nclink::conform::detail {
namespace {

bool numbers_equal(const Json& a, const Json& b) {
    if (a.is_number() && b.is_number())
        return std::abs(a.get<double>() - b.get<double>()) <= 1e-9 * std::max(1.0, std::abs(a.get<double>()));
    return a == b;
}

}  // namespace

bool is_topic(const Captured& c, TopicKind kind) {
    auto t = parse_topic(c.message.topic);
    return t && t->kind == kind;
}

std::optional<std::string> model_channel_of(const Captured& c, const std::string& dev) {
    auto t = parse_topic(c.message.topic);
    if (!t || t->kind != TopicKind::sample || t->dev != dev || !t->channel) return std::nullopt;
    return t->channel;
}

std::vector<ChannelSpec> Runner::channel_specs() const {
    std::vector<ChannelSpec> out;
    if (!model || !device) return out;
    for (const auto& ch : model->channels()) {
        if (!ch.device_id.empty() && ch.device_id != device->id) continue;
        out.push_back(ChannelSpec{ch.id, ch.ids.size(), ch.sample_interval_ms, ch.upload_interval_ms});
    }
    return out;
}

// ---- sampling (table 58) --------------------------------------------------------------------

void Runner::sampling() {
    auto& s = item("sampling");
    if (!device) {
        s.skip("no usable model");
        return;
    }
    const auto specs = channel_specs();
    if (specs.empty()) {
        s.not_supported("the model defines no sample channel (9.3.3: table 63 item 2 need not be tested)");
        return;
    }
    // Samples have been recorded since the run began; wait for at least three
    // DTUs per channel, bounded by the slowest channel and --max-wait-ms.
    double slowest = 0;
    for (const auto& c : specs) slowest = std::max(slowest, std::max(c.upload_ms, c.sample_ms));
    const auto window = std::min(opts.max_wait, std::chrono::milliseconds(static_cast<long long>(3.5 * slowest)) + opts.timeout);
    const auto began = std::chrono::steady_clock::now();
    std::map<std::string, std::vector<Captured>> by_channel;
    while (true) {
        by_channel.clear();
        for (auto& c : wire.collect(start_mark, [&](const Captured& m) { return model_channel_of(m, dev).has_value(); }))
            by_channel[*model_channel_of(c, dev)].push_back(std::move(c));
        const bool enough = std::all_of(specs.begin(), specs.end(), [&](const ChannelSpec& c) {
            auto it = by_channel.find(c.id);
            return it != by_channel.end() && it->second.size() >= 3;
        });
        if (enough || ms_since(began) >= window) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (by_channel.empty()) {
        s.not_supported(
            fmt::format("no Sample DTU on {} within {} ms although the model defines {} channel(s) "
                        "(silence is taken as not supported)",
                        topics::sample(dev, "+"), ms_since(began).count() + 0, specs.size()));
        return;
    }
    std::size_t dtus = 0;
    for (const auto& [channel, run] : by_channel) {
        if (std::none_of(specs.begin(), specs.end(), [&](const ChannelSpec& c) { return c.id == channel; }))
            fail_with(s, fmt::format("Sample DTU of channel \"{}\", which the model does not define", channel), run.front());
    }
    for (const auto& spec : specs) {
        auto it = by_channel.find(spec.id);
        if (it == by_channel.end()) {
            s.fail(fmt::format("channel \"{}\" is silent while other channels publish (no DTU on {} within {} ms)", spec.id,
                               topics::sample(dev, spec.id), window.count()));
            continue;
        }
        std::vector<SampleArrival> arrivals;
        std::size_t bad = 0;
        for (const auto& c : it->second) {
            ++dtus;
            std::string why;
            auto dtu = parse_object(c.message.payload, &why);
            if (!dtu) {
                if (++bad <= 3) fail_with(s, fmt::format("channel \"{}\": Sample DTU is {}", spec.id, why), c);
                continue;
            }
            auto checked = check_sample_dtu(*dtu, dev, spec);
            if (!checked.problems.empty() && ++bad <= 3)
                fail_with(s, fmt::format("channel \"{}\": {}", spec.id, join(checked.problems)), c);
            if (checked.shape) arrivals.push_back(SampleArrival{checked.shape->begin_time, checked.shape->rows, c.wall_ms});
        }
        if (bad > 3) s.fail(fmt::format("channel \"{}\": {} more malformed DTUs", spec.id, bad - 3));
        if (auto problems = check_sample_sequence(arrivals, spec); !problems.empty())
            fail_with(s, fmt::format("channel \"{}\" over {} DTUs: {}", spec.id, arrivals.size(), join(problems)),
                      it->second.back());
        if (it->second.size() < 3)
            s.notes.push_back(fmt::format("channel \"{}\": only {} DTU(s) within {} ms; the upload pace was not checked", spec.id,
                                          it->second.size(), window.count()));
    }
    if (s.outcome == Outcome::pass)
        s.summary =
            fmt::format("{} channel(s), {} Sample DTUs: columns, rows, beginTime continuity and upload pace match the model",
                        specs.size(), dtus);
}

// ---- dynamic sampling (table 60) ---------------------------------------------------------------

void Runner::dynamic_sampling() {
    auto& reg = item("dynamic-register");
    auto& data = item("dynamic-sample");
    auto& unreg = item("dynamic-unregister");
    if (!device) {
        for (auto* i : {&reg, &data, &unreg}) i->skip("no usable model");
        return;
    }
    // Up to three items the model already samples, else the first single data items.
    std::vector<std::string> ids;
    if (const auto specs = channel_specs(); !specs.empty())
        for (const auto* obj : model->channel_items(specs.front().id))
            if (ids.size() < 3) ids.push_back(obj->id);
    if (ids.empty())
        for (const auto* obj : served_items(*model, *device))
            if (ids.size() < 3 && obj->kind == DataKind::single && !obj->config) ids.push_back(obj->id);
    if (ids.empty()) {
        for (auto* i : {&reg, &data, &unreg}) i->skip("the model has no data object to sample");
        return;
    }
    const ChannelSpec wanted{"", ids.size(), 100, 500};
    Json list = Json::array();
    for (const auto& id : ids) list.push_back(Json{{"id", id}});
    const auto before = wire.mark();
    auto x = request_kind(
        TopicKind::sample_register_request,
        Json{{"guid", dev}, {"sampleInterval", wanted.sample_ms}, {"uploadInterval", wanted.upload_ms}, {"ids", list}});
    if (settle_unusable(reg, x, true)) {
        for (auto* i : {&data, &unreg}) {
            if (reg.outcome == Outcome::not_supported) i->not_supported("dynamic sampling registration is not supported");
            else i->skip("the registration failed");
        }
        return;
    }
    if (auto problems = check_sample_register_response(*x.dtu, x.sent_id, dev); !problems.empty())
        fail_with(reg, join(problems), x);
    if (!is_ok(*x.dtu) || x.dtu->value("id", std::string()).empty()) {
        if (!is_ok(*x.dtu)) fail_with(reg, "dynamic sampling of items the model samples was refused", x);
        for (auto* i : {&data, &unreg}) i->skip("the registration failed");
        return;
    }
    ChannelSpec spec = wanted;
    spec.id = x.dtu->value("id", std::string());
    if (reg.outcome == Outcome::pass)
        reg.summary =
            fmt::format("channel \"{}\" registered for {} item(s) every 100 ms, uploaded every 500 ms", spec.id, ids.size());

    const std::string topic = topics::dynamic_sample(dev, ex, spec.id);
    const auto on_topic = [&](const Captured& m) { return m.message.topic == topic; };
    const auto window = std::min(opts.max_wait, std::chrono::milliseconds(4 * 500) + opts.timeout);
    auto got = wire.wait_count(before, on_topic, 3, window);
    if (got.empty()) {
        data.fail(fmt::format("channel \"{}\" registered, but no DTU on {} within {} ms", spec.id, topic, window.count()));
    } else {
        std::vector<SampleArrival> arrivals;
        for (const auto& c : got) {
            std::string why;
            auto dtu = parse_object(c.message.payload, &why);
            if (!dtu) {
                fail_with(data, "Sample DTU is " + why, c);
                continue;
            }
            auto checked = check_sample_dtu(*dtu, dev, spec);
            if (!checked.problems.empty()) fail_with(data, join(checked.problems), c);
            if (checked.shape) arrivals.push_back(SampleArrival{checked.shape->begin_time, checked.shape->rows, c.wall_ms});
        }
        if (auto problems = check_sample_sequence(arrivals, spec); !problems.empty())
            fail_with(data, fmt::format("over {} DTUs: {}", arrivals.size(), join(problems)), got.back());
        if (data.outcome == Outcome::pass)
            data.summary =
                fmt::format("{} DTU(s) on {} with {} column(s) at the registered intervals", got.size(), topic, ids.size());
    }

    auto u = request_kind(TopicKind::sample_unregister_request, Json{{"guid", dev}, {"id", spec.id}});
    if (settle_unusable(unreg, u, true)) return;
    if (auto problems = check_unregister_response(*u.dtu, u.sent_id, dev); !problems.empty()) fail_with(unreg, join(problems), u);
    if (!is_ok(*u.dtu)) {
        fail_with(unreg, fmt::format("unregistering channel \"{}\" was refused", spec.id), u);
        return;
    }
    // One upload interval may be under way when the answer goes out.
    std::this_thread::sleep_for(std::chrono::milliseconds(1300));
    const auto quiet_after = u.reply->at + std::chrono::milliseconds(800);
    for (const auto& c : wire.collect(u.reply->seq, on_topic)) {
        if (c.at > quiet_after) {
            fail_with(unreg, fmt::format("channel \"{}\" still publishes after Unregister/Sample was answered OK", spec.id), c);
            break;
        }
    }
    if (unreg.outcome == Outcome::pass) unreg.summary = fmt::format("channel \"{}\" unregistered; no data after it", spec.id);
}

// ---- data set (table 57 item 2) -------------------------------------------------------------------

void Runner::set() {
    auto& s = item("set");
    if (!opts.allow_write) {
        s.skip(needs_write);
        return;
    }
    if (!device) {
        s.skip("no usable model");
        return;
    }
    std::size_t changed = 0, rewritten = 0, unsupported = 0, tried = 0;
    const auto send_set = [&](const std::string& id, const Json& params) {
        return request_kind(TopicKind::set_request,
                            Json{{"guid", dev}, {"values", Json::array({Json{{"id", id}, {"params", params}}})}});
    };
    // Checks a one-item Set answer; returns the entry when usable. Refusals
    // as unavailable are counted (the feature may be unsupported as a whole).
    std::optional<Evidence> unsupported_evidence;
    bool refused_unavailable = false;
    const auto settle_set = [&](const Exchange& x, const std::string& id) -> const Json* {
        refused_unavailable = false;
        ItemResult scratch;
        if (settle_unusable(scratch, x, true)) {
            if (scratch.outcome == Outcome::not_supported) {
                refused_unavailable = true;
                if (!unsupported_evidence)
                    unsupported_evidence = scratch.evidence.empty() ? Evidence{scratch.summary, x.topic, x.request.dump()}
                                                                    : scratch.evidence.front();
            } else {
                for (auto& e : scratch.evidence) s.fail(e.note, e.topic, e.dtu);
            }
            return nullptr;
        }
        for (auto& e : scratch.evidence) s.fail(e.note, e.topic, e.dtu);  // unmirrored answer
        if (auto problems = check_set_response(*x.dtu, x.sent_id, dev, {id}); !problems.empty()) {
            fail_with(s, join(problems), x);
            return nullptr;
        }
        const Json* e = result_entry(*x.dtu, 0);
        if (e && says_not_supported(*e)) {
            refused_unavailable = true;
            if (!unsupported_evidence)
                unsupported_evidence = Evidence{"the adapter answers NG 202 for the item", x.reply->message.topic, e->dump()};
            return nullptr;
        }
        return e;
    };
    for (const auto* obj : served_items(*model, *device)) {
        if (!obj->setable || !whole_values.count(obj->id)) continue;
        const Json original = whole_values[obj->id];
        Json params, check_params, expect;
        bool change = false;
        if (obj->kind == DataKind::single) {
            if (original.is_number()) {
                expect = original.get<double>() >= 1 ? Json(original.get<double>() - 1) : Json(original.get<double>() + 1);
                if (original.is_number_integer() || original.is_number_unsigned())
                    expect = original.get<std::int64_t>() >= 1 ? Json(original.get<std::int64_t>() - 1)
                                                               : Json(original.get<std::int64_t>() + 1);
                change = true;
            } else if (original.is_boolean()) {
                expect = !original.get<bool>();
                change = true;
            } else {
                expect = original;  // no value is known to be safe: write the same one back
            }
            params = Json{{"value", expect}};
        } else if (obj->kind == DataKind::list && original.is_array() && !original.empty()) {
            expect = original[0];
            params = Json{{"index", 0}, {"value", expect}};
            check_params = Json{{"operation", "get_value"}, {"indexes", Json::array({"0"})}};
        } else if (obj->kind == DataKind::dict && original.is_object() && !original.empty()) {
            expect = original.begin().value();
            params = Json{{"key", original.begin().key()}, {"value", expect}};
            check_params = Json{{"operation", "get_value"}, {"keys", Json::array({original.begin().key()})}};
        } else {
            s.notes.push_back(fmt::format("{}: empty or unknown value, not written", obj->id));
            continue;
        }
        ++tried;
        auto x = send_set(obj->id, params);
        const Json* e = settle_set(x, obj->id);
        if (refused_unavailable) ++unsupported;
        if (!e) continue;
        if (!is_ok(*e)) {
            s.fail(fmt::format("{}: Set of a setable item to {} answered NG", obj->id, expect.dump()), x.reply->message.topic,
                   e->dump());
            continue;
        }
        if (auto echo = check_set_echo(*e, params); !echo.empty())
            s.fail(fmt::format("{}: {}", obj->id, join(echo)), x.reply->message.topic, e->dump());
        std::string why;
        auto now = query_value(obj->id, check_params, &why);
        if (!now) s.fail(fmt::format("{}: Query after Set: {}", obj->id, why));
        else if (!numbers_equal(*now, expect))
            s.fail(fmt::format("{}: Set to {} answered OK, but a Query then answers {}", obj->id, expect.dump(), now->dump()),
                   x.reply->message.topic, x.reply->message.payload);
        if (change) {
            ++changed;
            auto r = send_set(obj->id, Json{{"value", original}});
            const Json* re = settle_set(r, obj->id);
            auto back = query_value(obj->id, Json(), &why);
            if (!re || !is_ok(*re) || !back || !numbers_equal(*back, original))
                s.fail(fmt::format("{}: COULD NOT RESTORE the original value {} (now {}): restore it by hand", obj->id,
                                   original.dump(), back ? back->dump() : why),
                       r.reply ? r.reply->message.topic : r.topic, r.reply ? r.reply->message.payload : r.request.dump());
        } else {
            ++rewritten;
        }
    }
    // Non-setable items are refused with 301 (the current value is written, so
    // even a wrong acceptance changes nothing).
    for (const auto* obj : served_items(*model, *device)) {
        if (obj->setable || obj->kind != DataKind::single || !whole_values.count(obj->id)) continue;
        auto x = send_set(obj->id, Json{{"value", whole_values[obj->id]}});
        const Json* e = settle_set(x, obj->id);
        if (e && (is_ok(*e) || e->value("error", Json()) != Json(301)))
            s.fail(
                fmt::format("{}: Set of an item that is not setable must answer NG 301 \"Permission Denied\" (table 19)", obj->id),
                x.reply->message.topic, e->dump());
        break;
    }
    if (s.outcome == Outcome::fail) return;
    if (tried == 0) {
        if (s.outcome == Outcome::pass) s.skip("the model has no setable data object with a known value");
        return;
    }
    if (unsupported == tried) {
        const Evidence e = unsupported_evidence.value_or(Evidence{});
        s.not_supported(fmt::format("Set of the model's setable items is not supported ({} of {} refused as unavailable or "
                                    "unanswered): {}",
                                    unsupported, tried, e.note),
                        e.topic, e.dtu);
        return;
    }
    if (unsupported > 0) {
        const Evidence e = unsupported_evidence.value_or(Evidence{});
        s.fail(fmt::format("{} of {} setable items refused as unavailable while others can be set", unsupported, tried), e.topic,
               e.dtu);
        return;
    }
    s.summary = fmt::format(
        "{} setable item(s): {} changed, checked by Query and restored; {} rewritten with their value; "
        "a non-setable item answers 301",
        tried - unsupported, changed, rewritten);
}

// ---- model set (table 56 item 2) ----------------------------------------------------------------

void Runner::model_set() {
    auto& m = item("model-set");
    if (!opts.allow_write) {
        m.skip(needs_write);
        return;
    }
    if (!device || !raw_model.is_object()) {
        m.skip("no usable model");
        return;
    }
    Json* raw_device = nullptr;
    Json bumped = raw_model;
    if (auto devices = bumped.find("devices"); devices != bumped.end() && devices->is_array())
        for (auto& d : *devices)
            if (d.is_object() && (d.value("guid", std::string()) == dev || d.value("id", std::string()) == device->id))
                raw_device = &d;
    if (!raw_device) {
        m.fail("the device cannot be found in the probe's \"devices\"");
        return;
    }
    refused_model_set(m);
    const std::string old_version = device->version;
    const std::string new_version = bump_version(old_version);
    (*raw_device)["version"] = new_version;

    const auto version_seen = [&](std::uint64_t from, const std::string& version) {
        return wire.wait_for(
            from,
            [&](const Captured& c) {
                if (c.message.topic != topics::probe_version(dev)) return false;
                auto dtu = parse_object(c.message.payload);
                return dtu && dtu->value("version", std::string()) == version;
            },
            opts.timeout);
    };
    const auto before_set = wire.mark();  // Probe/Version may overtake the answer
    auto x = request_kind(TopicKind::probe_set_request, Json{{"guid", dev}, {"probe", bumped}});
    if (settle_unusable(m, x, true)) return;
    if (auto problems = check_envelope(*x.dtu, x.sent_id, dev, false); !problems.empty()) fail_with(m, join(problems), x);
    if (auto problems = check_status_keys(*x.dtu); !problems.empty()) fail_with(m, join(problems), x);
    if (!is_ok(*x.dtu)) {
        fail_with(m, fmt::format("Probe/Set of the adapter's own model with version {} was refused", new_version), x);
        return;
    }
    if (!version_seen(before_set, new_version))
        m.fail(fmt::format("no Probe/Version/{} with version \"{}\" after the model was replaced (table 56 item 2b, 8.2.9.3)",
                           dev, new_version));
    std::string why;
    auto p = request_kind(TopicKind::probe_query_request, Json{{"guid", dev}});
    if (p.dtu) {
        auto checked = check_probe_response(*p.dtu, p.sent_id, dev);
        LoadResult now = checked.model ? parse_model(checked.model->dump()) : LoadResult{};
        const Device* d = now.model ? device_for(*now.model, dev) : nullptr;
        if (!d || d->version != new_version)
            fail_with(m,
                      fmt::format("after Probe/Set the probe still shows version \"{}\", expected \"{}\"", d ? d->version : "?",
                                  new_version),
                      p);
    } else {
        m.fail("no answer to Probe/Query after Probe/Set");
    }
    // Restore the original model, exactly as probed.
    const auto before_restore = wire.mark();
    auto r = request_kind(TopicKind::probe_set_request, Json{{"guid", dev}, {"probe", raw_model}});
    bool restored = r.dtu && is_ok(*r.dtu);
    if (!restored) {
        r = request_kind(TopicKind::probe_set_request, Json{{"guid", dev}, {"probe", raw_model}});  // once more
        restored = r.dtu && is_ok(*r.dtu);
    }
    if (!restored) {
        fail_with(m,
                  fmt::format("COULD NOT RESTORE the original model (version \"{}\"): the adapter now runs version \"{}\"; "
                              "send the original model with Probe/Set",
                              old_version, new_version),
                  r);
        return;
    }
    if (!version_seen(before_restore, old_version))
        m.fail(fmt::format("no Probe/Version/{} with version \"{}\" after the original model was restored", dev, old_version));
    auto back = request_kind(TopicKind::probe_query_request, Json{{"guid", dev}});
    auto checked = back.dtu ? check_probe_response(*back.dtu, back.sent_id, dev) : ProbeCheck{};
    LoadResult again = checked.model ? parse_model(checked.model->dump()) : LoadResult{};
    if (!again.model || *again.model != *model) fail_with(m, "after restoring, the probed model differs from the original", back);
    if (m.outcome == Outcome::pass)
        m.summary = fmt::format("version {} -> {} accepted and announced by Probe/Version, original model restored and announced",
                                old_version, new_version);
}

// ---- methods (table 62) ------------------------------------------------------------------------------

}  // namespace nclink::conform::detail
