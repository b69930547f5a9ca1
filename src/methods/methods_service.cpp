// Method/Call and Method/Control/Request (8.2.22-8.2.26): validation against
// the model, then the MethodTable runs the call. Every request is answered:
// a refused call on Method/Result (result "error", 8.2.22.3), a control
// request on Method/Control/Response.
#include "methods/methods_service.hpp"

#include "methods/method_args.hpp"
#include "methods/method_table.hpp"

#include <nclink/dtu.hpp>

#include <algorithm>
#include <atomic>

namespace nclink::methods_detail {
namespace {

enum class Action { stop, resume, cancel };

std::optional<Action> parse_action(const std::string& text) {
    if (text == "stop") return Action::stop;
    if (text == "resume") return Action::resume;
    if (text == "cancel") return Action::cancel;
    return std::nullopt;
}

/// privateInfo of a refusal: the detail a person needs, beside the table-19 reason.
std::optional<Json> detail_of(const Error& error) {
    if (error.message.empty()) return std::nullopt;
    return Json{{"message", error.message}};
}

class MethodsService final : public feature_detail::Feature {
public:
    MethodsService(feature_detail::FeatureHost& host, const MethodsConfig& config) : host_(host), stop_grace_(config.stop_grace) {
        MethodTable::Outlet outlet;
        outlet.dev = host.dev;
        outlet.transport = &host.transport;
        outlet.respond = host.respond;
        table_ = MethodTable::create(config, std::move(outlet), host.logger, host.clock, host.work);
    }
    ~MethodsService() override { stop(); }

    std::string_view name() const override { return "methods"; }

    bool handles(TopicKind kind) const override {
        return kind == TopicKind::method_call || kind == TopicKind::method_control_request;
    }

    Result<void> start() override {
        table_->start_ticker();
        return ok_result();
    }

    void stop() override { table_->shutdown(stop_grace_); }

    // Thread: a request worker.
    void handle(const ParsedTopic& topic, const std::string& payload) override {
        if (topic.kind == TopicKind::method_call) on_call(topic, payload);
        else on_control(topic, payload);
    }

    // A paused run whose application is gone would hold its slot for ever:
    // nobody is left to resume it. Running ones finish (a half-done program
    // transfer or cycle is worse than a result nobody reads).
    void on_application_gone(const std::string& ex_cid) override {
        for (const auto& run : table_->running()) {
            if (run->call_topic.ex != ex_cid || !run->snapshot().pause_requested) continue;
            host_.logger.info("method {}: cancelled, its paused caller {} is gone", run->method_id, ex_cid);
            run->request_cancel();
        }
    }

    Json stats() const override {
        Json s = table_->stats();
        s["rejected_calls"] = rejected_calls_.load();
        s["control_requests"] = control_requests_.load();
        return s;
    }

private:
    void on_call(const ParsedTopic& topic, const std::string& payload) {
        auto call = decode<MethodCall>(payload);
        if (!call) {
            host_.logger.info("malformed Method/Call answered NG: {}", call.error().describe());
            ++rejected_calls_;
            if (auto reply = make_error_reply(topic.kind, peek_message_id(payload), host_.dev, call.error()))
                table_->answer(topic, *reply);
            return;
        }
        auto refuse = [&](const Error& error) {
            ++rejected_calls_;
            host_.logger.info("Method/Call {} refused: {}", call->id, error.describe());
            MethodResult result = make_reply<MethodResult>(*call, host_.dev);
            result.id = call->id;
            result.result = "error";
            result.status = ResponseStatus(error);
            result.private_info = detail_of(error);
            table_->answer(topic, to_json(result));
        };
        const Method* method = find_method(call->id);
        if (!method) return refuse(make_error(ErrorCode::node_not_exists, "the model has no method " + call->id));
        auto args = check_method_args(*method, call->args);
        if (!args) return refuse(args.error());
        // The handle from the driver's current binding (driver.hpp, "Handles").
        const PointRef ref = host_.driver.current_ref(call->id);
        if (ref.handle == not_served)
            return refuse(make_error(ErrorCode::unavailable, "the driver does not serve method " + call->id));
        if (const MachineLinkStatus link = host_.driver.link(); link.state == MachineLink::disconnected)
            return refuse(make_error(ErrorCode::unavailable, link.reason.empty() ? std::string("machine disconnected")
                                                                                 : "machine disconnected: " + link.reason));
        auto started = table_->start(ref, topic, call->msg_id, std::move(args).value(), host_.driver.shared_driver());
        if (!started) return refuse(started.error());
    }

    void on_control(const ParsedTopic& topic, const std::string& payload) {
        ++control_requests_;
        auto request = decode<MethodControlRequest>(payload);
        if (!request) {
            host_.logger.info("malformed Method/Control request answered NG: {}", request.error().describe());
            if (auto reply = make_error_reply(topic.kind, peek_message_id(payload), host_.dev, request.error()))
                table_->answer(topic, *reply);
            return;
        }
        MethodControlResponse response = make_reply<MethodControlResponse>(*request, host_.dev);
        response.id = request->id;
        auto answer = [&](const Error* error) {
            if (error) {
                response.status = ResponseStatus(*error);
                response.private_info = detail_of(*error);
            }
            table_->answer(topic, to_json(response));
        };
        if (!find_method(request->id)) {
            const Error e = make_error(ErrorCode::node_not_exists, "the model has no method " + request->id);
            return answer(&e);
        }
        const auto action = parse_action(request->action);
        if (!action) {
            const Error e =
                make_error(ErrorCode::method_action_type, "action \"" + request->action + "\" is not stop, resume or cancel");
            return answer(&e);
        }
        const auto targets = targets_of(topic, *request);
        if (targets.empty()) {
            const Error e = make_error(ErrorCode::unavailable, "method " + request->id + " is not running");
            return answer(&e);
        }
        for (const auto& run : targets) {
            switch (*action) {
                case Action::stop: run->request_stop(); break;
                case Action::resume: run->request_resume(); break;
                case Action::cancel: run->request_cancel(); break;
            }
        }
        host_.logger.info("method {}: {} ({} run(s))", request->id, request->action, targets.size());
        answer(nullptr);
    }

    /// The runs a control request acts on: those of its method, narrowed to
    /// one call when privateInfo names it ({"call": <@id of the Method/Call>}),
    /// then to the caller's own runs when it has any (else, as an operator,
    /// it controls the others').
    std::vector<std::shared_ptr<MethodRun>> targets_of(const ParsedTopic& topic, const MethodControlRequest& request) const {
        auto runs = table_->running(request.id);
        if (request.private_info && request.private_info->is_object() && request.private_info->contains("call")) {
            const Json& call = (*request.private_info)["call"];
            runs.erase(
                std::remove_if(runs.begin(), runs.end(), [&](const auto& run) { return !run->call_id || *run->call_id != call; }),
                runs.end());
        }
        std::vector<std::shared_ptr<MethodRun>> own;
        for (const auto& run : runs)
            if (run->call_topic.ex == topic.ex) own.push_back(run);
        return own.empty() ? runs : own;
    }

    /// A METHOD object of the current model that belongs to this adapter
    /// (the root configs, where 6.2.7 puts them, or this device).
    const Method* find_method(const std::string& id) const {
        const auto state = host_.model.current();
        if (!state || !state->model) return nullptr;
        const Method* method = state->model->method(id);
        if (!method) return nullptr;
        const ObjectInfo* info = state->model->find(id);
        if (info && !info->device_id.empty() && state->device && info->device_id != state->device->id) return nullptr;
        return method;
    }

    feature_detail::FeatureHost& host_;
    const std::chrono::milliseconds stop_grace_;
    std::shared_ptr<MethodTable> table_;
    std::atomic<std::uint64_t> rejected_calls_{0}, control_requests_{0};
};

}  // namespace

std::unique_ptr<feature_detail::Feature> make_methods_service(feature_detail::FeatureHost& host, const MethodsConfig& config) {
    return std::make_unique<MethodsService>(host, config);
}

}  // namespace nclink::methods_detail
