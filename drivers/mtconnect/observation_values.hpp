// An observation's text as the NC-Link value of its item (the rules of
// reverse_mapping.hpp), and a condition's active alarms.
//
// UNAVAILABLE (MTConnect 1.4 part 3: the value is not known) is the item's
// absence of value: null, which the driver answers as 202 Unavailable
// (docs/gateway.md "MTConnect and SHDR sources"). One exception: a word
// table that maps UNAVAILABLE to an NC-Link word (SPINDLE_MODE "stop",
// appendix A's spindle direction) gives that word.
#pragma once

#include "mtconnect/reverse_mapping.hpp"

#include <nclink/json.hpp>

#include <map>
#include <string>
#include <string_view>

namespace nclink::mtconnect {

/// The NC-Link value of `text` for a SAMPLE or EVENT item; null for
/// UNAVAILABLE and for text the item's rule cannot read (a number item
/// given "abc": the observation says nothing usable).
Json value_of(const ItemBinding& item, std::string_view text);

/// The alarms a CONDITION item has active (MTConnect 1.4 part 3, 5.6:
/// each nativeCode is activated by Warning/Fault and cleared by Normal; a
/// Normal without nativeCode clears them all).
class ConditionAlarms {
public:
    /// One state: "Normal", "Warning", "Fault" or "Unavailable".
    void apply(std::string_view level, const std::string& native_code, const std::string& text);
    /// Forgets everything (before a /current, which lists every active one).
    void reset();
    /// null while unavailable; else the list of {"number", "text", "level"}
    /// (level "WARNING" or "FAULT"), empty when normal.
    Json value() const;

private:
    bool available_ = false;
    struct Alarm {
        std::string level;
        std::string text;
    };
    std::map<std::string, Alarm> active_;  ///< by nativeCode ("" for none given)
};

}  // namespace nclink::mtconnect
