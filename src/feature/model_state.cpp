#include "feature/model_state.hpp"

namespace nclink::detail {

const DataObject* ModelState::item(const std::string& id) const {
    const DataObject* object = model ? model->data_object(id) : nullptr;
    if (!object) return nullptr;
    // Items of another device of the same model file are not ours to serve.
    if (!object->device_id.empty() && device && object->device_id != device->id) return nullptr;
    return object;
}

PointRef ModelState::point(const std::string& id, DataKind kind) const {
    if (const PointRef* ref = bound(id)) return *ref;
    return PointRef{id, kind, no_handle};
}

}  // namespace nclink::detail
