#include "bridge/json_api.hpp"

#include "bridge/request_params.hpp"

#include <algorithm>
#include <limits>
#include <map>

namespace nclink::bridge {
namespace {

http::HttpResponse json_error(int status, const std::string& message) {
    return http::json_response(Json{{"error", message}}, status);
}

Json device_json(const DeviceEntry& d) {
    return Json{{"dev", d.dev}, {"name", d.mt.name}, {"state", d.state}, {"version", d.version}};
}

}  // namespace

Json JsonApi::value_json(const ItemEntry& item, const Observation& o, const std::string& state) {
    const bool good = state == "online" && !o.value.is_null();
    return Json{{"id", item.nclink_id}, {"value", o.value}, {"time", o.time_ms}, {"quality", good ? "good" : "bad"}};
}

Json JsonApi::method_run_json(const std::string& dev, const MethodRunEntry& run) {
    Json out{{"dev", dev},           {"ex", run.ex},          {"call", run.call},
             {"method", run.method}, {"start", run.start_ms}, {"time", run.time_ms}};
    if (!run.status.empty()) out["status"] = run.status;
    if (run.progress) out["progress"] = *run.progress;
    if (!run.result.empty()) out["result"] = run.result;
    if (run.outcome.is_object())
        for (const auto& [key, value] : run.outcome.items()) out[key] = value;
    return out;
}

Json JsonApi::event_json(const std::string& dev, const EventLogEntry& event) {
    return Json{{"dev", dev},         {"ex", event.ex},       {"event", event.event_id},
                {"item", event.item}, {"value", event.value}, {"time", event.time_ms}};
}

namespace {

Json activity_json(const DeviceEntry& d) {
    Json methods = Json::array(), events = Json::array();
    for (const auto& run : d.method_runs) methods.push_back(JsonApi::method_run_json(d.dev, run));
    for (const auto& e : d.events) events.push_back(JsonApi::event_json(d.dev, e));
    return Json{{"methods", std::move(methods)}, {"events", std::move(events)}};
}

std::string dump(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

}  // namespace

http::HttpResponse JsonApi::activity(const std::string& dev) const {
    return store_.read([&](const BridgeState& st) {
        const DeviceEntry* d = st.find_device(dev);
        if (!d) return json_error(404, "no device " + dev);
        Json out = activity_json(*d);
        out["dev"] = d->dev;
        return http::json_response(out);
    });
}

http::HttpResponse JsonApi::devices() const {
    Json list = Json::array();
    store_.read([&](const BridgeState& st) {
        for (const auto& d : st.devices) list.push_back(device_json(d));
        return 0;
    });
    return http::json_response(Json{{"devices", list}});
}

http::HttpResponse JsonApi::model(const std::string& dev) const {
    return store_.read([&](const BridgeState& st) {
        const DeviceEntry* d = st.find_device(dev);
        if (!d) return json_error(404, "no device " + dev);
        if (!d->model) return json_error(404, "the model of " + dev + " is not known yet");
        return http::json_response(d->model_json);
    });
}

http::HttpResponse JsonApi::nodeset(const std::string& dev, const std::string& profile_text) const {
    auto profile = opcua_profile_from_string(profile_text.empty() ? "basic" : profile_text);
    if (!profile) return json_error(400, "profile must be basic or cnc");
    std::shared_ptr<const Model> model;
    std::string uuid;
    store_.read([&](const BridgeState& st) {
        if (const DeviceEntry* d = st.find_device(dev)) {
            model = d->model;
            uuid = d->dev;
        }
        return 0;
    });
    if (!model) return json_error(404, "no device with a model named " + dev);
    MappingOptions options;
    options.opcua_profile = *profile;
    if (model->devices().size() == 1) options.dev_uuid = uuid;
    auto doc = map_to_opcua(*model, options);
    if (!doc) return json_error(500, doc.error().describe());
    return http::text_response(std::move(doc->xml), "application/xml");
}

http::HttpResponse JsonApi::set(const std::string& dev, const std::string& body) const {
    Json request = Json::parse(body, nullptr, false);
    if (request.is_discarded() || !request.is_object() || !request.contains("id") || !request["id"].is_string() ||
        (!request.contains("value") && !request.contains("params")))
        return json_error(400,
                          "the body must be a JSON object {\"id\": ..., \"value\": ...} or {\"id\": ..., \"params\": {...}}");
    bool known = false;
    store_.read([&](const BridgeState& st) {
        known = st.find_device(dev) != nullptr;
        return 0;
    });
    if (!known) return json_error(404, "no device " + dev);
    std::string target = dev;
    store_.read([&](const BridgeState& st) {
        target = st.find_device(dev)->dev;
        return 0;
    });
    SetItem item;
    item.id = request["id"].get<std::string>();
    if (request.contains("params")) {
        if (!request["params"].is_object()) return json_error(400, "params must be an object");
        item.params = request["params"];
    } else {
        item.params = Json{{"value", request["value"]}};
    }
    auto result = follower_.set(target, {item});
    if (!result) {
        return http::json_response(
            Json{{"code", "NG"}, {"error", static_cast<int>(result.error().code)}, {"reason", result.error().describe()}});
    }
    if (result->empty()) return http::json_response(Json{{"code", "NG"}, {"error", 202}, {"reason", "no answer"}});
    const SetResult& r = result->front();
    if (r.status.ok) return http::json_response(Json{{"code", "OK"}});
    return http::json_response(
        Json{{"code", "NG"}, {"error", r.status.error.value_or(0)}, {"reason", r.status.reason.value_or("")}});
}

http::HttpResponse JsonApi::call(const std::string& dev, const std::string& body) const {
    Json request = Json::parse(body, nullptr, false);
    if (request.is_discarded() || !request.is_object() || !request.contains("method") || !request["method"].is_string() ||
        request["method"].get_ref<const std::string&>().empty())
        return json_error(400, "the body must be a JSON object {\"method\": ..., \"args\": {...}, \"timeout_ms\": ...}");
    Json args = request.value("args", Json());
    if (!args.is_null() && !args.is_object()) return json_error(400, "args must be an object");
    // A run waits for its Method/Result: at most an hour, a minute unless told.
    std::int64_t timeout_ms = 60000;
    if (request.contains("timeout_ms")) {
        const Json& t = request["timeout_ms"];
        if (!t.is_number_integer() || t.get<std::int64_t>() < 1 || t.get<std::int64_t>() > 3600000)
            return json_error(400, "timeout_ms must be an integer from 1 to 3600000");
        timeout_ms = t.get<std::int64_t>();
    }
    std::string target;
    store_.read([&](const BridgeState& st) {
        if (const DeviceEntry* d = st.find_device(dev)) target = d->dev;
        return 0;
    });
    if (target.empty()) return json_error(404, "no device " + dev);
    auto result =
        follower_.call(target, request["method"].get<std::string>(), std::move(args), std::chrono::milliseconds(timeout_ms));
    // No Method/Result: NG with the client's code (203 timeout, 202 unreachable).
    if (!result)
        return http::json_response(Json{{"code", "NG"},
                                        {"result", "error"},
                                        {"error", static_cast<int>(result.error().code)},
                                        {"reason", result.error().describe()}},
                                   result.error().code == ErrorCode::timeout ? 504 : 502);
    Json answer{{"code", result->status.ok ? "OK" : "NG"}, {"result", result->result}};
    if (result->status.error) answer["error"] = *result->status.error;
    if (result->status.reason) answer["reason"] = *result->status.reason;
    if (result->return_value) answer["return"] = *result->return_value;
    if (result->private_info) answer["privateInfo"] = *result->private_info;
    return http::json_response(answer);
}

http::HttpResponse JsonApi::history(const std::string& dev, const http::HttpRequest& request) const {
    // ?id=<item>&from=<ms>&to=<ms>&max=<n>: the item's observations still in
    // the buffer with from <= time <= to, oldest first, at most max (for the
    // OPC UA server's HistoryRead).
    const auto id = request.param("id");
    if (!id || id->empty()) return json_error(400, "id (an item id) is required");
    std::int64_t from = std::numeric_limits<std::int64_t>::min(), to = std::numeric_limits<std::int64_t>::max();
    std::size_t max = 10000;
    const auto integer = [&](const char* name, std::int64_t& out) -> bool {
        const auto text = request.param(name);
        if (!text) return true;
        const bool negative = !text->empty() && (*text)[0] == '-';
        const auto digits = parse_unsigned(negative ? std::string_view(*text).substr(1) : std::string_view(*text));
        if (!digits || *digits > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return false;
        out = negative ? -static_cast<std::int64_t>(*digits) : static_cast<std::int64_t>(*digits);
        return true;
    };
    if (!integer("from", from) || !integer("to", to)) return json_error(400, "from and to must be integers (ms since the epoch)");
    if (const auto text = request.param("max")) {
        const auto n = parse_unsigned(*text);
        if (!n || *n < 1 || *n > 100000) return json_error(400, "max must be an integer from 1 to 100000");
        max = static_cast<std::size_t>(*n);
    }
    return store_.read([&](const BridgeState& st) -> http::HttpResponse {
        const DeviceEntry* d = st.find_device(dev);
        if (!d) return json_error(404, "no device " + dev);
        const auto it = d->by_nclink_id.find(*id);
        if (it == d->by_nclink_id.end()) return json_error(404, "no item " + *id + " at " + dev);
        const ItemIndex wanted = it->second;
        Json values = Json::array();
        bool more = false;
        std::int64_t oldest = 0;
        bool any = false;
        for (std::uint64_t seq = st.buffer.first_sequence(); seq <= st.buffer.last_sequence(); ++seq) {
            const Observation* o = st.buffer.find(seq);
            if (!o || o->item != wanted) continue;
            if (!any) oldest = o->time_ms;
            any = true;
            if (o->time_ms < from || o->time_ms > to) continue;
            if (values.size() == max) {
                more = true;
                break;
            }
            // quality as the stream says it: bad for UNAVAILABLE (offline, or the adapter could not read it).
            values.push_back(Json{{"value", o->value}, {"time", o->time_ms}, {"quality", o->value.is_null() ? "bad" : "good"}});
        }
        Json answer{{"dev", d->dev}, {"id", *id}, {"values", std::move(values)}, {"more", more}};
        if (any) answer["oldest"] = oldest;  // what the buffer still holds of the item begins here
        return http::json_response(answer);
    });
}

http::HttpResponse JsonApi::stream(const std::string& dev) const {
    bool known = dev.empty();
    if (!known)
        store_.read([&](const BridgeState& st) {
            known = st.find_device(dev) != nullptr;
            return 0;
        });
    if (!known) return json_error(404, "no device " + dev);
    http::HttpResponse r;
    r.content_type = std::string(http::sse_content_type);
    r.headers.emplace_back("Cache-Control", "no-cache");
    const BridgeStore* store = &store_;
    const auto heartbeat = heartbeat_;
    r.stream = [store, dev, heartbeat](http::StreamSink& sink) {
        http::SseWriter sse(sink);
        auto wanted = [&](const DeviceEntry& d) { return dev.empty() || d.dev == dev || d.mt.name == dev; };
        std::uint64_t cursor = 0;  // next sequence to send
        std::uint64_t generation = 0;
        std::uint64_t activity = 0;                                       // activity sequence sent up to
        std::map<std::string, std::pair<std::string, std::string>> seen;  // dev -> state, version
        bool need_snapshot = true;
        auto last_write = std::chrono::steady_clock::now();
        while (!sink.stopping()) {
            std::vector<std::pair<std::string, std::string>> events;  // name, data
            store->read([&](const BridgeState& st) {
                if (!need_snapshot && cursor < st.buffer.first_sequence()) need_snapshot = true;  // fell behind
                if (need_snapshot) {
                    for (const auto& d : st.devices) {
                        if (!wanted(d)) continue;
                        Json values = Json::array();
                        for (ItemIndex i : d.items) {
                            const ItemEntry& item = st.items[i];
                            if (item.availability || i >= st.buffer.latest().size() || !st.buffer.latest()[i]) continue;
                            values.push_back(JsonApi::value_json(item, *st.buffer.latest()[i], d.state));
                        }
                        Json snapshot = activity_json(d);  // the recent method runs and events
                        snapshot["dev"] = d.dev;
                        snapshot["state"] = d.state;
                        snapshot["values"] = std::move(values);
                        events.emplace_back("snapshot", dump(snapshot));
                        seen[d.dev] = {d.state, d.version};
                    }
                    cursor = st.buffer.next_sequence();
                    generation = st.device_generation;
                    activity = st.activity_sequence;
                    need_snapshot = false;
                    return 0;
                }
                if (st.device_generation != generation) {
                    generation = st.device_generation;
                    for (const auto& d : st.devices) {
                        if (!wanted(d)) continue;
                        auto now = std::make_pair(d.state, d.version);
                        auto it = seen.find(d.dev);
                        if (it != seen.end() && it->second == now) continue;
                        seen[d.dev] = now;
                        events.emplace_back("device", Json{{"dev", d.dev}, {"state", d.state}, {"version", d.version}}.dump());
                    }
                }
                if (st.activity_sequence > activity) {
                    // Method runs and events changed since the last pass, in the order they changed.
                    std::vector<std::pair<std::uint64_t, std::pair<std::string, std::string>>> changed;
                    for (const auto& d : st.devices) {
                        if (!wanted(d)) continue;
                        for (const auto& run : d.method_runs)
                            if (run.seq > activity)
                                changed.push_back({run.seq, {"method", dump(JsonApi::method_run_json(d.dev, run))}});
                        for (const auto& e : d.events)
                            if (e.seq > activity) changed.push_back({e.seq, {"event", dump(JsonApi::event_json(d.dev, e))}});
                    }
                    std::sort(changed.begin(), changed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
                    for (auto& c : changed) events.push_back(std::move(c.second));
                    activity = st.activity_sequence;
                }
                auto range = st.buffer.range(cursor, 4096, nullptr);
                cursor = range.next_sequence;
                for (const auto& o : range.observations) {
                    const ItemEntry& item = st.items[o.item];
                    const DeviceEntry& d = st.devices[item.device];
                    if (item.availability || !wanted(d)) continue;
                    Json v = JsonApi::value_json(item, o, d.state);
                    v["dev"] = d.dev;
                    events.emplace_back("value", v.dump(-1, ' ', false, Json::error_handler_t::replace));
                }
                return 0;
            });
            for (const auto& [name, data] : events) {
                if (!sse.event(name, data)) return;
                last_write = std::chrono::steady_clock::now();
            }
            if (std::chrono::steady_clock::now() - last_write >= heartbeat) {
                if (!sse.comment("ping")) return;
                last_write = std::chrono::steady_clock::now();
            }
            store->wait_for_change(cursor - 1, generation, std::chrono::milliseconds(100), activity);
        }
    };
    return r;
}

void JsonApi::install(http::HttpServer& server) {
    server.get("/nclink/v1/devices", [this](const http::HttpRequest&) { return devices(); });
    server.get("/nclink/v1/devices/{dev}/model", [this](const http::HttpRequest& r) { return model(r.path_param("dev")); });
    server.get("/nclink/v1/devices/{dev}/activity", [this](const http::HttpRequest& r) { return activity(r.path_param("dev")); });
    server.get("/nclink/v1/devices/{dev}/nodeset.xml",
               [this](const http::HttpRequest& r) { return nodeset(r.path_param("dev"), r.param("profile").value_or("basic")); });
    server.get("/nclink/v1/stream", [this](const http::HttpRequest& r) { return stream(r.param("dev").value_or("")); });
    server.post("/nclink/v1/devices/{dev}/set", [this](const http::HttpRequest& r) { return set(r.path_param("dev"), r.body); });
    server.post("/nclink/v1/devices/{dev}/call", [this](const http::HttpRequest& r) { return call(r.path_param("dev"), r.body); });
    server.get("/nclink/v1/devices/{dev}/history", [this](const http::HttpRequest& r) { return history(r.path_param("dev"), r); });
}

}  // namespace nclink::bridge
