// The simulator's state, shared by sim_driver.cpp (reads, time, methods)
// and sim_commit.cpp (what a Set does). Internal to drivers/sim.
#pragma once

#include "sim/sim_driver.hpp"

#include "mill_kinematics.hpp"
#include "mill_profile.hpp"
#include "value_generators.hpp"

#include <nclink/clock.hpp>

#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace nclink {
namespace sim_detail {

using sim::MillMethod;
using sim::MillRole;

struct Item {
    const DataObject* object = nullptr;
    /// Unused (default) when `use_stored`.
    sim::Generator generator;
    std::optional<MillRole> role;
    /// The value lives in `stored` (lists, dicts, fixed values): Sets change it.
    bool use_stored = false;
    /// A generated list/dict not Set yet: its value is make_collection()'s,
    /// built at each read rather than kept (build()).
    bool generated = false;
    Json stored;
    /// A Set on a computed single value holds it here (mill: until reset).
    std::optional<Json> pinned;
    /// WARNING items show the alarm state.
    bool alarm = false;
};

/// A count given as a number or a decimal string (part counts, tool numbers).
inline std::optional<std::int64_t> as_count(const Json& v) {
    if (v.is_number_integer() && v.get<std::int64_t>() >= 0) return v.get<std::int64_t>();
    if (v.is_number_unsigned()) return static_cast<std::int64_t>(v.get<std::uint64_t>());
    if (v.is_string()) {
        const auto& s = v.get_ref<const std::string&>();
        if (s.empty() || s.size() > 18 || s.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
        return std::stoll(s);
    }
    return std::nullopt;
}

}  // namespace sim_detail

struct SimDriver::Impl {
    using Item = sim_detail::Item;
    std::shared_ptr<const Model> model;
    SimOptions options;
    std::optional<Error> broken;
    const Device* device = nullptr;
    std::vector<Item> items;
    /// The row in `items` of each of the model's data objects (no_row: not
    /// this device's), by position in model->data_objects(): ids are found
    /// through the shared model's index, not a map of each machine's own.
    static constexpr std::uint32_t no_row = UINT32_MAX;
    std::vector<std::uint32_t> row_by_object;
    /// The row of data item `id` (bind(), and points without a handle).
    std::optional<std::size_t> row_of_id(std::string_view id) const;
    /// The row of `point`: its handle, else its id. Call with the mutex held.
    std::optional<std::size_t> row_of(const PointRef& point) const;
    std::optional<sim::MillProfile> profile;
    std::unique_ptr<sim::MillMachine> mill;
    std::uint64_t stream = 0;

    Clock::Steady start{};
    Clock::Steady last{};
    double t = 0;  // simulated seconds since construction
    std::int64_t wall_ms = 0;

    std::vector<Json> alarms;  // raised explicitly (API, Set), oldest first
    std::int64_t suppressed_slot = std::numeric_limits<std::int64_t>::min();
    bool emergency = false;

    mutable std::mutex mutex;
    /// Texts lent by read_samples(), valid until its next call (reserved per
    /// call, so no element moves while views into it are out).
    std::vector<std::string> lent_texts;  // read_samples: a text per point, kept to reuse its room

    void build();
    sim::ItemTraits traits_of(const DataObject& object) const;
    void advance();
    Json value_of(const Item& item) const;
    /// value_of() as a sample without a heap allocation (a text lands in
    /// `text`), for the mill's measured items; nullopt: take value_of().
    std::optional<SampleValue> sample_of(const Item& item, std::string& text) const;
    Json alarm_value(const Item& item) const;
    Result<void> commit(Item& item, Json value);
    Result<void> commit_mill(Item& item, sim::MillRole role, Json value);
    Result<void> commit_alarms(const Item& item, const Json& value);
    void add_alarm(const std::string& number, const std::string& text);
    void suppress_spontaneous();
    void release_mill_pins();
};

}  // namespace nclink
