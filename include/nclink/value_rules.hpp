// What a value of a data object may be: the rules of GB/T 41970-2022
// chapter 7 (tables 10 and 12-16, appendix A), compiled once per model into
// one small checker per data object. The SDK checks every value a driver
// hands it (Driver::read(), read_samples(), PushChannel::push(),
// Adapter::notify_value()) and every value a Set writes against its item's
// rule, so a string for a POSITION, "spinning" for a SPINDLE_MODE or a
// WARNING without its number never goes on the wire as if it were good.
//
// A rule is made of what the model declares about the item:
//   - its `datatype`: a list item holds an array, a dict item an object;
//   - its `type`: the JSON type of table 10/12/13 (number, string, Boolean,
//     object, list, dict, file), the values table 15/16 allow (STATUS,
//     WORK_MODE, CATAGORY under an AXIS or a MACHINE, ...), the keys of
//     table 14 (COORDINATE, PART, TOOL_PARAM, WARNING) and, for a
//     COORDINATE, the axes the device declares (AXIS components, table 9);
//   - its `units`: a physical quantity keeps its physical range (a MASS is
//     not negative, a TEMPERATURE not below absolute zero in its units).
// A type the standard does not define gets only the datatype check. Null is
// always accepted: it is "no value now" (a missed read), never a wrong one.
// docs/values.md lists every rule; docs/porting-guide.md says what a driver
// author sees when a value is refused.
//
// Thread safety: ValueRules and ValueRule are immutable after construction;
// every member is const and may be called from any number of threads.
#pragma once

#include <nclink/error.hpp>
#include <nclink/export.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>
#include <nclink/sample_value.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace nclink {

class Model;
struct DataObject;

/// Why a value breaks its item's rule.
enum class ValueFault : std::uint8_t {
    none,
    kind,         ///< not an array for a list item / not an object for a dict item (405)
    type,         ///< the JSON type its type does not have, e.g. a string for a POSITION (405)
    enumeration,  ///< not one of the values tables 15/16 allow, e.g. SPINDLE_MODE "spinning" (101)
    range,        ///< a number outside its quantity's physical range, e.g. a negative MASS (101)
    missing_key,  ///< an object without a key table 14 requires, e.g. a WARNING without "text" (410)
    key_type,     ///< a key of table 14 holding the wrong JSON type (405)
    axis,         ///< a COORDINATE key naming an axis the device does not declare (410)
};

/// "kind", "type", "enumeration", "range", "missing key", "key type", "axis".
NCLINK_API std::string_view to_string(ValueFault fault) noexcept;
/// The table-19 code a refused value is answered with: 405 Value type error
/// for kind/type/key_type, 101 Out of Range for enumeration/range, 410 key
/// error for missing_key/axis.
NCLINK_API ErrorCode error_code(ValueFault fault) noexcept;

/// The JSON shape chapter 7 gives a value (or each element of one).
enum class ValueShape : std::uint8_t {
    any,
    number,
    string,
    boolean,
    object,            ///< a table-14 object (keys checked when the type has some)
    array,             ///< table 12/13 "list" (VARIABLE, TOOL, SHELF_UNIT)
    dict,              ///< table 12 "dict" (PARAMETER); appendix A gives it as an array: both accepted
    file,              ///< table 13 "file" (FILE; appendix A: a dict): an object naming a file
    number_or_string,  ///< where table 14 and appendix A disagree (TOOL_PARAM radius/length)
};

namespace model_detail {
struct ObjectSpec;  // the keys of one table-14 object (src/model/value_tables.hpp)
}

/// The compiled rule of one data object. Hold it by pointer from its
/// ValueRules (rules are looked up once, then checked per value).
class NCLINK_API ValueRule {
public:
    /// Checks a whole value (null passes). Never throws, never allocates.
    ValueFault check(const Json& whole) const noexcept;

    /// Checks a sampled value without parsing anything: null, numbers,
    /// booleans and text completely; pre-serialized JSON (SampleValue::json)
    /// only by its first character (an object for an object, an array for a
    /// list). needs_parse() says when such a value needs check(Json) of its
    /// parsed text for the rest (keys, elements).
    ValueFault check(const SampleValue& value) const noexcept;
    /// True when `value` is pre-serialized JSON whose full check needs it parsed.
    bool needs_parse(const SampleValue& value) const noexcept;
    /// For a single-valued number item: true, with its bounds (-inf / +inf
    /// where chapter 7 gives none), so a hot loop can check a float64 sample
    /// inline; `v < min || v > max` is then exactly check()'s range fault
    /// (NaN passes, as it does there). False for every other rule.
    bool number_bounds(double& min, double& max) const noexcept;

    /// check() as an Error: the table-19 code and a message naming the item,
    /// its type and what was wrong (for logs and driver authors; the wire
    /// carries only the code).
    Result<void> verify(const Json& whole) const;
    /// The message verify() gives for `fault` (value not shown).
    std::string explain(ValueFault fault) const;

    /// Compiles the rule of one data object. `parent_type` is the type of
    /// the component or device holding it (CATAGORY, table 16; "" = not
    /// checked), `axes` the AXIS numbers its device declares (COORDINATE
    /// keys; empty = not checked). ValueRules does this for a whole model.
    static ValueRule compile(const DataObject& object, std::string_view parent_type = {},
                             const std::vector<std::string>& axes = {});

    const std::string& id() const noexcept { return id_; }
    const std::string& type() const noexcept { return type_; }
    /// True when the rule checks more than the datatype (the type is one chapter 7 defines).
    bool typed() const noexcept { return typed_; }

private:
    ValueFault check_json(const Json& whole, std::string* why) const;
    ValueFault check_element(const Json& value, std::string* why) const;
    ValueFault check_scalar(const SampleValue& value) const noexcept;

    std::string id_;
    std::string type_;
    std::string where_;           ///< "table 10", "table 15", ... for messages
    std::uint8_t container_ = 0;  ///< 0 whole value, 1 list (array of elements), 2 dict (object of elements)
    bool whole_object_ = false;   ///< dict item whose type is an object/file: the keys apply to the whole
    bool typed_ = false;
    ValueShape shape_ = ValueShape::any;         ///< of the whole value (container 0) or of each element
    std::vector<std::string> enumeration_;       ///< allowed strings (empty = any)
    std::vector<std::int64_t> int_enumeration_;  ///< allowed integers besides (STATUS 0/1/2, appendix A)
    bool has_min_ = false, has_max_ = false;
    double min_ = 0, max_ = 0;
    const model_detail::ObjectSpec* object_ = nullptr;  ///< keys of table 14 (static storage)
    std::vector<std::string> axes_;  ///< the device's AXIS numbers, upper case (COORDINATE); empty = not checked
};

/// Every data object's rule, compiled from one model. Immutable.
class NCLINK_API ValueRules {
public:
    /// No rules: every value passes.
    ValueRules() = default;
    explicit ValueRules(const Model& model);

    /// The rule of data object `id`; nullptr when the model has no such data object.
    const ValueRule* find(std::string_view id) const;
    /// find() + verify(); an id without a rule passes.
    Result<void> verify(std::string_view id, const Json& whole) const;
    std::size_t size() const noexcept { return rules_.size(); }

private:
    std::unordered_map<std::string, ValueRule> rules_;
};

}  // namespace nclink
