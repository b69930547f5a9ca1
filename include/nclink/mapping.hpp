// Model mapping (GB/T 39561.3-2020): an NC-Link model (GB/T 41970-2022
// chapters 6 and 7) as an MTConnect 1.4 Devices document (appendix A) and as
// an OPC UA NodeSet2 document (appendix B, optionally OPC 40502 "CNC
// Systems"), plus the per-item lookup a bridge needs to publish live values.
//
//   auto r = nclink::load_model_file("models/sim-mill.json");
//   auto doc = nclink::map_to_mtconnect(*r.model);          // Devices XML
//   for (const auto& u : doc->unmapped) warn(u.id, u.reason);
//   auto mt = nclink::mtconnect_mapping(*r.model);           // lookup
//   const nclink::MtDataItem* x = mt->find("x_position");    // Position, ACTUAL
//   for (auto& o : nclink::mtconnect_observations(*x, 12.5)) // "12.5"
//       stream(x->component_id, o.element, x->id, o.value);
//
// The identifier contract other parts of nclink rely on (docs/mapping.md):
//  - MTConnect: Device uuid = the terminal id (resolve_dev_uuid); DataItem id
//    = mtconnect_id(NC-Link id), which is the NC-Link id itself whenever that
//    is an ASCII XML name (see mtconnect_id); every Device has an AVAILABILITY
//    EVENT with id MtDevice::availability_id (normally "<device id>_avail").
//  - OPC UA: one namespace per device, urn:nclink:device:<dev_uuid>; every data
//    object is a variable "ns=<k>;s=<NC-Link id>", every component an object
//    "ns=<k>;s=<component id>", the device object "ns=<k>;s=<dev_uuid>";
//    auxiliary properties "s=<id>.EngineeringUnits", ".EURange",
//    ".EnumStrings", ".TrueState", ".FalseState". Setable items have
//    AccessLevel 3, the rest 1.
//
// Everything here is pure and thread-safe: results are values, nothing throws.
#pragma once

#include <nclink/export.hpp>
#include <nclink/json.hpp>
#include <nclink/model.hpp>
#include <nclink/result.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace nclink {

// ------------------------------------------------------------------ options

/// Which OPC UA information model map_to_opcua writes.
///  - basic: GB/T 39561.3 appendix B only; loads with the base nodeset alone.
///  - cnc:   basic plus OPC 40502 (CNC Systems 1.0): a CncInterface per device
///           with NC-Link axes, spindles and controllers as CncAxisType,
///           CncSpindleType and CncChannelType objects. Needs the CNC nodeset
///           (namespace http://opcfoundation.org/UA/CNC) loaded first.
enum class OpcUaProfile { basic, cnc };

/// "basic", "cnc".
NCLINK_API std::string_view to_string(OpcUaProfile profile) noexcept;
/// Parses "basic"/"cnc"; std::nullopt otherwise.
NCLINK_API std::optional<OpcUaProfile> opcua_profile_from_string(std::string_view text) noexcept;

struct NCLINK_API MappingOptions {
    /// Map only this device: its NC-Link id or its terminal id. Empty = all.
    std::string device;
    /// Terminal id override (as resolve_dev_uuid). Only with one device.
    std::string dev_uuid;
    OpcUaProfile opcua_profile = OpcUaProfile::basic;
    /// MTConnect Header creationTime and NodeSet LastModified/PublicationDate
    /// (xs:dateTime). Empty = the current UTC time. Tests pass a fixed one.
    std::string creation_time;
    /// MTConnect Header sender and instanceId.
    std::string sender = "nclink";
    std::uint64_t instance_id = 1;
    /// MTConnect only: when not empty, every id of the Devices document (the
    /// Device's, its components', its DataItems', the generated ones) starts
    /// with `mtconnect_id(id_prefix)` and a '.', so that the documents of
    /// several devices built from one model can share one document, where
    /// ids must be unique (MTConnect 1.4 part 2 IDType = xs:ID). The bridge
    /// passes the terminal id (docs/mapping.md "Identifier contract").
    std::string id_prefix;
};

// ------------------------------------------------------------------ documents

/// An object that had no standard mapping and went out under the fallback
/// rule (docs/mapping.md "Fallback"). Nothing is ever dropped silently.
struct NCLINK_API UnmappedItem {
    std::string id;           ///< NC-Link id of the data object or component
    std::string nclink_type;  ///< its type as written in the model
    std::string fallback;     ///< what it became ("EVENT MESSAGE x:TOOL", "System", ...)
    std::string reason;       ///< why (cites the clause where there is one)
};

/// Something the mapping assumed and a reader should know (a misspelt type
/// read as the standard one, a unit it could not convert, ...).
struct NCLINK_API MappingNote {
    std::string id;  ///< NC-Link id concerned
    std::string message;
};

struct NCLINK_API MappedDocument {
    std::string xml;                     ///< UTF-8, with XML declaration
    std::vector<UnmappedItem> unmapped;  ///< fallbacks, in model order
    std::vector<MappingNote> notes;
};

/// The MTConnect 1.4 Devices document (GB/T 39561.3 appendix A). Errors:
/// node_not_exists for an unknown MappingOptions::device, parameter_missing
/// when the model has no device, arguments_nimiety for dev_uuid with more than
/// one device, key_error when two generated identifiers collide.
NCLINK_API Result<MappedDocument> map_to_mtconnect(const Model& model, const MappingOptions& options = {});

/// The OPC UA NodeSet2 document (GB/T 39561.3 appendix B; OPC 40502 with
/// OpcUaProfile::cnc). Errors as map_to_mtconnect.
NCLINK_API Result<MappedDocument> map_to_opcua(const Model& model, const MappingOptions& options = {});

// ------------------------------------------------------------------ MTConnect lookup

enum class MtCategory { sample, event, condition };
/// "SAMPLE", "EVENT", "CONDITION".
NCLINK_API std::string_view to_string(MtCategory category) noexcept;

/// Where an NC-Link data object went in the Devices document.
enum class MtTarget {
    data_item,              ///< a DataItem of a standard 1.4 type
    fallback,               ///< a DataItem EVENT MESSAGE, subType x:<NC-Link type>
    description_attribute,  ///< a fixed value put into Description (table A.1/A.3 rows 3-5)
    component_element,      ///< a fixed value that chose the component element (Linear/Rotary)
};

/// How mtconnect_observations turns a JSON value into element text.
enum class MtValueForm {
    number,      ///< float pattern, after value * scale + offset (unit conversion)
    integer,     ///< [+-]?digits (PartCount, LineNumber)
    enumerated,  ///< through MtDataItem::values (booleans as "true"/"false")
    text,        ///< any text; objects and arrays as compact JSON
    condition,   ///< Normal/Fault/Unavailable per alarm
};

/// One NC-Link data object (data item or config item) as seen by MTConnect.
/// For the description_attribute and component_element targets there is no
/// DataItem: id, category, type and element are empty/unused.
struct NCLINK_API MtDataItem {
    std::string item_id;      ///< NC-Link id
    std::string nclink_type;  ///< chapter-7 spelling ("CATAGORY" for a written "TYPE")
    MtTarget target = MtTarget::data_item;
    std::string id;    ///< DataItem id (mtconnect_id(item_id))
    std::string name;  ///< DataItem name (NMTOKEN form of the NC-Link name), may be empty
    MtCategory category = MtCategory::event;
    std::string type;                   ///< "POSITION"
    std::string sub_type;               ///< "ACTUAL", "x:TOOL", or empty
    std::string units;                  ///< MTConnect units (SAMPLE only), may be empty
    std::string native_units;           ///< when the NC-Link unit differs from `units`
    std::optional<double> sample_rate;  ///< samples per second (A.4 h), when in a channel
    /// Observation element in a Streams document ("Position", "Execution",
    /// "RotaryVelocity", "Message"); empty for conditions, whose element is
    /// the state (MtObservation::element).
    std::string element;
    /// The component whose ComponentStream carries the observation.
    std::string component_id;       ///< MTConnect id ("axis_x", "controller_path", "mill")
    std::string component_element;  ///< "Linear", "Path", "Device", ...
    std::string component_name;     ///< may be empty
    std::string device_uuid;
    std::string attribute;  ///< description_attribute: "manufacturer", "model" or "serialNumber"
    MtValueForm value_form = MtValueForm::text;
    double scale = 1;  ///< number: MTConnect value = NC-Link value * scale + offset
    double offset = 0;
    /// enumerated: NC-Link value text -> MTConnect value ("running" -> "ACTIVE").
    std::vector<std::pair<std::string, std::string>> values;
};

struct NCLINK_API MtDevice {
    std::string item_id;          ///< NC-Link device id
    std::string uuid;             ///< terminal id (dev_uuid)
    std::string id;               ///< MTConnect Device id
    std::string name;             ///< MTConnect Device name (NMTOKEN)
    std::string availability_id;  ///< the AVAILABILITY DataItem id
};

/// The lookup of every data object of the mapped devices.
class NCLINK_API MtConnectMapping {
public:
    const std::vector<MtDevice>& devices() const noexcept { return devices_; }
    /// Every data object (dataItems and configs) of the mapped devices, in model order.
    const std::vector<MtDataItem>& items() const noexcept { return items_; }
    /// By NC-Link id; nullptr when unknown.
    const MtDataItem* find(std::string_view item_id) const;
    /// By DataItem id; nullptr when unknown (or not a DataItem).
    const MtDataItem* find_by_mtconnect_id(std::string_view id) const;
    /// The device entry of an NC-Link device id or terminal id; nullptr when unknown.
    const MtDevice* device(std::string_view id_or_uuid) const;

private:
    friend struct MtConnectMappingBuilder;
    std::vector<MtDevice> devices_;
    std::vector<MtDataItem> items_;
    std::unordered_map<std::string, std::size_t> by_item_;  ///< NC-Link id -> items_
    std::unordered_map<std::string, std::size_t> by_id_;    ///< DataItem id -> items_
};

NCLINK_API Result<MtConnectMapping> mtconnect_mapping(const Model& model, const MappingOptions& options = {});

/// One observation element of a Streams document.
struct NCLINK_API MtObservation {
    /// "Position", "Execution", ...; for conditions "Normal", "Fault" or "Unavailable".
    std::string element;
    /// Element text, NOT escaped (use xml_escape): a value, or "UNAVAILABLE".
    /// Conditions: the alarm text (may be empty).
    std::string value;
    std::string native_code;  ///< conditions: the alarm number, if any
    /// False when the NC-Link value cannot be expressed in the data item's
    /// type (a word outside its enumeration, text for a number): value is then
    /// UNAVAILABLE.
    bool exact = true;
};

/// The observation(s) for an NC-Link value (null = UNAVAILABLE). One element
/// for samples and events; for conditions one Fault per active alarm, or one
/// Normal / Unavailable. Empty for items that are no DataItem.
NCLINK_API std::vector<MtObservation> mtconnect_observations(const MtDataItem& item, const Json& value);

/// The MTConnect (XML ID) form of an NC-Link id: the id itself when it is an
/// ASCII NCName ([A-Za-z][A-Za-z0-9._-]*) not starting with '_'; otherwise
/// "_" followed by the UTF-8 bytes with every byte outside [A-Za-z0-9.-] as
/// "_XX" (two upper-case hex digits): "0103" -> "_0103", "a b" -> "_a_20b",
/// "_x" -> "__5Fx". Injective, so distinct NC-Link ids never collide.
NCLINK_API std::string mtconnect_id(std::string_view nclink_id);
/// The inverse of mtconnect_id; std::nullopt for text mtconnect_id never produces.
NCLINK_API std::optional<std::string> nclink_id_from_mtconnect(std::string_view mtconnect_id);

/// Text escaped for XML 1.0 element content and attribute values alike:
/// & < > " ' and TAB/LF/CR as character references; characters XML 1.0
/// forbids (other C0 controls, U+FFFE, U+FFFF) and invalid UTF-8 as U+FFFD.
NCLINK_API std::string xml_escape(std::string_view text);

// ------------------------------------------------------------------ OPC UA lookup

/// How the OPC UA server stores an NC-Link value in the variable.
enum class UaEncoding {
    scalar,      ///< the JSON number/string/boolean as DataType
    json,        ///< String holding compact JSON (lists, dicts, objects, files)
    enum_index,  ///< MultiStateDiscreteType: UInt32 index into enum_strings
    two_state,   ///< TwoStateDiscreteType: Boolean; for text items true = true_value
};

/// "scalar", "json", "enum_index", "two_state".
NCLINK_API std::string_view to_string(UaEncoding encoding) noexcept;

struct NCLINK_API UaVariable {
    std::string item_id;                   ///< NC-Link id
    std::string nclink_type;               ///< chapter-7 spelling
    std::string node_id;                   ///< "ns=1;s=x_position" (index within the document)
    std::string namespace_uri;             ///< urn:nclink:device:<dev_uuid>
    std::string browse_name;               ///< without namespace prefix
    std::string data_type;                 ///< "Double", "Int32", "UInt32", "Boolean", "String", "BaseDataType"
    std::string type_definition;           ///< "AnalogItemType", "TwoStateDiscreteType", ...
    int access_level = 1;                  ///< 1 CurrentRead, 3 CurrentRead|CurrentWrite (setable)
    double minimum_sampling_interval = 0;  ///< ms, the channel's sampleInterval
    UaEncoding encoding = UaEncoding::scalar;
    std::vector<std::string> enum_strings;  ///< enum_index: index -> NC-Link value
    std::string true_value;                 ///< two_state text items: the NC-Link value meaning true
    std::string false_value;
    bool fallback = false;  ///< BaseDataVariableType fallback (unknown type)
    /// cnc profile: the OPC 40502 slot this item fills ("CncAxisType/PosDirect/ActPos"),
    /// empty when none (its browse_name is then the slot's).
    std::string cnc_slot;
};

struct NCLINK_API UaNamespace {
    std::string uri;
    std::string device_id;  ///< NC-Link device id ("" for the CNC namespace)
    std::string dev_uuid;
};

class NCLINK_API OpcUaMapping {
public:
    /// NamespaceUris of the document in order (index 1 first).
    const std::vector<UaNamespace>& namespaces() const noexcept { return namespaces_; }
    const std::vector<UaVariable>& variables() const noexcept { return variables_; }
    const UaVariable* find(std::string_view item_id) const;

private:
    friend struct OpcUaMappingBuilder;
    std::vector<UaNamespace> namespaces_;
    std::vector<UaVariable> variables_;
    std::unordered_map<std::string, std::size_t> by_item_;  ///< NC-Link id -> variables_
};

NCLINK_API Result<OpcUaMapping> opcua_mapping(const Model& model, const MappingOptions& options = {});

/// The OPC 40502 namespace URI the cnc profile references (as the CNC
/// nodeset 1.0.0 and node-opcua-nodesets spell it: no trailing slash).
inline constexpr std::string_view cnc_namespace_uri = "http://opcfoundation.org/UA/CNC";

}  // namespace nclink
