// The three data types of GB/T 41970 6.2.1 a data object can have.
#pragma once

#include <optional>
#include <string_view>

namespace nclink {

/// `datatype` of a data object: absent means single (any JSON value, accessed
/// only as a whole), "list" (JSON array, element access by index) or "dict"
/// (JSON object, element access by key).
enum class DataKind { single, list, dict };

constexpr std::string_view to_string(DataKind kind) noexcept {
    switch (kind) {
        case DataKind::single: return "single";
        case DataKind::list: return "list";
        case DataKind::dict: return "dict";
    }
    return "single";
}

}  // namespace nclink
