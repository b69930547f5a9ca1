// The id and path index of a Model: built by ModelBuilder, read by lookups.
#include "model/model_builder.hpp"

#include <fmt/format.h>

namespace nclink {

std::shared_ptr<const Model> ModelBuilder::finish() {
    if (model_) {
        Model& m = *model_;
        m.devices_.shrink_to_fit();
        m.components_.shrink_to_fit();
        m.data_objects_.shrink_to_fit();
        m.channels_.shrink_to_fit();
        m.methods_.shrink_to_fit();
        m.objects_.shrink_to_fit();
    }
    return std::move(model_);
}

bool ModelBuilder::index(ObjectInfo info, std::size_t typed) {
    Model& m = *model_;
    const auto found = m.by_id_.find(info.id);
    if (found != m.by_id_.end()) {
        const ObjectInfo& first = m.objects_[found->second.object];
        problems_.fatal(
            model_detail::pointer_append(info.pointer, "id"),
            fmt::format("duplicate id \"{}\" (first defined at {})", info.id, first.pointer.empty() ? "/" : first.pointer));
        return false;
    }
    m.by_id_.emplace(info.id, Model::Slot{m.objects_.size(), typed});
    m.by_path_[info.path].push_back(info.id);
    m.objects_.push_back(std::move(info));
    return true;
}

bool ModelBuilder::set_root(Root root, ObjectInfo info) {
    if (!index(std::move(info), 0)) return false;
    model_->root_ = std::move(root);
    return true;
}

bool ModelBuilder::add_device(Device device, ObjectInfo info) {
    if (!index(std::move(info), model_->devices_.size())) return false;
    model_->devices_.push_back(std::move(device));
    return true;
}

bool ModelBuilder::add_component(Component component, ObjectInfo info) {
    if (!index(std::move(info), model_->components_.size())) return false;
    model_->components_.push_back(std::move(component));
    return true;
}

bool ModelBuilder::add_data_object(DataObject object, ObjectInfo info) {
    if (!index(std::move(info), model_->data_objects_.size())) return false;
    model_->data_objects_.push_back(std::move(object));
    return true;
}

bool ModelBuilder::add_channel(SampleChannel channel, ObjectInfo info) {
    if (!index(std::move(info), model_->channels_.size())) return false;
    model_->channels_.push_back(std::move(channel));
    return true;
}

bool ModelBuilder::add_method(Method method, ObjectInfo info) {
    if (!index(std::move(info), model_->methods_.size())) return false;
    model_->methods_.push_back(std::move(method));
    return true;
}

Children* ModelBuilder::children_of(const std::string& id) {
    Model& m = *model_;
    const auto found = m.by_id_.find(id);
    if (found == m.by_id_.end()) return nullptr;
    const std::size_t typed = found->second.typed;
    switch (m.objects_[found->second.object].kind) {
        case ObjectKind::root: return &m.root_.children;
        case ObjectKind::device: return &m.devices_[typed].children;
        case ObjectKind::component: return &m.components_[typed].children;
        default: return nullptr;
    }
}

// ---- lookups -------------------------------------------------------------

namespace {
// by_id_ is keyed by std::string and C++17 has no lookup by string_view:
// the key is copied into a buffer of the calling thread, which keeps its
// room, so an id longer than the small-string buffer (16 characters and
// more, "spindle_override") costs no allocation per lookup once warm (the
// sampling path and Query look items up by id).
const std::string& lookup_key(std::string_view id) {
    thread_local std::string key;
    key.assign(id.data(), id.size());
    return key;
}
}  // namespace

const ObjectInfo* Model::find(std::string_view id) const {
    const auto found = by_id_.find(lookup_key(id));
    return found == by_id_.end() ? nullptr : &objects_[found->second.object];
}

// One lookup per typed vector; the kinds listed are those stored in it.
#define NCLINK_MODEL_LOOKUP(Type, name, vector, ...)                 \
    const Type* Model::name(std::string_view id) const {             \
        const auto found = by_id_.find(lookup_key(id));              \
        if (found == by_id_.end()) return nullptr;                   \
        const ObjectKind kind = objects_[found->second.object].kind; \
        const ObjectKind kinds[] = {__VA_ARGS__};                    \
        for (ObjectKind k : kinds)                                   \
            if (k == kind) return &vector[found->second.typed];      \
        return nullptr;                                              \
    }

NCLINK_MODEL_LOOKUP(Device, device, devices_, ObjectKind::device)
NCLINK_MODEL_LOOKUP(Component, component, components_, ObjectKind::component)
NCLINK_MODEL_LOOKUP(DataObject, data_object, data_objects_, ObjectKind::data_item, ObjectKind::config_item)
NCLINK_MODEL_LOOKUP(SampleChannel, channel, channels_, ObjectKind::sample_channel)
NCLINK_MODEL_LOOKUP(Method, method, methods_, ObjectKind::method)
#undef NCLINK_MODEL_LOOKUP

const Device* Model::owning_device(std::string_view id) const {
    const ObjectInfo* info = find(id);
    if (info == nullptr) return nullptr;
    if (info->kind == ObjectKind::device) return device(info->id);
    return info->device_id.empty() ? nullptr : device(info->device_id);
}

const std::vector<std::string>& Model::ids_at_path(std::string_view path) const {
    static const std::vector<std::string> kNone;
    const auto found = by_path_.find(std::string(path));
    return found == by_path_.end() ? kNone : found->second;
}

std::vector<const DataObject*> Model::channel_items(std::string_view channel_id) const {
    std::vector<const DataObject*> items;
    const SampleChannel* ch = channel(channel_id);
    if (ch == nullptr) return items;
    items.reserve(ch->ids.size());
    for (const auto& id : ch->ids)
        if (const DataObject* item = data_object(id)) items.push_back(item);
    return items;
}

}  // namespace nclink
