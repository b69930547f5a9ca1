// JSON type names (get_attributes) and the type rule of set_value.
#include "values/value_internal.hpp"

namespace nclink {
namespace {

// Numbers of every representation are one type for clients: number is
// "dynamically converted to integer or float by its user" (6.2.1).
Json::value_t category(const Json& value) noexcept {
    switch (value.type()) {
        case Json::value_t::number_integer:
        case Json::value_t::number_unsigned:
        case Json::value_t::number_float: return Json::value_t::number_float;
        case Json::value_t::discarded: return Json::value_t::null;
        default: return value.type();
    }
}

}  // namespace

std::string_view json_type_name(const Json& value) noexcept {
    switch (value.type()) {
        case Json::value_t::object: return "object";
        case Json::value_t::array: return "array";
        case Json::value_t::string: return "string";
        case Json::value_t::boolean: return "boolean";
        case Json::value_t::number_integer:
        case Json::value_t::number_unsigned:
        case Json::value_t::number_float: return "number";
        case Json::value_t::binary: return "binary";
        case Json::value_t::null:
        case Json::value_t::discarded: return "null";
    }
    return "null";
}

bool same_value_type(const Json& existing, const Json& value) noexcept {
    return existing.is_null() || category(existing) == category(value);
}

namespace values_detail {

bool fits_kind(const Json& value, DataKind kind) noexcept {
    switch (kind) {
        case DataKind::single: return true;
        case DataKind::list: return value.is_null() || value.is_array();
        case DataKind::dict: return value.is_null() || value.is_object();
    }
    return false;
}

}  // namespace values_detail
}  // namespace nclink
