// The model engine: loads, validates, indexes and serializes an NC-Link probe
// (model) file, GB/T 41970-2022 chapter 6 with the vocabularies of chapter 7.
//
// Loading never throws and never stops at the first defect: every problem is
// collected with a JSON pointer (RFC 6901) into the file, so a vendor can fix
// a model in one round. A file with a fatal problem yields no Model.
//
// Thread safety: a Model is immutable after load; every member is const and
// may be called from any number of threads at once. LoadResult shares it via
// std::shared_ptr<const Model> so adapters can swap models atomically.
#pragma once

#include <nclink/data_kind.hpp>
#include <nclink/export.hpp>
#include <nclink/json.hpp>

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace nclink {

/// How bad a problem is.
///  - fatal: the model cannot be run (no Model is produced);
///  - conformance: a deviation from chapter 6 that nclink still runs
///    (`nclink validate` fails, an adapter in strict mode refuses the file);
///  - warning: allowed by the standard but suspicious (unknown vocabulary, ...).
enum class Severity { fatal, conformance, warning };

/// "fatal", "conformance", "warning".
NCLINK_API std::string_view to_string(Severity severity) noexcept;

/// One finding of the validator.
struct NCLINK_API Problem {
    Severity severity = Severity::fatal;
    /// RFC 6901 pointer into the loaded document; "" is the whole file. For a
    /// missing attribute it points where the attribute should be.
    std::string pointer;
    std::string message;
};

/// Kinds of object in a model.
enum class ObjectKind {
    root,
    device,
    component,
    data_item,       ///< data object listed in `dataItems` (a sample source)
    config_item,     ///< data object listed in `configs` (queryable, not sampled)
    sample_channel,  ///< SAMPLE_CHANNEL object
    method,          ///< METHOD object
};

/// "root", "device", "component", "data_item", "config_item", "sample_channel", "method".
NCLINK_API std::string_view to_string(ObjectKind kind) noexcept;

/// Where an object sits in the model; one per indexed object.
struct NCLINK_API ObjectInfo {
    ObjectKind kind = ObjectKind::data_item;
    std::string id;
    /// Owning device id; "" for the root and objects in the root's configs.
    std::string device_id;
    /// Id of the containing root/device/component.
    std::string parent_id;
    /// Component path, see component_path rule in docs/model.md:
    /// "/" + the `type` of each object from the device down to this one,
    /// "@number" appended when the object has a `number`
    /// ("/MACHINE/AXIS@X/SCREW/POSITION"). Objects in the root's configs use
    /// the root type as first segment ("/NC_LINK_ROOT/METHOD"). Paths need not
    /// be unique; Model::ids_at_path lists every id sharing one.
    std::string path;
    /// JSON pointer of the object in the loaded file (provenance only: it is
    /// not part of model equality).
    std::string pointer;
    /// A data object's `source` attribute as written (6.2.5 note b,
    /// "NC_LINK_ROOT:MACHINE#0001:AXIS"); "" for other kinds.
    std::string source;
};

/// Ordered children of a root, device or component (ids in file order).
struct NCLINK_API Children {
    std::vector<std::string> configs;     ///< data objects, channels, methods
    std::vector<std::string> data_items;  ///< data objects (and misplaced objects)
    std::vector<std::string> components;  ///< components (devices for the root)
};

struct NCLINK_API Root {
    std::string id;
    std::string name;
    std::string type;  ///< "NC_LINK_ROOT" (also when the file omits it)
    std::string description;
    std::string version;          ///< normalized: "1.0.0" when missing, "1.2" -> "1.2.0"
    Children children;            ///< children.components holds the device ids
    Json extra = Json::object();  ///< attributes chapter 6 does not define, kept verbatim
};

struct NCLINK_API Device {
    std::string id;
    std::string name;
    std::string type;
    std::string description;
    std::string number;
    std::optional<std::string> guid;
    std::string version;  ///< normalized like Root::version
    Children children;
    Json extra = Json::object();
};

struct NCLINK_API Component {
    std::string id;
    std::string name;
    std::string type;
    std::string description;
    std::string number;
    std::string device_id;
    Children children;
    Json extra = Json::object();
};

/// A data object (table 4), from `dataItems` or from `configs`.
struct NCLINK_API DataObject {
    std::string id;
    std::string name;
    std::string type;
    std::string description;
    DataKind kind = DataKind::single;
    /// `datatype: "file"`: 6.2.1 names file a data type beside list and dict
    /// (table 4 allows only those two). The item is accessed as a whole, like
    /// a single item (kind is single), and its value is a file object
    /// (docs/values.md, "FILE").
    bool datatype_file = false;
    /// Given only when the value is known and fixed (table 4 note a).
    std::optional<Json> value;
    /// `source` exactly as written ("NC_LINK_ROOT:MACHINE#0001:AXIS").
    std::string source;
    std::string units;
    bool setable = false;
    /// True for objects listed in a `configs` array (6.2.2 note b: never sampled).
    bool config = false;
    std::string device_id;  ///< "" for root configs
    Json extra = Json::object();
};

/// A SAMPLE_CHANNEL object (table 5).
struct NCLINK_API SampleChannel {
    std::string id;
    std::string name;
    std::string description;
    std::vector<std::string> ids;  ///< sampled data items, in column order
    /// Milliseconds as double: appendix A wants positive integers, but a
    /// fractional interval is representable and harmless to carry.
    double sample_interval_ms = 0;
    double upload_interval_ms = 0;
    std::string device_id;  ///< owning device ("" if misplaced in the root)
    Json extra = Json::object();
};

/// A METHOD object (table 6).
struct NCLINK_API Method {
    std::string id;
    std::string name;
    std::string description;
    Json args;  ///< as written (object in the standard's examples); null when absent
    Json extra = Json::object();
};

bool operator==(const Children& a, const Children& b);
bool operator==(const Root& a, const Root& b);
bool operator==(const Device& a, const Device& b);
bool operator==(const Component& a, const Component& b);
bool operator==(const DataObject& a, const DataObject& b);
bool operator==(const SampleChannel& a, const SampleChannel& b);
bool operator==(const Method& a, const Method& b);

class ModelBuilder;  // src/model: the only writer

/// A loaded model. Immutable; all lookups are O(1) on ids.
class NCLINK_API Model {
public:
    const Root& root() const noexcept { return root_; }
    /// Objects of each kind in file order.
    const std::vector<Device>& devices() const noexcept { return devices_; }
    const std::vector<Component>& components() const noexcept { return components_; }
    const std::vector<DataObject>& data_objects() const noexcept { return data_objects_; }
    const std::vector<SampleChannel>& channels() const noexcept { return channels_; }
    const std::vector<Method>& methods() const noexcept { return methods_; }
    /// Every indexed object (root first) in file order.
    const std::vector<ObjectInfo>& objects() const noexcept { return objects_; }

    /// Kind, owner, path and pointer of any object; nullptr when unknown.
    const ObjectInfo* find(std::string_view id) const;
    const Device* device(std::string_view id) const;
    const Component* component(std::string_view id) const;
    const DataObject* data_object(std::string_view id) const;
    const SampleChannel* channel(std::string_view id) const;
    const Method* method(std::string_view id) const;
    /// Device owning the object (the device itself for a device id).
    const Device* owning_device(std::string_view id) const;
    /// Ids whose component path is `path`, in file order (empty if none).
    const std::vector<std::string>& ids_at_path(std::string_view path) const;
    /// The channel's data objects in column order (empty for unknown channels).
    std::vector<const DataObject*> channel_items(std::string_view channel_id) const;

    friend bool operator==(const Model& a, const Model& b);

private:
    friend class ModelBuilder;
    struct Slot {
        std::size_t object = 0;  // into objects_
        std::size_t typed = 0;   // into the vector of its kind
    };

    Root root_;
    std::vector<Device> devices_;
    std::vector<Component> components_;
    std::vector<DataObject> data_objects_;
    std::vector<SampleChannel> channels_;
    std::vector<Method> methods_;
    std::vector<ObjectInfo> objects_;
    std::unordered_map<std::string, Slot> by_id_;
    std::unordered_map<std::string, std::vector<std::string>> by_path_;
};

/// Model equality: same objects with the same attributes in the same places.
/// JSON pointers (provenance) are ignored.
bool operator==(const Model& a, const Model& b);
inline bool operator!=(const Model& a, const Model& b) { return !(a == b); }

/// Outcome of loading: every problem found, and the model unless a problem is fatal.
struct NCLINK_API LoadResult {
    std::vector<Problem> problems;
    std::shared_ptr<const Model> model;
    /// The document exactly as provided, in UTF-8 (a GBK file converted, a
    /// UTF-8 byte order mark dropped); set whenever `model` is. The model is
    /// normalized (versions, spellings); this text is what was given, and is
    /// what an adapter answers Probe/Query with (8.2.8).
    std::shared_ptr<const std::string> document;

    bool ok() const noexcept { return model != nullptr; }
    std::size_t count(Severity severity) const noexcept;
};

/// Parses and validates model text (UTF-8, or GBK when it is not valid UTF-8).
NCLINK_API LoadResult parse_model(std::string_view text);

/// Reads a file and parses it; an unreadable file is a fatal problem at "".
NCLINK_API LoadResult load_model_file(const std::string& path);

/// The model as a probe document: 2-space indent, chapter-6 spelling
/// (`datatype`, `setable` as boolean), attributes in the order
/// id/name/type/description/... Unknown attributes follow the known ones.
/// parse_model(serialize_model(m)) yields a model equal to m.
NCLINK_API std::string serialize_model(const Model& model);
/// The same document as a JSON value (for Probe/Query responses).
NCLINK_API Json model_to_json(const Model& model);

/// Terminal id of a device (8.1.4; docs/wire.md "Model files in the wild"): `override_id` when not empty
/// (configuration/command line), else the device `guid`, else its `id`.
NCLINK_API std::string resolve_dev_uuid(const Device& device, std::string_view override_id = {});

}  // namespace nclink
