// The vocabulary of GB/T 41970-2022 chapter 7 as nclink's validator knows it:
// device types (table 7), component types (table 8), data object types
// (tables 10, 12, 13) with the value and default units the tables give,
// the fixed values of table 15/16, unit names (tables 10, 11, appendix A) and
// the deployed spellings the validator recognises. docs/vocabulary.md is
// generated from these tables (vocabulary_markdown(); a test fails when the
// file drifts). Constant data: every function is thread-safe.
#pragma once

#include <nclink/export.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

/// One standard type.
struct NCLINK_API VocabularyTerm {
    std::string_view name;     ///< "AXIS", "POSITION"
    std::string_view source;   ///< the clause or table that defines it: "table 8"
    std::string_view meaning;  ///< in English
    std::string_view value;    ///< data types: the value's type the table gives ("number", "Boolean", "object"...)
    std::string_view units;    ///< data types: the default units ("mm"), empty when none
    std::string_view values;   ///< data types with fixed values (tables 15, 16): "running, free, holding"
};

/// Unit names of one source (the validator accepts every one).
struct NCLINK_API VocabularyUnits {
    std::string_view source;  ///< "table 10/13 default units", "table 11", "appendix A unitType"...
    std::vector<std::string_view> units;
};

/// A spelling seen in deployed files, what the standard calls it, and whether
/// the validator takes it as that term (conformance problem) or only hints.
struct NCLINK_API VocabularyAlias {
    std::string_view used;
    std::string_view meant;
    std::string_view why;
};

NCLINK_API const std::vector<VocabularyTerm>& vocabulary_device_types();
NCLINK_API const std::vector<VocabularyTerm>& vocabulary_component_types();
NCLINK_API const std::vector<VocabularyTerm>& vocabulary_data_types();
NCLINK_API const std::vector<VocabularyUnits>& vocabulary_units();
/// Misspellings and abbreviations of standard types (conformance problems).
NCLINK_API const std::vector<VocabularyAlias>& vocabulary_type_aliases();
/// Common names for standard units and component types that the standard
/// spells otherwise ("rpm" -> "r/min", "SPINDLE" -> AXIS with number "S"):
/// the validator suggests them.
NCLINK_API const std::vector<VocabularyAlias>& vocabulary_hints();

/// docs/vocabulary.md: every table above as Markdown.
NCLINK_API std::string vocabulary_markdown();

}  // namespace nclink
