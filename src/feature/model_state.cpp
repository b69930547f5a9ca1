#include "feature/model_state.hpp"

namespace nclink::feature_detail {

const DataObject* ModelState::item(const std::string& id) const {
    const DataObject* object = model ? model->data_object(id) : nullptr;
    if (!object) return nullptr;
    // Items of another device of the same model file are not ours to serve.
    if (!object->device_id.empty() && device && object->device_id != device->id) return nullptr;
    return object;
}

ModelState::ItemEntry ModelState::entry(const std::string& id) const {
    if (!index_.empty()) {
        const auto found = index_.find(id);
        return found == index_.end() ? ItemEntry{} : found->second;
    }
    return ItemEntry{item(id), bound(id), rules ? rules->find(id) : nullptr};
}

void ModelState::index_items() {
    index_.clear();
    if (!model) return;
    for (const auto& object : model->data_objects())
        if (item(object.id) == &object)
            index_.emplace(object.id, ItemEntry{&object, bound(object.id), rules ? rules->find(object.id) : nullptr});
}

PointRef ModelState::point(const std::string& id, DataKind kind) const {
    if (const PointRef* ref = bound(id)) return *ref;
    return PointRef{id, kind, no_handle};
}

}  // namespace nclink::feature_detail
