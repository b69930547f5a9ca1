#include "client/responders.hpp"

#include <fmt/format.h>

#include <cctype>
#include <functional>
#include <utility>

namespace nclink::client_detail {
namespace {

// The standard prints the reason as "DEV _ UNREACH- ABLE" once (table 54);
// compare letters and underscores only.
bool is_dev_unreachable_reason(std::string_view reason) {
    std::string letters;
    for (char c : reason)
        if (std::isalnum(static_cast<unsigned char>(c)) || c == '_')
            letters.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
    return letters == dev_unreachable_reason;
}

template <class Dtu, class T>
class TypedResponder final : public Responder {
public:
    using Convert = std::function<Result<T>(Dtu&)>;
    using OnFail = std::function<Result<T>(Error)>;

    TypedResponder(Completion<T> done, Convert convert, OnFail on_fail = {})
        : done_(std::move(done)), convert_(std::move(convert)), on_fail_(std::move(on_fail)) {}

    bool decode(std::string_view payload) override {
        auto decoded = nclink::decode<Dtu>(payload);
        if (!decoded) return false;
        dtu_ = std::move(decoded).value();
        return true;
    }
    void complete() override {
        if (done_ && dtu_) done_(convert_(*dtu_));
    }
    void fail(Error error) override {
        if (!done_) return;
        if (on_fail_) done_(on_fail_(std::move(error)));
        else done_(Result<T>(std::move(error)));
    }

private:
    Completion<T> done_;
    Convert convert_;
    OnFail on_fail_;
    std::optional<Dtu> dtu_;
};

template <class Dtu, class T>
std::shared_ptr<Responder> make(Completion<T> done, typename TypedResponder<Dtu, T>::Convert convert,
                                typename TypedResponder<Dtu, T>::OnFail on_fail = {}) {
    return std::make_shared<TypedResponder<Dtu, T>>(std::move(done), std::move(convert), std::move(on_fail));
}

}  // namespace

Error error_from_status(const ResponseStatus& status) {
    const std::string reason_text = status.reason.value_or("");
    const std::string number = status.error ? std::to_string(*status.error) : std::string("-");
    std::string message = fmt::format("NG {} {}", number, reason_text);
    if (is_dev_unreachable_reason(reason_text)) return make_error(ErrorCode::unavailable, std::move(message));
    if (auto code = status.error_code()) return make_error(*code, std::move(message));
    if (auto code = error_code_from_reason(reason_text)) return make_error(*code, std::move(message));
    // A user-defined (negative) or unknown code: keep it in the message.
    return make_error(ErrorCode::syntax_error, std::move(message));
}

std::optional<Error> unreachable_error(std::string_view payload) {
    // Cheap filter first: this runs for every response.
    if (payload.find("UNREACH") == std::string_view::npos) return std::nullopt;
    const Json dtu = Json::parse(payload.begin(), payload.end(), nullptr, false);
    if (!dtu.is_object()) return std::nullopt;
    const auto code = dtu.find("code");
    const auto reason_it = dtu.find("reason");
    if (code == dtu.end() || !code->is_string() || *code != "NG") return std::nullopt;
    if (reason_it == dtu.end() || !reason_it->is_string()) return std::nullopt;
    const std::string reason_text = reason_it->get<std::string>();
    if (!is_dev_unreachable_reason(reason_text)) return std::nullopt;
    std::string message = "DEV_UNREACHABLE";
    if (const auto dev = dtu.find("dev_uuid"); dev != dtu.end() && dev->is_string())
        message += ": device " + dev->get<std::string>() + " is not reachable from the agent";
    return make_error(ErrorCode::unavailable, std::move(message));
}

std::shared_ptr<Responder> register_responder(Completion<RegisterOutcome> done) {
    return make<RegisterResponse, RegisterOutcome>(
        std::move(done),
        [](RegisterResponse& r) -> Result<RegisterOutcome> {
            RegisterOutcome out;
            out.kind = r.status.ok ? RegisterOutcome::Kind::accepted : RegisterOutcome::Kind::refused;
            out.status = r.status;
            return out;
        },
        [](Error error) -> Result<RegisterOutcome> {
            // Nobody answering is normal without an agent.
            if (error.code == ErrorCode::timeout) return RegisterOutcome{};
            return error;
        });
}

std::shared_ptr<Responder> probe_responder(Completion<Json> done) {
    return make<ProbeQueryResponse, Json>(std::move(done), [](ProbeQueryResponse& r) -> Result<Json> {
        if (!r.status.ok) return error_from_status(r.status);
        if (!r.probe || !r.probe->is_object())
            return make_error(ErrorCode::parameter_missing, "Probe/Query response without a probe object");
        return std::move(*r.probe);
    });
}

std::shared_ptr<Responder> probe_set_responder(Completion<void> done) {
    return make<ProbeSetResponse, void>(std::move(done), [](ProbeSetResponse& r) -> Result<void> {
        if (!r.status.ok) return error_from_status(r.status);
        return ok_result();
    });
}

std::shared_ptr<Responder> query_responder(Completion<std::vector<QueryResult>> done) {
    return make<QueryResponse, std::vector<QueryResult>>(std::move(done), [](QueryResponse& r) -> Result<std::vector<QueryResult>> {
        if (r.status && !r.status->ok) return error_from_status(*r.status);
        return std::move(r.values);
    });
}

std::shared_ptr<Responder> set_responder(Completion<std::vector<SetResult>> done) {
    return make<SetResponse, std::vector<SetResult>>(std::move(done), [](SetResponse& r) -> Result<std::vector<SetResult>> {
        if (r.status && !r.status->ok) return error_from_status(*r.status);
        return std::move(r.results);
    });
}

}  // namespace nclink::client_detail
