// The only writer of a Model: appends objects while the reader walks the
// document, keeps the id/path index, and reports duplicate ids.
#pragma once

#include "model/problems.hpp"

#include <nclink/model.hpp>

#include <memory>

namespace nclink {

class ModelBuilder {
public:
    explicit ModelBuilder(model_detail::Problems& problems) : problems_(problems), model_(std::make_shared<Model>()) {}

    /// Each add_* indexes the object; on a duplicate id it reports a fatal
    /// problem at info.pointer and returns false (the object is not added).
    bool set_root(Root root, ObjectInfo info);
    bool add_device(Device device, ObjectInfo info);
    bool add_component(Component component, ObjectInfo info);
    bool add_data_object(DataObject object, ObjectInfo info);
    bool add_channel(SampleChannel channel, ObjectInfo info);
    bool add_method(Method method, ObjectInfo info);

    /// Children of an already added container (root, device or component).
    Children* children_of(const std::string& id);

    const Model& model() const noexcept { return *model_; }

    /// Hands the model over; the builder is empty afterwards. The object
    /// vectors grew by doubling while the file was read; a model is kept for
    /// as long as its machine is served (a gateway holds thousands), so they
    /// give back what they reserved beyond their size (45 KB of a 300-point
    /// machine's 1.9 MB; docs/performance.md, "Memory per machine").
    std::shared_ptr<const Model> finish();

private:
    bool index(ObjectInfo info, std::size_t typed);

    model_detail::Problems& problems_;
    std::shared_ptr<Model> model_;
};

}  // namespace nclink
