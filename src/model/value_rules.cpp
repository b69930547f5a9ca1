// Compiles chapter 7 (value_tables.cpp) into one ValueRule per data object
// and checks values against it. The checks never allocate on a passing
// value and never parse: a rule is a handful of fields switched on.
#include "model/value_tables.hpp"

#include <nclink/model.hpp>
#include <nclink/value_rules.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string>

namespace nclink {

using model_detail::KeySpec;
using model_detail::ObjectSpec;

namespace {

constexpr std::uint8_t kWhole = 0, kList = 1, kDict = 2;

std::string upper(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

std::string_view shape_name(ValueShape shape) noexcept {
    switch (shape) {
        case ValueShape::any: return "any JSON";
        case ValueShape::number: return "number";
        case ValueShape::string: return "string";
        case ValueShape::boolean: return "Boolean";
        case ValueShape::object: return "object";
        case ValueShape::array: return "list (array)";
        case ValueShape::dict: return "dict (object)";
        case ValueShape::file: return "file (an object naming the file)";
        case ValueShape::number_or_string: return "number or string";
    }
    return "any JSON";
}

std::string clip(const Json& value) {
    std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
    if (text.size() > 120) text = text.substr(0, 117) + "...";
    return text;
}

void say(std::string* why, std::string text) {
    if (why != nullptr && why->empty()) *why = std::move(text);
}

ValueFault check_object(const ObjectSpec& spec, const Json& value, const std::vector<std::string>& axes, std::string* why);

// A key's value against the shape table 14 gives it.
bool key_shape_ok(ValueShape shape, const Json& value, std::string* why) {
    switch (shape) {
        case ValueShape::any: return true;
        case ValueShape::number: return value.is_number();
        case ValueShape::string: return value.is_string();
        case ValueShape::boolean: return value.is_boolean();
        case ValueShape::object: return value.is_object();
        case ValueShape::array: return value.is_array();
        case ValueShape::dict: return value.is_object() || value.is_array();
        case ValueShape::number_or_string: return value.is_number() || value.is_string();
        case ValueShape::file: return check_object(model_detail::file_object(), value, {}, why) == ValueFault::none;
    }
    return true;
}

// An object of table 14 (or a FILE object). {} passes: it says "none" (no
// active warning, no part loaded); otherwise the required keys must be
// there, the known keys must hold their shape and, for a COORDINATE, the
// axis keys must be numbers naming axes the device declares.
ValueFault check_object(const ObjectSpec& spec, const Json& value, const std::vector<std::string>& axes, std::string* why) {
    if (!value.is_object()) {
        if (why) say(why, fmt::format("a {} value is an object, not {}", spec.name, value.type_name()));
        return ValueFault::type;
    }
    if (value.empty()) return ValueFault::none;
    for (const KeySpec& key : spec.keys) {
        if (key.required && !value.contains(key.key)) {
            if (why) say(why, fmt::format("a {} object has the key \"{}\"", spec.name, key.key));
            return ValueFault::missing_key;
        }
    }
    for (auto it = value.begin(); it != value.end(); ++it) {
        const Json& member = it.value();
        if (member.is_null()) continue;
        const std::string& name = it.key();
        const auto known = std::find_if(spec.keys.begin(), spec.keys.end(), [&](const KeySpec& k) { return k.key == name; });
        if (known != spec.keys.end()) {
            if (!key_shape_ok(known->shape, member, why)) {
                if (why)
                    say(why, fmt::format("\"{}\" of a {} is a {}, not {}", name, spec.name, shape_name(known->shape),
                                         member.type_name()));
                return ValueFault::key_type;
            }
            continue;
        }
        if (!spec.axis_keys || !model_detail::is_axis_key(name)) continue;  // a key of the user's own
        if (!member.is_number()) {
            if (why) say(why, fmt::format("axis value \"{}\" of a {} is a number, not {}", name, spec.name, member.type_name()));
            return ValueFault::key_type;
        }
        if (!axes.empty() && std::find(axes.begin(), axes.end(), upper(name)) == axes.end()) {
            std::string list;
            for (const auto& a : axes) list += (list.empty() ? "" : ", ") + a;
            if (why)
                say(why, fmt::format("\"{}\" names axis {}, but the device declares the axes {} (AXIS components, table 9)", name,
                                     upper(name), list));
            return ValueFault::axis;
        }
    }
    return ValueFault::none;
}

// First non-space character of pre-serialized JSON.
char first_char(std::string_view text) noexcept {
    for (char c : text)
        if (c != ' ' && c != '\t' && c != '\n' && c != '\r') return c;
    return '\0';
}

bool is_number_kind(SampleValue::Kind kind) noexcept {
    return kind == SampleValue::Kind::int64 || kind == SampleValue::Kind::uint64 || kind == SampleValue::Kind::float64;
}

}  // namespace

std::string_view to_string(ValueFault fault) noexcept {
    switch (fault) {
        case ValueFault::none: return "none";
        case ValueFault::kind: return "kind";
        case ValueFault::type: return "type";
        case ValueFault::enumeration: return "enumeration";
        case ValueFault::range: return "range";
        case ValueFault::missing_key: return "missing key";
        case ValueFault::key_type: return "key type";
        case ValueFault::axis: return "axis";
    }
    return "none";
}

ErrorCode error_code(ValueFault fault) noexcept {
    switch (fault) {
        case ValueFault::none: return ErrorCode::success;
        case ValueFault::kind:
        case ValueFault::type:
        case ValueFault::key_type: return ErrorCode::value_type;
        case ValueFault::enumeration:
        case ValueFault::range: return ErrorCode::out_of_range;
        case ValueFault::missing_key:
        case ValueFault::axis: return ErrorCode::key_error;
    }
    return ErrorCode::value_type;
}

// ---- compiling ------------------------------------------------------------------

ValueRule ValueRule::compile(const DataObject& object, std::string_view parent_type, const std::vector<std::string>& axes) {
    ValueRule r;
    r.id_ = object.id;
    r.type_ = object.type;
    const model_detail::TypeSpec* spec = model_detail::type_spec(object.type);
    ValueShape base = spec ? spec->shape : ValueShape::any;
    r.typed_ = spec != nullptr;
    r.where_ = spec ? std::string(spec->where) : std::string();
    if (spec) {
        r.object_ = spec->object;
        for (auto v : spec->enumeration) r.enumeration_.emplace_back(v);
        r.int_enumeration_ = spec->int_enumeration;
        r.has_min_ = spec->has_min;
        r.min_ = spec->temperature ? model_detail::absolute_zero(object.units) : spec->min;
        r.has_max_ = spec->has_max;
        r.max_ = spec->max;
        if (object.type == "CATAGORY")
            for (auto v : model_detail::catagory_values(parent_type)) r.enumeration_.emplace_back(v);
        if (object.type == "COORDINATE")
            for (const auto& a : axes) r.axes_.push_back(upper(a));
    }
    if (object.datatype_file) {
        // `datatype: "file"` (6.2.1): a whole value naming a file, whatever the type.
        base = ValueShape::file;
        r.object_ = &model_detail::file_object();
        r.typed_ = true;
        if (r.where_.empty()) r.where_ = "6.2.1";
    }
    switch (object.kind) {
        case DataKind::single:
            r.container_ = kWhole;
            r.shape_ = base;
            break;
        case DataKind::list:
            r.container_ = kList;
            r.shape_ = (base == ValueShape::array || base == ValueShape::dict) ? ValueShape::any : base;
            break;
        case DataKind::dict:
            r.container_ = kDict;
            if (base == ValueShape::object || base == ValueShape::file) {
                r.whole_object_ = true;  // a COORDINATE/WARNING/FILE accessed by key: the keys are the object's
                r.shape_ = base;
            } else {
                r.shape_ = (base == ValueShape::array || base == ValueShape::dict) ? ValueShape::any : base;
            }
            break;
    }
    if (base == ValueShape::file && r.object_ == nullptr) r.object_ = &model_detail::file_object();
    return r;
}

ValueRules::ValueRules(const Model& model) {
    // The AXIS numbers of each device (table 9), for COORDINATE keys.
    std::unordered_map<std::string, std::vector<std::string>> axes;
    for (const auto& c : model.components())
        if (c.type == "AXIS" && !c.number.empty()) axes[c.device_id].push_back(c.number);
    static const std::vector<std::string> none;
    for (const auto& object : model.data_objects()) {
        std::string_view parent_type;
        if (const ObjectInfo* info = model.find(object.id)) {
            if (const Component* c = model.component(info->parent_id)) parent_type = c->type;
            else if (const Device* d = model.device(info->parent_id)) parent_type = d->type;
        }
        const auto found = axes.find(object.device_id);
        rules_.emplace(object.id, ValueRule::compile(object, parent_type, found != axes.end() ? found->second : none));
    }
}

const ValueRule* ValueRules::find(std::string_view id) const {
    const auto it = rules_.find(std::string(id));
    return it == rules_.end() ? nullptr : &it->second;
}

Result<void> ValueRules::verify(std::string_view id, const Json& whole) const {
    const ValueRule* rule = find(id);
    return rule ? rule->verify(whole) : ok_result();
}

// ---- checking Json ----------------------------------------------------------------

ValueFault ValueRule::check_element(const Json& value, std::string* why) const {
    if (value.is_null()) return ValueFault::none;
    switch (shape_) {
        case ValueShape::any: return ValueFault::none;
        case ValueShape::number: {
            if (!value.is_number()) return ValueFault::type;
            const double v = value.get<double>();
            if ((has_min_ && v < min_) || (has_max_ && v > max_)) return ValueFault::range;
            return ValueFault::none;
        }
        case ValueShape::string:
            if (value.is_string()) {
                if (enumeration_.empty()) return ValueFault::none;
                const auto& text = value.get_ref<const std::string&>();
                return std::find(enumeration_.begin(), enumeration_.end(), text) != enumeration_.end() ? ValueFault::none
                                                                                                       : ValueFault::enumeration;
            }
            if (!int_enumeration_.empty() && value.is_number_integer()) {
                const auto n = value.get<std::int64_t>();
                return std::find(int_enumeration_.begin(), int_enumeration_.end(), n) != int_enumeration_.end()
                           ? ValueFault::none
                           : ValueFault::enumeration;
            }
            return ValueFault::type;
        case ValueShape::boolean: return value.is_boolean() ? ValueFault::none : ValueFault::type;
        case ValueShape::object:
        case ValueShape::file:
            if (!value.is_object()) return ValueFault::type;
            return object_ ? check_object(*object_, value, axes_, why) : ValueFault::none;
        case ValueShape::array: return value.is_array() ? ValueFault::none : ValueFault::type;
        case ValueShape::dict: return value.is_object() || value.is_array() ? ValueFault::none : ValueFault::type;
        case ValueShape::number_or_string: return value.is_number() || value.is_string() ? ValueFault::none : ValueFault::type;
    }
    return ValueFault::none;
}

// Without `why` nothing here allocates, so nothing can throw.
ValueFault ValueRule::check(const Json& whole) const noexcept { return check_json(whole, nullptr); }

ValueFault ValueRule::check_json(const Json& whole, std::string* why) const {
    if (whole.is_null()) return ValueFault::none;
    if (container_ == kList) {
        if (!whole.is_array()) return ValueFault::kind;
        if (shape_ == ValueShape::any) return ValueFault::none;
        for (std::size_t i = 0; i < whole.size(); ++i) {
            const ValueFault f = check_element(whole[i], why);
            if (f != ValueFault::none) {
                if (why) say(why, fmt::format("element {}", i));
                return f;
            }
        }
        return ValueFault::none;
    }
    if (container_ == kDict) {
        if (!whole.is_object()) return ValueFault::kind;
        if (whole_object_) return check_element(whole, why);
        if (shape_ == ValueShape::any) return ValueFault::none;
        for (auto it = whole.begin(); it != whole.end(); ++it) {
            const ValueFault f = check_element(it.value(), why);
            if (f != ValueFault::none) {
                if (why) say(why, fmt::format("key \"{}\"", it.key()));
                return f;
            }
        }
        return ValueFault::none;
    }
    return check_element(whole, why);
}

// ---- checking samples ----------------------------------------------------------------

ValueFault ValueRule::check_scalar(const SampleValue& value) const noexcept {
    const auto kind = value.kind();
    switch (shape_) {
        case ValueShape::any: return ValueFault::none;
        case ValueShape::number: {
            if (kind == SampleValue::Kind::json) return ValueFault::none;  // a number literal? needs_parse()
            if (!is_number_kind(kind)) return ValueFault::type;
            if (!has_min_ && !has_max_) return ValueFault::none;
            const double v = kind == SampleValue::Kind::float64 ? value.as_double()
                             : kind == SampleValue::Kind::int64 ? static_cast<double>(value.as_int64())
                                                                : static_cast<double>(value.as_uint64());
            return (has_min_ && v < min_) || (has_max_ && v > max_) ? ValueFault::range : ValueFault::none;
        }
        case ValueShape::string:
            if (kind == SampleValue::Kind::text) {
                if (enumeration_.empty()) return ValueFault::none;
                const std::string_view text = value.as_text();
                for (const auto& allowed : enumeration_)
                    if (allowed == text) return ValueFault::none;
                return ValueFault::enumeration;
            }
            if (kind == SampleValue::Kind::json) return ValueFault::none;
            if (!int_enumeration_.empty() && (kind == SampleValue::Kind::int64 || kind == SampleValue::Kind::uint64)) {
                const auto n = kind == SampleValue::Kind::int64 ? value.as_int64() : static_cast<std::int64_t>(value.as_uint64());
                for (auto allowed : int_enumeration_)
                    if (allowed == n) return ValueFault::none;
                return ValueFault::enumeration;
            }
            return ValueFault::type;
        case ValueShape::boolean:
            return kind == SampleValue::Kind::boolean || kind == SampleValue::Kind::json ? ValueFault::none : ValueFault::type;
        case ValueShape::object:
        case ValueShape::file:
            return kind == SampleValue::Kind::json && first_char(value.as_text()) == '{' ? ValueFault::none : ValueFault::type;
        case ValueShape::array:
            return kind == SampleValue::Kind::json && first_char(value.as_text()) == '[' ? ValueFault::none : ValueFault::type;
        case ValueShape::dict: {
            const char c = kind == SampleValue::Kind::json ? first_char(value.as_text()) : '\0';
            return c == '{' || c == '[' ? ValueFault::none : ValueFault::type;
        }
        case ValueShape::number_or_string:
            return is_number_kind(kind) || kind == SampleValue::Kind::text || kind == SampleValue::Kind::json ? ValueFault::none
                                                                                                              : ValueFault::type;
    }
    return ValueFault::none;
}

ValueFault ValueRule::check(const SampleValue& value) const noexcept {
    const auto kind = value.kind();
    if (kind == SampleValue::Kind::null) return ValueFault::none;
    if (container_ == kList)
        return kind == SampleValue::Kind::json && first_char(value.as_text()) == '[' ? ValueFault::none : ValueFault::kind;
    if (container_ == kDict)
        return kind == SampleValue::Kind::json && first_char(value.as_text()) == '{' ? ValueFault::none : ValueFault::kind;
    return check_scalar(value);
}

bool ValueRule::needs_parse(const SampleValue& value) const noexcept {
    if (value.kind() != SampleValue::Kind::json) return false;
    if (container_ != kWhole) return shape_ != ValueShape::any || whole_object_;
    return shape_ != ValueShape::any && shape_ != ValueShape::array && shape_ != ValueShape::dict;
}

bool ValueRule::number_bounds(double& min, double& max) const noexcept {
    if (container_ != kWhole || shape_ != ValueShape::number) return false;
    min = has_min_ ? min_ : -std::numeric_limits<double>::infinity();
    max = has_max_ ? max_ : std::numeric_limits<double>::infinity();
    return true;
}

// ---- messages ------------------------------------------------------------------------

std::string ValueRule::explain(ValueFault fault) const {
    const std::string item = type_.empty() ? fmt::format("\"{}\"", id_) : fmt::format("\"{}\" ({})", id_, type_);
    const std::string_view container = container_ == kList ? "list" : container_ == kDict ? "dict" : "single";
    switch (fault) {
        case ValueFault::none: return item + ": the value fits its rule";
        case ValueFault::kind:
            return fmt::format("{} is a {} item: its value is {} (datatype, 6.2.1)", item, container,
                               container_ == kList ? "an array" : "an object");
        case ValueFault::type:
            return fmt::format("{}: {} gives it {} values{}", item, where_.empty() ? "chapter 7" : where_, shape_name(shape_),
                               container_ == kWhole ? "" : " (each element)");
        case ValueFault::enumeration: {
            std::string allowed;
            for (const auto& v : enumeration_) allowed += (allowed.empty() ? "" : ", ") + fmt::format("\"{}\"", v);
            for (auto v : int_enumeration_) allowed += (allowed.empty() ? "" : ", ") + std::to_string(v);
            return fmt::format("{}: {} allows only {}", item, where_, allowed);
        }
        case ValueFault::range: {
            std::string range;
            if (has_min_) range = fmt::format(">= {}", min_);
            if (has_max_) range += (range.empty() ? "" : " and ") + fmt::format("<= {}", max_);
            return fmt::format("{}: a physical quantity of {} is {}", item, where_, range);
        }
        case ValueFault::missing_key:
        case ValueFault::key_type:
        case ValueFault::axis:
            return fmt::format("{}: its object does not follow {}", item, where_.empty() ? "table 14" : where_);
    }
    return item;
}

Result<void> ValueRule::verify(const Json& whole) const {
    std::string why;
    const ValueFault fault = check_json(whole, &why);
    if (fault == ValueFault::none) return ok_result();
    std::string message = explain(fault);
    if (!why.empty()) message += " (" + why + ")";
    message += ": got " + clip(whole);
    return make_error(error_code(fault), std::move(message));
}

}  // namespace nclink
