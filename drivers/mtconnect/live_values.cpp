#include "mtconnect/live_values.hpp"

namespace nclink::mtconnect {

void LiveValues::install(std::shared_ptr<const ReverseModel> model) {
    std::lock_guard lock(mutex_);
    model_ = std::move(model);
    const std::size_t n = model_ ? model_->items.size() : 0;
    values_.assign(n, nullptr);
    alarms_.assign(n, ConditionAlarms{});
    available_.reset();
}

std::shared_ptr<const ReverseModel> LiveValues::model() const {
    std::lock_guard lock(mutex_);
    return model_;
}

void LiveValues::reset() {
    std::lock_guard lock(mutex_);
    for (auto& v : values_) v = nullptr;
    for (auto& a : alarms_) a.reset();
    available_.reset();
}

void LiveValues::all_unavailable() { reset(); }

bool LiveValues::apply_at(std::size_t index, const std::string& element, const std::string& native_code, const std::string& text,
                          bool condition) {
    const ItemBinding& item = model_->items[index];
    if (item.rule == ValueRule::availability) {
        available_ = text == "AVAILABLE";
        return true;
    }
    if (item.rule == ValueRule::condition) {
        if (!condition) return false;
        alarms_[index].apply(element, native_code, text);
        values_[index] = alarms_[index].value();
        return true;
    }
    if (item.fixed) return true;  // the model holds the value (a single Constraints/Value)
    values_[index] = value_of(item, text);
    return true;
}

bool LiveValues::apply(const StreamObservation& o) {
    std::lock_guard lock(mutex_);
    if (!model_) return false;
    const auto it = model_->by_mt_id.find(o.item_id);
    if (it == model_->by_mt_id.end()) return false;
    return apply_at(it->second, o.element, o.native_code, o.text, o.condition);
}

bool LiveValues::apply_value(const std::string& key, const std::string& text) {
    std::lock_guard lock(mutex_);
    if (!model_) return false;
    const auto it = model_->by_shdr_key.find(key);
    if (it == model_->by_shdr_key.end()) return false;
    if (model_->items[it->second].rule == ValueRule::condition) return false;
    return apply_at(it->second, {}, {}, text, false);
}

bool LiveValues::apply_condition(const std::string& key, const std::string& level, const std::string& native_code,
                                 const std::string& text) {
    std::lock_guard lock(mutex_);
    if (!model_) return false;
    const auto it = model_->by_shdr_key.find(key);
    if (it == model_->by_shdr_key.end() || model_->items[it->second].rule != ValueRule::condition) return false;
    return apply_at(it->second, level, native_code, text, true);
}

std::optional<Json> LiveValues::get(const std::string& nclink_id) const {
    std::lock_guard lock(mutex_);
    if (!model_) return std::nullopt;
    const auto it = model_->by_nclink_id.find(nclink_id);
    if (it == model_->by_nclink_id.end()) return std::nullopt;
    return values_[it->second];
}

std::optional<bool> LiveValues::available() const {
    std::lock_guard lock(mutex_);
    return available_;
}

}  // namespace nclink::mtconnect
