// Names, equality and the dev_uuid rule: the small value-level parts of the model API.
#include <nclink/model.hpp>

#include <algorithm>

namespace nclink {

std::string_view to_string(Severity severity) noexcept {
    switch (severity) {
        case Severity::fatal: return "fatal";
        case Severity::conformance: return "conformance";
        case Severity::warning: return "warning";
    }
    return "fatal";
}

std::string_view to_string(ObjectKind kind) noexcept {
    switch (kind) {
        case ObjectKind::root: return "root";
        case ObjectKind::device: return "device";
        case ObjectKind::component: return "component";
        case ObjectKind::data_item: return "data_item";
        case ObjectKind::config_item: return "config_item";
        case ObjectKind::sample_channel: return "sample_channel";
        case ObjectKind::method: return "method";
    }
    return "data_item";
}

std::size_t LoadResult::count(Severity severity) const noexcept {
    return static_cast<std::size_t>(
        std::count_if(problems.begin(), problems.end(), [&](const Problem& p) { return p.severity == severity; }));
}

std::string resolve_dev_uuid(const Device& device, std::string_view override_id) {
    if (!override_id.empty()) return std::string(override_id);
    if (device.guid && !device.guid->empty()) return *device.guid;
    return device.id;
}

bool operator==(const Children& a, const Children& b) {
    return a.configs == b.configs && a.data_items == b.data_items && a.components == b.components;
}

bool operator==(const Root& a, const Root& b) {
    return a.id == b.id && a.name == b.name && a.type == b.type && a.description == b.description && a.version == b.version &&
           a.children == b.children && a.extra == b.extra;
}

bool operator==(const Device& a, const Device& b) {
    return a.id == b.id && a.name == b.name && a.type == b.type && a.description == b.description && a.number == b.number &&
           a.guid == b.guid && a.version == b.version && a.children == b.children && a.extra == b.extra;
}

bool operator==(const Component& a, const Component& b) {
    return a.id == b.id && a.name == b.name && a.type == b.type && a.description == b.description && a.number == b.number &&
           a.device_id == b.device_id && a.children == b.children && a.extra == b.extra;
}

bool operator==(const DataObject& a, const DataObject& b) {
    return a.id == b.id && a.name == b.name && a.type == b.type && a.description == b.description && a.kind == b.kind &&
           a.datatype_file == b.datatype_file && a.value == b.value && a.source == b.source && a.units == b.units &&
           a.setable == b.setable && a.config == b.config && a.device_id == b.device_id && a.extra == b.extra;
}

bool operator==(const SampleChannel& a, const SampleChannel& b) {
    return a.id == b.id && a.name == b.name && a.description == b.description && a.ids == b.ids &&
           a.sample_interval_ms == b.sample_interval_ms && a.upload_interval_ms == b.upload_interval_ms &&
           a.device_id == b.device_id && a.extra == b.extra;
}

bool operator==(const Method& a, const Method& b) {
    return a.id == b.id && a.name == b.name && a.description == b.description && a.args == b.args && a.extra == b.extra;
}

namespace {

bool same_place(const ObjectInfo& a, const ObjectInfo& b) {
    return a.kind == b.kind && a.id == b.id && a.device_id == b.device_id && a.parent_id == b.parent_id && a.path == b.path &&
           a.source == b.source;
}

}  // namespace

bool operator==(const Model& a, const Model& b) {
    return a.root_ == b.root_ && a.devices_ == b.devices_ && a.components_ == b.components_ &&
           a.data_objects_ == b.data_objects_ && a.channels_ == b.channels_ && a.methods_ == b.methods_ &&
           std::equal(a.objects_.begin(), a.objects_.end(), b.objects_.begin(), b.objects_.end(), same_place);
}

}  // namespace nclink
