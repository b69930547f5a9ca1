// run_conformance(): plumbing, the connection test (table 55), state
// notification (table 61), model probe and model-file check (table 56 item 1,
// 9.3.2) and data query (table 57 item 1). The feature items are in
// runner_features.cpp.
#include "conform/runner_impl.hpp"

#include <nclink/dtu_common.hpp>
#include <nclink/version.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <ctime>
#include <set>
#include <thread>

namespace nclink::conform {

std::vector<std::string> tester_subscriptions(const std::string& dev, const std::string& ex) {
    std::vector<std::string> f = {
        topics::register_response(ex),
        topics::discovery_response(ex),
        topics::notify_state(dev),
        topics::probe_version(dev),
        topics::sample(dev, "#"),  // model channels and dynamic channels (Sample/{dev}/{ex}/{ch})
        topics::event(dev),
        topics::event(dev, "#"),
        topics::method_status(dev),
        topics::method_status(dev, "#"),
        topics::method_result(dev),
        topics::method_result(dev, "#"),
    };
    using Builder = std::string (*)(std::string_view, topics::OptEx);
    for (Builder b : {Builder(&topics::probe_query_response), Builder(&topics::probe_set_response),
                      Builder(&topics::query_response), Builder(&topics::set_response), Builder(&topics::method_control_response)}) {
        f.push_back(b(dev, std::nullopt));
        f.push_back(b(dev, "+"));
    }
    using SpelledBuilder = std::string (*)(std::string_view, topics::OptEx, Spelling);
    for (SpelledBuilder b :
         {SpelledBuilder(&topics::sample_register_response), SpelledBuilder(&topics::sample_unregister_response),
          SpelledBuilder(&topics::event_register_response), SpelledBuilder(&topics::event_unregister_response)}) {
        for (Spelling s : {Spelling::standard, Spelling::typo}) {
            f.push_back(b(dev, std::nullopt, s));
            f.push_back(b(dev, "+", s));
        }
    }
    return f;
}

namespace detail {

std::string join(const Problems& problems) {
    std::string out;
    for (const auto& p : problems) out += (out.empty() ? "" : "; ") + p;
    return out;
}

namespace {

std::string now_iso() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

// The rows of table C.1, in its order.
std::vector<ItemResult> c1_rows() {
    auto row = [](const char* key, const char* title, const char* c1, const char* clause, bool mandatory, bool required) {
        ItemResult r;
        r.key = key;
        r.title = title;
        r.c1_row = c1;
        r.clause = clause;
        r.c1_mandatory = mandatory;
        r.required = required;
        return r;
    };
    return {
        row("register", "Terminal registration (Register/Request)", "连接测试: 终端注册", "table 55 item 1; 8.2.1/8.2.2", true,
            false),
        row("discovery", "Terminal discovery (Discovery/Request)", "连接测试: 终端探测", "table 55 item 2; 8.2.3/8.2.4", true,
            false),
        row("probe", "Model probe (Probe/Query)", "模型侦测", "table 56 item 1a; 8.2.7/8.2.8", true, true),
        row("model-file", "Model file check", "模型文件数据项定义检查", "table 56 item 1b; 9.2.3, 9.3.2, chapters 6-7", true, true),
        row("model-set", "Model set with version check (Probe/Set, Probe/Version)", "模型设置",
            "table 56 item 2; 8.2.5, 8.2.9/8.2.10", true, false),
        row("query", "Data query (Query)", "数据查询", "table 57 item 1; 8.2.11/8.2.12", true, true),
        row("state", "State notification (Notify/State)", "状态通知", "table 61; 8.2.16", true, false),
        row("set", "Data set (Set)", "数据设置", "table 57 item 2; 8.2.13/8.2.14", false, false),
        row("sampling", "Sample channel sampling (Sample)", "采样通道采样", "table 58; 8.2.15", false, false),
        row("method-call", "Method call (Method/Call)", "内构方法: 调用", "table 62; 8.2.22", false, false),
        row("method-status", "Method progress (Method/Status)", "内构方法: 状态", "table 62; 8.2.23", false, false),
        row("method-control", "Method control (Method/Control)", "内构方法: 控制", "table 62; 8.2.25/8.2.26", false, false),
        row("method-result", "Method result (Method/Result)", "内构方法: 结果", "table 62; 8.2.24", false, false),
        row("event-register", "Event registration (Register/Event)", "事件: 注册", "table 59 item 1; 8.2.27/8.2.28", false, false),
        row("event-data", "Event data (Event)", "事件: 查询", "table 59 item 2; 8.2.31", false, false),
        row("event-unregister", "Event unregistration (Unregister/Event)", "事件: 注销", "table 59 item 1; 8.2.29/8.2.30", false,
            false),
        row("dynamic-register", "Dynamic sampling registration (Register/Sample)", "动态采样: 注册",
            "table 60 item 1; 8.2.17/8.2.18", false, false),
        row("dynamic-sample", "Dynamic sampling data (Sample/{dev}/{ex}/{ch})", "动态采样: 采样", "table 60 item 2; 8.2.21",
            false, false),
        row("dynamic-unregister", "Dynamic sampling unregistration (Unregister/Sample)", "动态采样: 注销",
            "table 60 item 1; 8.2.19/8.2.20", false, false),
    };
}

}  // namespace

Evidence evidence_of(const Captured& c, std::string note) {
    return Evidence{std::move(note), c.message.topic, clip(c.message.payload)};
}

Runner::Runner(Wire& w, const RunOptions& options) : wire(w), opts(options), dev(options.device), ex(w.ex_cid()) {
    record.device = dev;
    record.broker = opts.broker;
    record.client_id = ex;
    record.date = now_iso();
    record.tool_version = library_version();
    record.allow_write = opts.allow_write;
    record.items = c1_rows();
}

ItemResult& Runner::item(std::string_view key) {
    for (auto& i : record.items)
        if (i.key == key) return i;
    record.items.push_back(ItemResult{});
    record.items.back().key = std::string(key);
    return record.items.back();
}

std::chrono::milliseconds Runner::ms_since(std::chrono::steady_clock::time_point t) const {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t);
}

Exchange Runner::request(const std::string& topic, Json payload, const std::vector<std::string>& reply_topics,
                         const std::vector<std::string>& unmirrored_topics) {
    Exchange x;
    x.topic = topic;
    x.sent_id = Json(wire.next_msg_id());
    payload["@id"] = x.sent_id;
    sent_ids.insert(x.sent_id.get<std::string>());
    x.request = payload;
    const std::set<std::string> mirrored(reply_topics.begin(), reply_topics.end());
    const std::set<std::string> other(unmirrored_topics.begin(), unmirrored_topics.end());
    std::uint64_t from = wire.mark();
    if (auto sent = wire.publish(topic, payload); !sent) {
        x.unparsable = "could not publish the request: " + sent.error().describe();
        return x;
    }
    auto deadline = std::chrono::steady_clock::now() + opts.timeout;
    while (true) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) break;
        auto c = wire.wait_for(
            from, [&](const Captured& m) { return mirrored.count(m.message.topic) || other.count(m.message.topic); }, left);
        if (!c) break;
        from = c->seq + 1;
        const MessageId id = peek_message_id(c->message.payload);
        if (id && *id == x.sent_id) {
            x.mirrored = mirrored.count(c->message.topic) > 0;
            std::string why;
            x.dtu = parse_object(c->message.payload, &why);
            if (!x.dtu) x.unparsable = why;
            x.reply = std::move(c);
            break;
        }
        if (id && id->is_string() && sent_ids.count(id->get<std::string>())) continue;  // a late answer to an earlier request
        if (mirrored.count(c->message.topic)) {
            // On our own response topic with another "@id": a wrong echo (or a
            // late answer). Give the right answer a short grace, then stop.
            x.strays.push_back(std::move(*c));
            deadline = std::min(deadline, std::chrono::steady_clock::now() + std::chrono::milliseconds(300));
        }
    }
    return x;
}

Exchange Runner::request_kind(TopicKind kind, Json payload) {
    ParsedTopic t;
    t.kind = kind;
    t.dev = dev;
    t.ex = ex;
    const std::string topic = build_topic(t);
    ParsedTopic bare = t;
    bare.ex.reset();
    return request(topic, std::move(payload), response_topics(t, true), response_topics(bare, true));
}

void Runner::fail_with(ItemResult& i, const std::string& note, const Exchange& x) {
    if (x.reply) i.fail(note, x.reply->message.topic, x.reply->message.payload);
    else i.fail(note, x.topic, x.request.dump());
}

void Runner::fail_with(ItemResult& i, const std::string& note, const Captured& c) {
    i.fail(note, c.message.topic, c.message.payload);
}

bool Runner::settle_unusable(ItemResult& i, const Exchange& x, bool optional_feature) {
    if (!x.reply) {
        if (!x.unparsable.empty()) {
            i.fail(x.unparsable, x.topic, x.request.dump());
            return true;
        }
        if (!x.strays.empty()) {
            for (std::size_t k = 0; k < x.strays.size() && k < 3; ++k)
                fail_with(
                    i,
                    fmt::format("an answer on our response topic carries \"@id\" {} instead of the request's {} (8.1.3)",
                                peek_message_id(x.strays[k].message.payload).value_or(Json("(none)")).dump(), x.sent_id.dump()),
                    x.strays[k]);
            return true;
        }
        const std::string note = fmt::format("no answer to the request on {} within {} ms", x.topic, opts.timeout.count());
        if (optional_feature)
            i.not_supported(note + " (an optional feature: silence is taken as not supported)", x.topic, x.request.dump());
        else i.fail(note, x.topic, x.request.dump());
        return true;
    }
    if (!x.dtu) {
        fail_with(i, "the answer is " + x.unparsable, x);
        return true;
    }
    if (!x.mirrored)
        fail_with(i,
                  fmt::format("answered on {}; docs/wire.md: a request on {} is answered on the mirrored topic",
                              x.reply->message.topic, x.topic),
                  x);
    if (says_not_supported(*x.dtu)) {
        i.not_supported(fmt::format("the adapter answers NG {} \"{}\"", x.dtu->value("error", Json()).dump(),
                                    x.dtu->value("reason", std::string())),
                        x.reply->message.topic, x.reply->message.payload);
        return true;
    }
    return false;
}

// ---- connection (table 55) ----------------------------------------------------------

void Runner::connection() {
    auto& reg = item("register");
    auto x = request(topics::register_request(), Json{{"cli_uuid", ex}}, {topics::register_response(ex)});
    if (!settle_unusable(reg, x, true)) {
        auto problems = check_register_response(*x.dtu, x.sent_id, ex);
        if (!problems.empty()) fail_with(reg, join(problems), x);
        else reg.summary = "the agent accepted Register/Request (code OK)";
    }
    if (reg.outcome == Outcome::not_supported)
        reg.summary = fmt::format(
            "no agent answered Register/Request within {} ms (a bare broker has no agent; "
            "run beside an NC-Link agent to test the connection)",
            opts.timeout.count());

    auto& disc = item("discovery");
    auto d = request(topics::discovery_request(ex), Json{{"guid", ex}}, {topics::discovery_response(ex)});
    if (!settle_unusable(disc, d, true)) {
        auto problems = check_discovery_response(*d.dtu, d.sent_id, ex, dev);
        if (!problems.empty()) fail_with(disc, join(problems), d);
        else disc.summary = fmt::format("the agent lists \"{}\"", dev);
    }
    if (disc.outcome == Outcome::not_supported && disc.summary.rfind("no answer", 0) == 0)
        disc.summary = fmt::format("no agent answered Discovery/Request within {} ms", opts.timeout.count());
    connection_failed = reg.outcome == Outcome::fail || disc.outcome == Outcome::fail;
}

// ---- state notification (table 61) ----------------------------------------------------

void Runner::state_notification() {
    auto& st = item("state");
    const std::string topic = topics::notify_state(dev);
    auto c = wire.wait_for(
        start_mark, [&](const Captured& m) { return m.message.topic == topic; }, opts.timeout);
    if (!c) {
        st.not_supported(fmt::format("no message on {} within {} ms (the adapter or an agent publishes the state, retained)",
                                     topic, opts.timeout.count()));
        return;
    }
    auto problems = check_notify_state(c->message, dev);
    if (!problems.empty()) {
        fail_with(st, join(problems), *c);
        return;
    }
    st.summary = fmt::format("retained {} says online", topic);
    st.notes.push_back(
        "the offline notification of table 61 is not exercised: the tester never takes the adapter "
        "offline; stop the adapter while watching Notify/State (`nclink state`) to see it");
}

// ---- model (table 56 item 1, 9.3.2) -------------------------------------------------------

void Runner::probe() {
    auto& pr = item("probe");
    auto x = request_kind(TopicKind::probe_query_request, Json{{"guid", dev}});
    if (settle_unusable(pr, x, false)) return;
    auto checked = check_probe_response(*x.dtu, x.sent_id, dev);
    if (!checked.problems.empty()) fail_with(pr, join(checked.problems), x);
    if (checked.model) {
        raw_model = std::move(*checked.model);
        if (pr.outcome == Outcome::pass) pr.summary = fmt::format("model received ({} bytes)", x.reply->message.payload.size());
    }
}

void Runner::model_file() {
    auto& mf = item("model-file");
    if (raw_model.is_null()) {
        mf.skip("no model: Probe/Query gave none");
        return;
    }
    const LoadResult loaded = parse_model(raw_model.dump(-1, ' ', false, Json::error_handler_t::replace));
    for (const auto& p : loaded.problems) {
        const std::string where = p.pointer.empty() ? "/" : p.pointer;
        if (p.severity == Severity::warning) mf.notes.push_back(fmt::format("warning at {}: {}", where, p.message));
        else mf.fail(fmt::format("{} problem at {}: {}", to_string(p.severity), where, p.message));
    }
    model = loaded.model;
    if (model) {
        device = device_for(*model, dev);
        if (!device) mf.fail(fmt::format("no device of the model has the terminal id \"{}\" (guid, else id; 8.1.4)", dev));
        else if (resolve_dev_uuid(*device) != dev)
            mf.notes.push_back(fmt::format(
                "device \"{}\" has no guid \"{}\" (8.1.4: the adapter's terminal id is the model's GUID)", device->id, dev));
        record.objects = count_objects(*model);
        record.model_version = device ? device->version : model->root().version;
    }
    if (mf.outcome == Outcome::pass)
        mf.summary = fmt::format("the model follows chapters 6 and 7 ({} warnings)", mf.notes.size());
    else
        mf.summary =
            fmt::format("{} fatal, {} conformance problems", loaded.count(Severity::fatal), loaded.count(Severity::conformance));
}

// ---- data query (table 57 item 1) ------------------------------------------------------------

void Runner::query() {
    auto& q = item("query");
    if (!device) {
        q.skip("no usable model: the items to query are unknown");
        return;
    }
    const auto items = served_items(*model, *device);
    if (items.empty()) {
        q.skip("the model defines no data objects");
        return;
    }
    constexpr std::size_t batch = 32;
    std::size_t answered = 0;
    std::vector<const DataObject*> containers;
    for (std::size_t start = 0; start < items.size(); start += batch) {
        std::vector<std::string> ids;
        Json list = Json::array();
        for (std::size_t k = start; k < std::min(items.size(), start + batch); ++k) {
            ids.push_back(items[k]->id);
            list.push_back(Json{{"id", items[k]->id}});
        }
        auto x = request_kind(TopicKind::query_request, Json{{"guid", dev}, {"ids", list}});
        if (settle_unusable(q, x, false)) return;
        if (auto problems = check_query_response(*x.dtu, x.sent_id, dev, ids); !problems.empty()) fail_with(q, join(problems), x);
        for (std::size_t k = 0; k < ids.size(); ++k) {
            const Json* entry = result_entry(*x.dtu, k);
            if (!entry || entry->value("id", std::string()) != ids[k]) continue;  // reported above
            const DataObject& obj = *items[start + k];
            if (!is_ok(*entry)) {
                q.fail(fmt::format("{}: a data object of the model answers NG", obj.id), x.reply->message.topic, entry->dump());
                continue;
            }
            auto values = entry->find("values");
            if (values == entry->end() || !values->is_array()) continue;  // reported above
            ++answered;
            if (auto problems = check_whole_value(obj, *values); !problems.empty())
                q.fail(fmt::format("{} ({}): {}", obj.id, to_string(obj.kind), join(problems)), x.reply->message.topic,
                       entry->dump());
            else {
                whole_values[obj.id] = (*values)[0];
                whole_values_topic = x.reply->message.topic;
            }
            if (obj.kind != DataKind::single) containers.push_back(&obj);
        }
    }
    // Element access of list and dict items (8.1.5): get_length / get_keys.
    if (!containers.empty()) {
        std::vector<std::string> ids;
        Json list = Json::array();
        for (const auto* obj : containers) {
            ids.push_back(obj->id);
            list.push_back(
                Json{{"id", obj->id}, {"params", Json{{"operation", obj->kind == DataKind::list ? "get_length" : "get_keys"}}}});
        }
        auto x = request_kind(TopicKind::query_request, Json{{"guid", dev}, {"ids", list}});
        if (!settle_unusable(q, x, false)) {
            if (auto problems = check_query_response(*x.dtu, x.sent_id, dev, ids); !problems.empty())
                fail_with(q, join(problems), x);
            for (std::size_t k = 0; k < ids.size(); ++k) {
                const Json* entry = result_entry(*x.dtu, k);
                if (!entry || !is_ok(*entry) || !entry->contains("values")) {
                    if (entry)
                        q.fail(fmt::format("{}: {} answered NG", ids[k],
                                           containers[k]->kind == DataKind::list ? "get_length" : "get_keys"),
                               x.reply->message.topic, entry->dump());
                    continue;
                }
                const Json whole = whole_values.count(ids[k]) ? whole_values[ids[k]] : Json();
                auto problems = containers[k]->kind == DataKind::list ? check_list_length((*entry)["values"], whole)
                                                                      : check_dict_keys((*entry)["values"], whole);
                if (!problems.empty())
                    q.fail(fmt::format("{}: {}", ids[k], join(problems)), x.reply->message.topic, entry->dump());
            }
        }
    }
    // An id the model does not define: NG 401 (table 19).
    const std::string unknown = "nclink-conform-no-such-item";
    auto x = request_kind(TopicKind::query_request, Json{{"guid", dev}, {"ids", Json::array({Json{{"id", unknown}}})}});
    if (!settle_unusable(q, x, false)) {
        const Json* entry = result_entry(*x.dtu, 0);
        const bool right =
            entry && !is_ok(*entry) &&
            (entry->value("error", Json()) == Json(401) || entry->value("reason", std::string()) == "Node not exists");
        if (!right)
            fail_with(
                q, fmt::format("a Query of the unknown id \"{}\" must answer NG 401 \"Node not exists\" (table 19)", unknown), x);
    }
    query_fidelity(q);
    if (q.outcome == Outcome::pass)
        q.summary = fmt::format(
            "{} data objects answered with the shape of their data type; {} list/dict element checks; "
            "an unknown id answers 401",
            answered, containers.size());
}

std::optional<Json> Runner::query_value(const std::string& id, const Json& params, std::string* why) {
    Json entry = Json{{"id", id}};
    if (!params.is_null()) entry["params"] = params;
    auto x = request_kind(TopicKind::query_request, Json{{"guid", dev}, {"ids", Json::array({entry})}});
    if (!x.dtu) {
        *why = x.reply ? "the answer is " + x.unparsable : fmt::format("no answer within {} ms", opts.timeout.count());
        return std::nullopt;
    }
    const Json* e = result_entry(*x.dtu, 0);
    if (!e || !is_ok(*e) || !e->contains("values") || !(*e)["values"].is_array() || (*e)["values"].empty()) {
        *why = "unusable answer " + clip(x.dtu->dump(), 300);
        return std::nullopt;
    }
    return (*e)["values"][0];
}

// ---- the run -----------------------------------------------------------------------------------

TestRecord Runner::run() {
    start_mark = 0;
    // The basics (connection, state, probe, model, query) always run: the
    // feature items stand on their model and values.
    auto step = [&](const char* name, void (Runner::*fn)(), const char* feature = nullptr) {
        if (feature != nullptr && !opts.only.empty() && !opts.only.count(feature)) {
            for (auto& i : record.items)
                if (i.key.rfind(feature, 0) == 0 && i.outcome == Outcome::pass && i.summary.empty())
                    i.skip("not selected (RunOptions::only)");
            return;
        }
        opts.logger.info("conform: {}", name);
        (this->*fn)();
    };
    step("connection test (table 55)", &Runner::connection);
    if (connection_failed) {
        for (auto& i : record.items)
            if (i.key != "register" && i.key != "discovery")
                i.skip("the connection test failed; 9.2.1: no further tests are run");
        return record;
    }
    step("state notification (table 61)", &Runner::state_notification);
    step("model probe (table 56)", &Runner::probe);
    step("model file check (9.3.2)", &Runner::model_file);
    step("data query (table 57)", &Runner::query);
    step("sampling (table 58)", &Runner::sampling, "sampling");
    step("events (table 59)", &Runner::events, "event");
    step("dynamic sampling (table 60)", &Runner::dynamic_sampling, "dynamic");
    step("data set (table 57)", &Runner::set, "set");
    step("model set (table 56)", &Runner::model_set, "model-set");
    step("methods (table 62)", &Runner::methods, "method");
    for (auto& i : record.items)
        if (i.summary.empty()) i.summary = i.outcome == Outcome::fail ? fmt::format("{} problem(s)", i.evidence.size()) : "";
    return record;
}

}  // namespace detail

TestRecord run_conformance(Wire& wire, const RunOptions& options) {
    detail::Runner runner(wire, options);
    return runner.run();
}

}  // namespace nclink::conform
