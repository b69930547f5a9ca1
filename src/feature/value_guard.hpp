// Chapter 7 at the SDK boundary: every value a driver hands the SDK (a read
// for Query or events, a sampled row, Adapter::notify_value) is checked
// against its item's rule (value_rules.hpp) before it goes on the wire. A
// value that breaks the rule is never published as if good: a Query answers
// the item NG with the rule's table-19 code (405, 101 or 410), a Sample DTU
// carries null in its slot (a missed value, 6.2.6.2), an event sees nothing.
// Each refusal is counted; the first of each item is logged with why (the
// driver author's clue, docs/porting-guide.md "Values the SDK checks").
//
// Thread safety: every member is thread-safe. The passing path takes no lock
// and allocates nothing; a refusal takes a short lock for the once-per-item log.
#pragma once

#include "feature/model_state.hpp"

#include <nclink/log.hpp>
#include <nclink/result.hpp>
#include <nclink/value_rules.hpp>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_set>

namespace nclink::feature_detail {

class ValueGuard {
public:
    /// `enabled` false: nothing is checked (AdapterConfig::check_values).
    explicit ValueGuard(Logger logger, bool enabled = true) : logger_(std::move(logger)), enabled_(enabled) {}

    bool enabled() const noexcept { return enabled_; }

    /// A driver's answer `read` for item `id`, checked against the item's
    /// rule in `state`: a value breaking it becomes the rule's table-19 error
    /// (refused: counted, logged the first time for the item). `source`
    /// names the path in the log ("query", "event poll", ...).
    void screen(const ModelState& state, const std::string& id, Result<Json>& read, std::string_view source);
    /// The same with the item's rule already found (ModelState::entry(); null: no rule).
    void screen(const ValueRule* rule, Result<Json>& read, std::string_view source);

    /// True when `value` may go out for item `id` (no rule, or it passes);
    /// otherwise refused as above.
    bool admit(const ModelState& state, const std::string& id, const Json& value, std::string_view source);

    /// Records one refusal of `rule`'s item (a sampled value the caller
    /// checked itself); `shown` is the value as text, for the log.
    void refuse(const ValueRule& rule, ValueFault fault, std::string_view source, std::string_view shown);

    /// Values refused so far, and the items they belonged to.
    std::uint64_t refused() const noexcept { return refused_.load(std::memory_order_relaxed); }
    std::size_t refused_items() const;

private:
    void report(const ValueRule& rule, std::string_view source, ErrorCode code, const std::string& message);

    const Logger logger_;
    const bool enabled_;
    std::atomic<std::uint64_t> refused_{0};
    mutable std::mutex mutex_;
    std::unordered_set<std::string> logged_;
};

}  // namespace nclink::feature_detail
