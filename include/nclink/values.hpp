// Value operations of GB/T 41970-2022 6.2.1 and 8.1.5: how the `params` of one
// Query (8.2.11) or Set (8.2.13) item read or change a data item's value.
//
// Two layers, so vendor drivers can serve machine-held values themselves:
//   parse_query / parse_set   params JSON (QueryItem::params / SetItem::params
//                             of dtu.hpp) -> typed QueryParams / SetParams,
//                             validated against the item's DataKind;
//   evaluate / apply          run a parsed request on a Json value the caller
//                             holds (the SDK's ValueStore, or a driver's copy).
// evaluate_query / apply_set do both in one call.
//
// Every failure is an Error whose code is the table-19 code to answer with;
// nothing here throws. docs/values.md has the complete error mapping and the
// offset/length rules. All functions are pure (no shared state) and so safe
// to call from any thread; ValueStore (value_store.hpp) adds the locking.
#pragma once

#include <nclink/data_kind.hpp>
#include <nclink/export.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

/// One entry of `indexes`: "5" is {5, 5}, "5-8" is {5, 8}. Inclusive bounds,
/// first <= last always holds for a parsed range.
struct NCLINK_API IndexRange {
    std::size_t first = 0;
    std::size_t last = 0;

    /// Number of indexes covered (saturates at SIZE_MAX for absurd ranges).
    std::size_t count() const noexcept;
    friend bool operator==(const IndexRange& a, const IndexRange& b) noexcept { return a.first == b.first && a.last == b.last; }
};

/// Parses one index entry: a non-negative integer number, a numeric string
/// ("7", " 7 ") or a range string ("5-8"). Errors: 405 for the wrong JSON type
/// or a non-numeric string ("abc", 1.5), 412 for a malformed range ("8-5",
/// "5-", "-1"), 101 for a negative number or one that does not fit size_t.
NCLINK_API Result<IndexRange> parse_index(const Json& entry);

/// Total number of indexes the ranges select (duplicates counted; saturating).
NCLINK_API std::size_t index_count(const std::vector<IndexRange>& ranges) noexcept;

/// Most elements one request may select (ranges may overlap, so a small
/// payload could otherwise select billions): beyond it, 404.
inline constexpr std::size_t max_selected_indexes = std::size_t{1} << 20;

/// The selected indexes flattened in request order (duplicates kept), after
/// checking every one against `length`: 101 when one is >= length, 404 when
/// more than max_selected_indexes are selected. Checks before expanding, so
/// a hostile "0-4000000000" never allocates.
NCLINK_API Result<std::vector<std::size_t>> expand_indexes(const std::vector<IndexRange>& ranges, std::size_t length);

// ---------------------------------------------------------------- Query --

enum class QueryOperation {
    get_value,       ///< whole item (no keys/indexes), or the selected elements
    get_keys,        ///< dict only
    get_length,      ///< list only
    get_attributes,  ///< dict or list: JSON type name of each selected element
};

/// "get_value", "get_keys", ... as on the wire.
NCLINK_API std::string_view to_string(QueryOperation op) noexcept;

/// The parsed `params` of one Query item.
struct NCLINK_API QueryParams {
    QueryOperation operation = QueryOperation::get_value;
    std::vector<std::string> keys;    ///< dict get_value/get_attributes, in request order
    std::vector<IndexRange> indexes;  ///< list get_value/get_attributes, in request order
    /// Appendix A Query_Params: part of each selected list element (get_value
    /// only), as a Set's offset/length write it: code points of a string,
    /// elements of an array, bits of an integer (one bit, 0 or 1, without length).
    std::optional<std::size_t> offset;
    std::optional<std::size_t> length;

    /// True when the whole value is asked for (params absent, null or {}, or
    /// get_value on a single item). The response is then `[value]`.
    bool whole_item() const noexcept { return operation == QueryOperation::get_value && keys.empty() && indexes.empty(); }
};

/// Parses `params` of one Query item (pass a null Json when absent).
NCLINK_API Result<QueryParams> parse_query(const Json& params, DataKind kind);

/// Runs a query on `current` and returns the response `values` array:
/// whole item -> [value]; get_value -> one element per key / selected index
/// in request order; get_keys -> the keys; get_length -> [n];
/// get_attributes -> "number"/"string"/"boolean"/"array"/"object"/"null" per
/// selected element. A null `current` (value unknown) answers the whole-item
/// query with [null] and every element operation with 202.
NCLINK_API Result<Json> evaluate(const QueryParams& request, const Json& current, DataKind kind);
/// The same, consuming `current`: a whole-item answer takes the value over
/// instead of copying it (the common Query, answered per item).
NCLINK_API Result<Json> evaluate(const QueryParams& request, Json&& current, DataKind kind);

/// parse_query + evaluate.
NCLINK_API Result<Json> evaluate_query(const Json& params, const Json& current, DataKind kind);

// ------------------------------------------------------------------ Set --

enum class SetOperation {
    set_value,  ///< default when `operation` is omitted
    add,        ///< dict: new key; list: insert at index (index == length appends)
    remove,     ///< "delete" on the wire (a C++ keyword)
};

/// "set_value", "add", "delete" as on the wire.
NCLINK_API std::string_view to_string(SetOperation op) noexcept;

/// The parsed `params` of one Set item.
///
/// Targets are `keys` (dict), the flattened `indexes` (list), or the whole
/// item when both are empty. `values` holds either one value per target, in
/// target order, or exactly one value written to every target (the request
/// gave `value` with several targets); use value_for(). Empty for delete.
///
/// `offset`/`length` (set_value on list elements only) patch part of the
/// element instead of replacing it:
///   string element: UTF-8 code points; the `length` code points from
///     `offset` are replaced by the given string (length defaults to the new
///     string's length; offset + length must not pass the end, 101);
///   array element: elements; likewise, an array value is spliced element by
///     element, any other value counts as one element;
///   integer element, offset only: bit `offset` (0-63) is set when the value
///     is true or a non-zero number and cleared when false or 0 (HNC register
///     convention);
///   integer element, offset + length: the bit field of `length` bits at
///     `offset` gets the integer value (must fit, else 101).
/// An omitted offset with a length means offset 0.
struct NCLINK_API SetParams {
    SetOperation operation = SetOperation::set_value;
    std::vector<std::string> keys;
    std::vector<IndexRange> indexes;
    std::vector<Json> values;
    std::optional<std::size_t> offset;
    std::optional<std::size_t> length;

    bool whole_item() const noexcept { return keys.empty() && indexes.empty(); }
    /// Number of targets: keys, selected indexes (with duplicates), or 1.
    std::size_t target_count() const noexcept;
    /// The value for the i-th target (0-based, in target order); a null Json
    /// when there is none (delete, or a hand-built request that is short).
    const Json& value_for(std::size_t target) const noexcept;
};

/// Parses `params` of one Set item (pass a null Json when absent, which is
/// 102: there is no value to write).
NCLINK_API Result<SetParams> parse_set(const Json& params, DataKind kind);

/// Applies a set to `current`. Mutates only on success: a request touching
/// several keys/indexes either changes all of them or none. Checks `setable`
/// first (301). Type rule: a written value must have the JSON type of the
/// element it replaces (numbers of any kind are one type) unless that element
/// is null; a whole dict/list value must stay an object/array (405).
NCLINK_API Result<void> apply(const SetParams& request, Json& current, DataKind kind, bool setable);

/// `setable` check (301), then parse_set + apply.
NCLINK_API Result<void> apply_set(const Json& params, Json& current, DataKind kind, bool setable);

// -------------------------------------------------------------- helpers --

/// JSON type name used by get_attributes: "number", "string", "boolean",
/// "array", "object" or "null".
NCLINK_API std::string_view json_type_name(const Json& value) noexcept;

/// True when `value` may replace `existing` under the set type rule above.
NCLINK_API bool same_value_type(const Json& existing, const Json& value) noexcept;

}  // namespace nclink

#include <nclink/value_store.hpp>
