// The current NC-Link value of every item of an MTConnect source, kept up to
// date by the source's thread (agent_source, shdr_source) and read by the
// driver's read() on the SDK's threads: every call is one short lock.
#pragma once

#include "mtconnect/observation_values.hpp"
#include "mtconnect/reverse_mapping.hpp"
#include "mtconnect/streams_document.hpp"

#include <nclink/json.hpp>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace nclink::mtconnect {

class LiveValues {
public:
    /// A (new) mapping: every value starts unknown (null).
    void install(std::shared_ptr<const ReverseModel> model);
    std::shared_ptr<const ReverseModel> model() const;

    /// Forgets every value (a /current follows, or the source restarted).
    void reset();
    /// One observation of the agent's Streams; unknown DataItem ids are ignored
    /// (another device's, or one the probe did not list). Returns whether it was used.
    bool apply(const StreamObservation& observation);
    /// By SHDR key: a value token, or a condition's fields (shdr_source).
    bool apply_value(const std::string& shdr_key, const std::string& text);
    bool apply_condition(const std::string& shdr_key, const std::string& level, const std::string& native_code,
                         const std::string& text);
    /// Every item (after a lost SHDR connection: nothing is known any more).
    void all_unavailable();

    /// The value of an NC-Link item: nullopt when the item is not in the
    /// mapping, null while it has no value (UNAVAILABLE).
    std::optional<Json> get(const std::string& nclink_id) const;
    /// AVAILABILITY of the device: nullopt when the probe has none or no
    /// observation came yet.
    std::optional<bool> available() const;

private:
    bool apply_at(std::size_t index, const std::string& element, const std::string& native_code, const std::string& text,
                  bool condition);

    mutable std::mutex mutex_;
    std::shared_ptr<const ReverseModel> model_;
    std::vector<Json> values_;
    std::vector<ConditionAlarms> alarms_;
    std::optional<bool> available_;
};

}  // namespace nclink::mtconnect
