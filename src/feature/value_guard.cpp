#include "feature/value_guard.hpp"

#include <fmt/format.h>

namespace nclink::feature_detail {

void ValueGuard::screen(const ModelState& state, const std::string& id, Result<Json>& read, std::string_view source) {
    if (!enabled_ || !read || !state.rules) return;
    screen(state.rules->find(id), read, source);
}

void ValueGuard::screen(const ValueRule* rule, Result<Json>& read, std::string_view source) {
    if (!enabled_ || !read || rule == nullptr || rule->check(read.value()) == ValueFault::none) return;
    auto verdict = rule->verify(read.value());
    if (verdict) return;  // cannot happen: check() and verify() agree
    refused_.fetch_add(1, std::memory_order_relaxed);
    report(*rule, source, verdict.error().code, verdict.error().message);
    read = Result<Json>(std::move(verdict).error());
}

bool ValueGuard::admit(const ModelState& state, const std::string& id, const Json& value, std::string_view source) {
    if (!enabled_ || !state.rules) return true;
    const ValueRule* rule = state.rules->find(id);
    if (rule == nullptr || rule->check(value) == ValueFault::none) return true;
    refused_.fetch_add(1, std::memory_order_relaxed);
    auto verdict = rule->verify(value);
    if (!verdict) report(*rule, source, verdict.error().code, verdict.error().message);
    return false;
}

void ValueGuard::refuse(const ValueRule& rule, ValueFault fault, std::string_view source, std::string_view shown) {
    refused_.fetch_add(1, std::memory_order_relaxed);
    std::string text(shown.substr(0, 120));
    if (shown.size() > 120) text += "...";
    report(rule, source, error_code(fault), fmt::format("{}: got {}", rule.explain(fault), text));
}

std::size_t ValueGuard::refused_items() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return logged_.size();
}

void ValueGuard::report(const ValueRule& rule, std::string_view source, ErrorCode code, const std::string& message) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!logged_.insert(rule.id()).second) return;
    }
    logger_.warn(
        "value of item {} refused on {} (chapter 7; answered {}): {}. Further refusals of this item are only "
        "counted (nclink stats: values.refused)",
        rule.id(), source, to_int(code), message);
}

}  // namespace nclink::feature_detail
