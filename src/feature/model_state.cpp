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
    if (!entries_.empty()) {
        const DataObject* object = model->data_object(id);
        return object ? entries_[static_cast<std::size_t>(object - model->data_objects().data())] : ItemEntry{};
    }
    return ItemEntry{item(id), bound(id), rules ? rules->find(id) : nullptr};
}

void ModelState::index_items() {
    entries_.clear();
    if (!model) return;
    entries_.resize(model->data_objects().size());  // ItemEntry{}: not an item of this device
    for (std::size_t i = 0; i < entries_.size(); ++i) {
        const DataObject& object = model->data_objects()[i];
        if (item(object.id) == &object)
            entries_[i] = ItemEntry{&object, bound(object.id), rules ? rules->find(object.id) : nullptr};
    }
}

PointRef ModelState::point(const std::string& id, DataKind kind) const {
    if (const PointRef* ref = bound(id)) return *ref;
    return PointRef{id, kind, no_handle};
}

}  // namespace nclink::feature_detail
