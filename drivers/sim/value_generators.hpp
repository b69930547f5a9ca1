// Generic simulation by data-object type: how any data object of any model
// gets a plausible value. Single values are pure functions of (generator,
// time), so a read at any cadence sees the same curve; list/dict items get a
// table that is a function of the seed (built at each read until a Set
// changes it, sim_driver.cpp) and changed only by Sets.
#pragma once

#include <nclink/data_kind.hpp>
#include <nclink/json.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::sim {

/// The simulator's reading of a `type`: upper case, known misspellings and
/// appendix-A aliases mapped to the chapter-7 name (`SPDL_OVERRIDE` ->
/// `SPINDLE_OVERRIDE`, `TYPE` -> `CATAGORY`, `manufacturer` -> `MANUFACTURER`).
std::string canonical_type(std::string_view type);

enum class Shape {
    drift,         ///< smooth noise within [lo, hi]
    stepped,       ///< piecewise constant, multiples of `step` in [lo, hi]
    override_pct,  ///< mostly 100, sometimes another multiple of 10 up to hi
    constant,      ///< a number fixed per item
    ramp,          ///< grows at `rate` per second from `base` (energy)
    sawtooth,      ///< falls from hi to lo every `period` seconds
    counter,       ///< integer base + floor(t / period), as a string
    line_number,   ///< program line advancing within a cycle, as a string
    boolean,       ///< true with probability p_true, re-drawn every period
    choice,        ///< one of `words` (weighted), re-drawn every period
    text,          ///< the fixed string `words[0]`
    warning,       ///< table-14 WARNING object, now and then an alarm
    object,        ///< a fixed object/array built at creation (`fixed`)
};

struct Generator {
    Shape shape = Shape::drift;
    std::uint64_t stream = 0;  ///< per-item random stream
    double lo = 0;
    double hi = 100;
    double period = 10;  ///< seconds
    double step = 1;
    double p_true = 0.5;
    double rate = 0;
    double base = 0;
    double origin = 0;  ///< time (s) at which `base` held (ramp, counter)
    int decimals = 3;   ///< rounding; 0 gives JSON integers
    std::vector<std::string> words;
    std::vector<double> weights;  ///< parallel to words (choice); empty = equal
    Json fixed;                   ///< Shape::object
};

/// Everything make_generator needs to know about one data object.
struct ItemTraits {
    std::string id;
    std::string name;
    std::string canonical;    ///< canonical_type(type)
    std::string parent_type;  ///< type of the owning component/device
    /// Under a rotary axis (AXIS numbered A/B/C..., table 9): positions are degrees.
    bool rotary = false;
    DataKind kind = DataKind::single;
};

/// The generator of a single value.
Generator make_generator(const ItemTraits& item, std::uint64_t seed, std::size_t list_size);

/// The value of a generator at `t` seconds of simulated time; `wall_ms` is
/// the clock's wall time at `t` (for emerge_time).
Json generate(const Generator& generator, double t, std::int64_t wall_ms);

/// The initial value of a list (array) or dict (object) item: `size`
/// elements that fit the type (TOOL_PARAM objects for TOOL, G54.. for
/// COORDINATE, numbers for PARAMETER, ...).
Json make_collection(const ItemTraits& item, std::uint64_t seed, std::size_t size);

/// Table-14 WARNING object.
Json warning_object(const std::string& number, const std::string& text, std::int64_t emerge_time);

/// A typical alarm (number, text) from a small catalogue, chosen by `pick`.
std::pair<std::string, std::string> sample_alarm(std::uint64_t pick);

}  // namespace nclink::sim
