// The methods item of run_conformance() (table 62): Method/Call, the
// Method/Status sequence and Method/Result (8.2.22-8.2.26).
#include "conform/checks_fidelity.hpp"
#include "conform/runner_impl.hpp"

#include <nclink/dtu_common.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <thread>

namespace nclink::conform::detail {

void Runner::methods() {
    auto& call = item("method-call");
    auto& status = item("method-status");
    auto& control = item("method-control");
    auto& result = item("method-result");
    const auto all = {&call, &status, &control, &result};
    if (!opts.allow_write) {
        for (auto* i : all) i->skip(needs_write);
        return;
    }
    if (!model) {
        for (auto* i : all) i->skip("no usable model");
        return;
    }
    if (model->methods().empty()) {
        for (auto* i : all) i->not_supported("the model defines no METHOD object (9.3.3: table 63 item 5 need not be tested)");
        return;
    }
    if (opts.method.empty()) {
        for (auto* i : all)
            i->skip("no method named: pass --method ID (the tester never guesses which method is harmless on this machine)");
        return;
    }
    const Method* method = model->method(opts.method);
    if (!method) {
        for (auto* i : all) i->skip(fmt::format("the model has no method \"{}\"", opts.method));
        return;
    }
    Json args = opts.method_args ? *opts.method_args : method->args;
    Json payload{{"guid", dev}, {"id", method->id}};
    if (!args.is_null()) payload["args"] = args;
    // The call is answered by Method/Status (accepted) and Method/Result.
    ParsedTopic t;
    t.kind = TopicKind::method_call;
    t.dev = dev;
    t.ex = ex;
    const std::string call_topic = build_topic(t);
    const std::vector<std::string> result_topics = {topics::method_result(dev, ex)};
    const auto from = wire.mark();
    auto x = request(call_topic, payload, result_topics, {topics::method_result(dev)});
    const auto statuses = wire.collect(from, [&](const Captured& c) {
        if (!is_topic(c, TopicKind::method_status)) return false;
        auto dtu = parse_object(c.message.payload);
        return dtu && dtu->value("id", std::string()) == method->id;
    });
    if (!x.reply && statuses.empty() && x.strays.empty()) {
        for (auto* i : all)
            i->not_supported(fmt::format("no Method/Status or Method/Result within {} ms of Method/Call \"{}\"",
                                         opts.timeout.count(), method->id));
        return;
    }
    if (settle_unusable(result, x, true)) {
        if (result.outcome == Outcome::not_supported) {
            for (auto* i : {&call, &status, &control})
                i->not_supported(fmt::format("methods are not supported: {}", result.summary));
            return;
        }
        call.fail("the call got no usable Method/Result");
    } else {
        if (auto problems = check_method_result(*x.dtu, x.sent_id, dev, method->id); !problems.empty())
            fail_with(result, join(problems), x);
        if (result.outcome == Outcome::pass)
            result.summary = fmt::format("Method/Result \"{}\" code {}", x.dtu->value("result", std::string()),
                                         x.dtu->value("code", std::string()));
        if (!is_ok(*x.dtu)) result.notes.push_back("the method ended NG: " + clip(x.dtu->dump(), 300));
        if (call.outcome == Outcome::pass) call.summary = fmt::format("\"{}\" called; the adapter answered", method->id);
    }
    if (statuses.empty()) {
        if (x.dtu && is_ok(*x.dtu))
            status.fail(
                fmt::format("the call was accepted (Method/Result OK) but no Method/Status came (8.2.22.3: an accepted call "
                            "is answered on Method/Status)"));
        else status.skip("the call was refused, so no progress is expected");
    } else {
        for (const auto& c : statuses) {
            auto dtu = parse_object(c.message.payload);
            if (auto problems = check_method_status(*dtu, dev, method->id); !problems.empty()) {
                fail_with(status, join(problems), c);
                break;
            }
        }
        if (status.outcome == Outcome::pass)
            status.summary = fmt::format("{} Method/Status DTU(s) with the shape of table 44", statuses.size());
    }
    // Control: "resume" changes nothing for a method that is not paused, and
    // may be refused (not running) with any table-19 code; an unknown action
    // must be refused with 418. Both answered 202 = control not supported.
    auto c = request_kind(TopicKind::method_control_request, Json{{"guid", dev}, {"id", method->id}, {"action", "resume"}});
    if (!c.dtu || !c.mirrored) {
        settle_unusable(control, c, true);
        return;
    }
    if (auto problems = check_method_control_response(*c.dtu, c.sent_id, dev, method->id); !problems.empty())
        fail_with(control, join(problems), c);
    auto bad = request_kind(TopicKind::method_control_request,
                            Json{{"guid", dev}, {"id", method->id}, {"action", "nclink-conform-no-such-action"}});
    if (!bad.dtu || !bad.mirrored) {
        settle_unusable(control, bad, true);
        return;
    }
    const bool refused_418 = !is_ok(*bad.dtu) && bad.dtu->value("error", Json()) == Json(418);
    if (!refused_418 && says_not_supported(*c.dtu) && says_not_supported(*bad.dtu)) {
        control.not_supported(fmt::format("both control requests answered NG 202 \"{}\"", bad.dtu->value("reason", std::string())),
                              bad.reply->message.topic, bad.reply->message.payload);
        return;
    }
    if (!refused_418)
        fail_with(control, "an unknown action must be refused with NG 418 \"method action type error\" (table 19)", bad);
    if (control.outcome == Outcome::pass)
        control.summary = fmt::format("\"resume\" answered {} {}; an unknown action answers 418",
                                      c.dtu->value("code", std::string()), c.dtu->value("reason", std::string()));
}

}  // namespace nclink::conform::detail
