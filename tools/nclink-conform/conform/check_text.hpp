// Small text helpers the conformance checks share (checks.cpp,
// checks_sample.cpp): how a value is shown in a finding, and the checks of
// one string key.
#pragma once

#include "conform/checks.hpp"

#include <nclink/json.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace nclink::conform::check_text {

/// A value as a finding shows it (compact JSON, clipped).
std::string show(const Json& value, std::size_t max = 200);
std::string lower(std::string_view text);
/// A string member, or std::nullopt when absent or not a string.
std::optional<std::string> str(const Json& dtu, const char* key);
/// Appends `from` to `to`, each finding prefixed.
void add_all(Problems& to, Problems from, std::string_view prefix = {});
/// A required string key equal to `expected` (`table` names the rule).
void expect_string(Problems& out, const Json& dtu, const char* key, std::string_view expected, std::string_view table);
/// Envelope and status keys of a response.
Problems response_basics(const Json& dtu, const Json& sent_id, std::string_view dev, bool guid_required);

}  // namespace nclink::conform::check_text
