// The events item of run_conformance() (table 59): register a change event
// on an item that moves, expect Event DTUs of table 52, unregister.
#include "conform/runner_impl.hpp"

#include <nclink/dtu_common.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <thread>

namespace nclink::conform::detail {
namespace {

// beginTime of a Sample DTU in ms (a string or a number, docs/wire.md); 0 if absent.
std::int64_t begin_time_ms(const Json& dtu) {
    const auto it = dtu.find("beginTime");
    if (it == dtu.end()) return 0;
    if (it->is_number()) return it->get<std::int64_t>();
    if (it->is_string()) {
        try {
            return std::stoll(it->get<std::string>());
        } catch (const std::exception&) {
            return 0;
        }
    }
    return 0;
}

std::int64_t wall_ms_now() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

bool Runner::moved_since(const std::string& id, std::uint64_t mark, const std::optional<Json>& before, std::int64_t since_wall_ms) {
    // Its Sample rows stamped from `since_wall_ms` on (a DTU arriving in the
    // window also holds rows sampled before it): two different non-null
    // values, or one differing from the value before.
    for (const auto& c : wire.collect(mark, [&](const Captured& m) { return model_channel_of(m, dev).has_value(); })) {
        const auto* ch = model->channel(*model_channel_of(c, dev));
        auto dtu = parse_object(c.message.payload);
        if (!ch || !dtu || !dtu->contains("data") || !(*dtu)["data"].is_array()) continue;
        const Json& data = (*dtu)["data"];
        for (std::size_t k = 0; k < data.size() && k < ch->ids.size(); ++k) {
            if (ch->ids[k] != id) continue;
            const Json& col = data[k];
            if (!col.is_object() || !col.contains("data") || !col["data"].is_array()) continue;
            const Json* first = before && !before->is_null() ? &*before : nullptr;
            const std::int64_t begin = begin_time_ms(*dtu);
            const double interval = ch->sample_interval_ms;
            const Json& rows = col["data"];
            for (std::size_t r = 0; r < rows.size(); ++r) {
                const Json& v = rows[r];
                if (v.is_null() || begin + static_cast<std::int64_t>(static_cast<double>(r) * interval) < since_wall_ms) continue;
                if (first == nullptr) first = &v;
                else if (v != *first) return true;
            }
        }
    }
    // A Query now against the value before.
    if (!before || before->is_null()) return false;
    std::string why;
    auto now = query_value(id, Json(), &why);
    return now && !now->is_null() && *now != *before;
}

// ---- events (table 59) ----------------------------------------------------------------------

std::string Runner::changing_item(bool* seen_changing) {
    *seen_changing = true;
    // 1. A sampled column whose values vary.
    for (const auto& c : wire.collect(start_mark, [&](const Captured& m) { return model_channel_of(m, dev).has_value(); })) {
        const auto* ch = model->channel(*model_channel_of(c, dev));
        auto dtu = parse_object(c.message.payload);
        if (!ch || !dtu || !dtu->contains("data") || !(*dtu)["data"].is_array()) continue;
        const Json& data = (*dtu)["data"];
        for (std::size_t k = 0; k < data.size() && k < ch->ids.size(); ++k) {
            const Json& col = data[k];
            if (!col.is_object() || !col.contains("data") || !col["data"].is_array()) continue;
            const Json& v = col["data"];
            const auto* obj = model->data_object(ch->ids[k]);
            if (!obj || obj->kind != DataKind::single) continue;
            for (std::size_t r = 1; r < v.size(); ++r)
                if (v[r] != v[0] && !v[r].is_null() && !v[0].is_null()) return ch->ids[k];
        }
    }
    // 2. A single item whose value differs from the Query item's answer.
    std::vector<std::string> candidates;
    for (const auto* obj : served_items(*model, *device))
        if (obj->kind == DataKind::single && !obj->value && whole_values.count(obj->id)) candidates.push_back(obj->id);
    for (std::size_t k = 0; k < candidates.size() && k < 64; ++k) {
        std::string why;
        auto now = query_value(candidates[k], Json(), &why);
        if (now && *now != whole_values[candidates[k]]) return candidates[k];
    }
    *seen_changing = false;
    if (!candidates.empty()) return candidates.front();
    for (const auto* obj : served_items(*model, *device))
        if (obj->kind == DataKind::single) return obj->id;
    return {};
}

void Runner::events() {
    auto& reg = item("event-register");
    auto& data = item("event-data");
    auto& unreg = item("event-unregister");
    if (!device) {
        for (auto* i : {&reg, &data, &unreg}) i->skip("no usable model");
        return;
    }
    bool changing = false;
    const std::string target = changing_item(&changing);
    if (target.empty()) {
        for (auto* i : {&reg, &data, &unreg}) i->skip("the model has no single-valued data object to watch");
        return;
    }
    Json filters = Json::array({Json{{"type", "change"}}});
    const auto before = wire.mark();  // an event may overtake the registration's answer
    auto x = request_kind(TopicKind::event_register_request,
                          Json{{"guid", dev}, {"id", target}, {"filters", filters}, {"triggerType", "always"}});
    if (settle_unusable(reg, x, true)) {
        const std::string why = reg.outcome == Outcome::fail ? "the registration failed" : "event registration is not supported";
        for (auto* i : {&data, &unreg}) {
            if (reg.outcome == Outcome::not_supported) i->not_supported(why);
            else i->skip(why);
        }
        return;
    }
    if (auto problems = check_event_register_response(*x.dtu, x.sent_id, dev); !problems.empty())
        fail_with(reg, join(problems), x);
    if (!is_ok(*x.dtu)) {
        fail_with(reg, fmt::format("a change event on \"{}\" was refused", target), x);
        for (auto* i : {&data, &unreg}) i->skip("the registration failed");
        return;
    }
    const std::string event_id = x.dtu->value("id", std::string());
    if (event_id.empty()) {
        for (auto* i : {&data, &unreg}) i->skip("the registration gave no event id");
        return;
    }
    if (reg.outcome == Outcome::pass) reg.summary = fmt::format("change event on \"{}\" registered as \"{}\"", target, event_id);
    // Its value once registered: whether it moved during the window is judged against it.
    const std::int64_t registered_ms = wall_ms_now();
    std::string unused;
    const std::optional<Json> at_register = query_value(target, Json(), &unused);

    // Event data: the first events of this id (table 52).
    const auto is_ours = [&](const Captured& m) {
        auto t = parse_topic(m.message.topic);
        if (!t || t->kind != TopicKind::event || t->dev != dev || (t->ex && *t->ex != ex)) return false;
        auto id = parse_object(m.message.payload);
        return id && id->value("id", std::string()) == event_id;
    };
    const auto window = std::max(opts.timeout, std::chrono::milliseconds(3000));
    auto got = wire.wait_count(before, is_ours, 3, window);
    if (got.empty()) {
        // An item seen moving earlier may stand still now (a mill's Z while
        // it cuts in XY): only a change inside the window owes an Event.
        if (moved_since(target, before, at_register, registered_ms))
            data.fail(fmt::format("\"{}\" changed during the window, but no Event \"{}\" arrived on {} within {} ms", target,
                                  event_id, topics::event(dev, ex), window.count()));
        else
            data.skip(fmt::format("no event within {} ms, and \"{}\" did not change during it ({})", window.count(), target,
                                  changing ? "it was seen changing earlier" : "no item of the model was seen changing"));
    } else {
        for (const auto& c : got) {
            auto dtu = parse_object(c.message.payload);
            if (auto problems = check_event_data(*dtu, dev, event_id, target); !problems.empty()) {
                fail_with(data, join(problems), c);
                break;
            }
        }
        if (data.outcome == Outcome::pass)
            data.summary = fmt::format("{} Event DTU(s) for \"{}\" with the shape of table 52", got.size(), target);
    }

    // Unregister, then no more events.
    auto u = request_kind(TopicKind::event_unregister_request, Json{{"guid", dev}, {"id", event_id}});
    if (settle_unusable(unreg, u, true)) return;
    if (auto problems = check_unregister_response(*u.dtu, u.sent_id, dev); !problems.empty()) fail_with(unreg, join(problems), u);
    if (!is_ok(*u.dtu)) {
        fail_with(unreg, fmt::format("unregistering event \"{}\" was refused", event_id), u);
        return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    const auto quiet_after = u.reply->at + std::chrono::milliseconds(300);
    for (const auto& c : wire.collect(u.reply->seq, is_ours)) {
        if (c.at > quiet_after) {
            fail_with(unreg, fmt::format("Event \"{}\" still arrives after Unregister/Event was answered OK", event_id), c);
            break;
        }
    }
    if (unreg.outcome == Outcome::pass) unreg.summary = fmt::format("event \"{}\" unregistered; no event after it", event_id);
}

}  // namespace nclink::conform::detail
