#include "adapter/model_host.hpp"
#include "core/atomic_file.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace nclink::adapter_detail {

ModelHost::ModelHost(std::string persistence_dir, Logger logger) : dir_(std::move(persistence_dir)), logger_(std::move(logger)) {}

Result<std::shared_ptr<feature_detail::ModelState>> ModelHost::build(const LoadResult& loaded, const std::string& device_id,
                                                                     const Driver& driver) const {
    if (!loaded.model) return make_error(ErrorCode::syntax_error, "the model has fatal problems");
    auto state = std::make_shared<feature_detail::ModelState>();
    state->model = loaded.model;
    for (const auto& p : loaded.problems)
        if (p.severity != Severity::fatal) state->problems.push_back(p);
    const auto& devices = state->model->devices();
    if (devices.empty()) return make_error(ErrorCode::node_not_exists, "the model has no device");
    state->device = device_id.empty() ? &devices.front() : state->model->device(device_id);
    if (!state->device) return make_error(ErrorCode::node_not_exists, fmt::format("the model has no device '{}'", device_id));

    state->store = std::make_shared<ValueStore>();
    for (const auto& object : state->model->data_objects()) {
        if (!object.device_id.empty() && object.device_id != state->device->id) continue;
        const bool sdk_item = object.value.has_value() || object.config;
        if (!sdk_item || driver.claims(object.id)) continue;
        Json initial = object.value.value_or(Json(nullptr));
        auto added = state->store->add(object.id, object.kind, object.setable, std::move(initial));
        if (!added) {
            // A fixed value that does not fit its datatype (e.g. a string for a
            // list): serve it unknown rather than refuse the whole model.
            logger_.warn("model item {}: fixed value does not fit its datatype ({}); served as unknown", object.id,
                         added.error().message);
            (void)state->store->add(object.id, object.kind, object.setable, Json(nullptr));
        }
    }
    if (!dir_.empty()) {
        std::ifstream in(std::filesystem::path(dir_) / "values.json");
        if (in) {
            std::stringstream text;
            text << in.rdbuf();
            const Json snapshot = Json::parse(text.str(), nullptr, false);
            if (auto restored = state->store->load(snapshot); restored)
                logger_.info("restored {} persisted value(s) from {}/values.json", restored.value(), dir_);
            else logger_.warn("ignoring {}/values.json: {}", dir_, restored.error().describe());
        }
    }

    if (loaded.document) {
        state->probe_text = loaded.document;
    } else {
        // A LoadResult built in code, without a document: the model's own form.
        state->probe_text =
            std::make_shared<const std::string>(model_to_json(*state->model).dump(-1, ' ', false, Json::error_handler_t::replace));
    }
    state->rules = cache_ ? cache_->rules(state->model) : std::make_shared<const ValueRules>(*state->model);
    return state;
}

Result<void> ModelHost::bind(feature_detail::ModelState& state, driver_detail::DriverRunner& runner) {
    std::vector<BindPoint> points;
    const Model& model = *state.model;
    for (const auto& object : model.data_objects()) {
        if (!object.device_id.empty() && object.device_id != state.device->id) continue;
        if (state.sdk_held(object.id)) continue;
        BindPoint p;
        p.id = object.id;
        p.kind = object.kind;
        p.type = object.type;
        p.name = object.name;
        p.units = object.units;
        const ObjectInfo* info = model.find(object.id);
        p.path = info ? info->path : std::string();
        p.setable = object.setable;
        p.config = object.config;
        p.object = &object;
        points.push_back(std::move(p));
    }
    for (const auto& method : model.methods()) {
        const ObjectInfo* info = model.find(method.id);
        if (info && !info->device_id.empty() && info->device_id != state.device->id) continue;
        BindPoint p;
        p.id = method.id;
        p.method = true;
        p.type = "METHOD";
        p.name = method.name;
        p.path = info ? info->path : std::string();
        p.method_object = &method;
        points.push_back(std::move(p));
    }
    auto table = runner.bind(points);
    if (!table) return std::move(table).error();
    state.points = std::move(table).value();
    state.index_items();
    return ok_result();
}

std::shared_ptr<const feature_detail::ModelState> ModelHost::current() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return current_;
}

void ModelHost::install(std::shared_ptr<const feature_detail::ModelState> state) {
    std::lock_guard<std::mutex> lock(mutex_);
    current_ = std::move(state);
}

std::string ModelHost::persisted_model_path() const {
    if (dir_.empty()) return {};
    const auto path = std::filesystem::path(dir_) / "model.json";
    return std::filesystem::exists(path) ? path.string() : std::string();
}

Result<void> ModelHost::persist_model(const std::string& text) const {
    if (dir_.empty()) return ok_result();
    return core_detail::write_file_atomically((std::filesystem::path(dir_) / "model.json").string(), text);
}

Result<void> ModelHost::persist_values(const ValueStore& store) const {
    if (dir_.empty()) return ok_result();
    const auto state = current();
    Json settable = Json::object();
    const Json all = store.snapshot();
    for (auto it = all.begin(); it != all.end(); ++it) {
        const DataObject* object = state ? state->model->data_object(it.key()) : nullptr;
        if (object && object->setable) settable[it.key()] = it.value();
    }
    return core_detail::write_file_atomically((std::filesystem::path(dir_) / "values.json").string(),
                                              settable.dump(2, ' ', false, Json::error_handler_t::replace));
}

}  // namespace nclink::adapter_detail
