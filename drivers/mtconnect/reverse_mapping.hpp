// GB/T 39561.3 appendix A read in reverse: an MTConnect device (its probe)
// as an NC-Link model (GB/T 41970-2022 chapters 6 and 7), plus the table
// that turns each DataItem's observations into the NC-Link item's value.
//
// The rule (docs/mapping.md "The reverse direction"):
//  - a DataItem becomes the NC-Link type whose forward mapping, at the same
//    place (device, controller, axis), is that DataItem's category, type and
//    subType (the tables of src/mapping/mapping_table.cpp, never a copy);
//    where several types map to one form the first row of the tables wins,
//    but inside a Rotary axis a SPINDLE_ type is preferred (a spindle);
//  - EVENT MESSAGE with subType x:<TYPE> (nclink's own fallback) becomes TYPE;
//  - a type only the subType differs from (POSITION COMMANDED) becomes that
//    type, with a note;
//  - anything else has no counterpart: it keeps its MTConnect type as its
//    NC-Link type and says "MTConnect <CATEGORY> <type>[/<subType>] (no
//    NC-Link counterpart)" in its description, and is listed in `unmatched`;
//  - units: the NC-Link spelling whose MTConnect units (and nativeUnits) are
//    the DataItem's, preferring the type's default spelling; values are
//    converted back (nclink = (mtconnect - offset) / scale);
//  - components: Linear/Rotary -> AXIS (with a CATAGORY config linear or
//    rotary), Controller -> CONTROLLER, Axes and a Controller's Path are
//    folded into their parent, the other elements by table 8's rows;
//    elements without a row become COMPONENT, named in their description;
//  - CONDITION DataItems -> WARNING items (value: the active alarms);
//  - AVAILABILITY -> no item: it is the machine link (Driver::link());
//  - a DataItem with a single Constraints/Value is a fixed value (a config
//    object with "value"); Description@manufacturer/model/serialNumber ->
//    MANUFACTURER/MODEL/SERIAL_NUMBER configs;
//  - DataItems with a sampleRate (A.4 h: the rate of their sample channel)
//    are grouped by rate into SAMPLE_CHANNELs of the device, sampleInterval
//    1000/rate ms but at least ReverseOptions::min_sample_interval_ms (the
//    values change no faster than the source is read), uploadInterval the
//    larger of 1000 ms and sampleInterval.
#pragma once

#include "mtconnect/probe_document.hpp"

#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace nclink::mtconnect {

/// How an observation's text becomes the NC-Link value.
enum class ValueRule {
    number,        ///< a float, converted: (v - offset) / scale
    number_3d,     ///< "x y z" -> [x, y, z], each converted
    integer,       ///< an integer
    text,          ///< the text as is
    json,          ///< JSON text (nclink's fallback of objects and lists) parsed, else the text
    words,         ///< through `words` (MTConnect word -> NC-Link word)
    boolean,       ///< "true"/"false" (or words mapping to them) -> a JSON boolean
    condition,     ///< a CONDITION: the active alarms as a list
    availability,  ///< AVAILABILITY: the machine link, no item
};

/// One DataItem and the NC-Link item it feeds.
struct ItemBinding {
    std::string mt_id;      ///< DataItem id
    std::string shdr_key;   ///< <Source>, else name, else id: the key of an SHDR line
    std::string name;       ///< DataItem name
    std::string nclink_id;  ///< "" for availability
    std::string nclink_type;
    std::string category;  ///< SAMPLE, EVENT, CONDITION
    std::string mt_type;   ///< POSITION
    std::string units;     ///< the NC-Link unit spelling, "" for none
    ValueRule rule = ValueRule::text;
    double scale = 1;
    double offset = 0;
    std::vector<std::pair<std::string, std::string>> words;  ///< MTConnect word -> NC-Link word
    bool fixed = false;                                      ///< a single Constraints/Value: the model holds the value
};

/// A DataItem or component with no NC-Link counterpart.
struct NoCounterpart {
    std::string mt_id;      ///< DataItem or component id
    std::string mtconnect;  ///< "EVENT CLOCK_TIME", "component Door"
    std::string became;     ///< "CLOCK_TIME (description names it)", "COMPONENT"
};

struct ReverseModel {
    Json model;                      ///< the NC-Link model document (NC_LINK_ROOT)
    std::string dev_uuid;            ///< the device's guid (the MTConnect uuid)
    std::string mt_device;           ///< the MTConnect Device's name or id
    std::string instance_id;         ///< the probe's Header@instanceId
    std::vector<ItemBinding> items;  ///< every DataItem of the device, in document order
    std::vector<NoCounterpart> unmatched;
    std::vector<std::string> notes;                             ///< assumptions a reader should know
    std::unordered_map<std::string, std::size_t> by_mt_id;      ///< DataItem id -> items
    std::unordered_map<std::string, std::size_t> by_shdr_key;   ///< SHDR key -> items
    std::unordered_map<std::string, std::size_t> by_nclink_id;  ///< NC-Link id -> items

    const ItemBinding* find_mt(std::string_view id) const;
    const ItemBinding* find_shdr(std::string_view key) const;
    const ItemBinding* find_nclink(std::string_view id) const;
};

struct ReverseOptions {
    std::string device;                 ///< the Device's uuid, name or id; "" = the first
    std::string root_id = "mtconnect";  ///< the model's root id
    std::string version = "1.0.0";      ///< the device's model version
    int min_sample_interval_ms = 100;   ///< the shortest sampleInterval of a generated channel
};

/// The NC-Link model of one device of `probe`. Errors: node_not_exists (204)
/// for an unknown device; key_error when two DataItems give one NC-Link id.
Result<ReverseModel> reverse_map(const ProbeDocument& probe, const ReverseOptions& options = {});

}  // namespace nclink::mtconnect
