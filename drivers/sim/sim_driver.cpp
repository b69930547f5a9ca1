// SimDriver: the generic per-type simulation for every data object, with the
// mill profile layered on top when the model is sim-mill.json. Time advances
// lazily to clock->now() on each call, under one mutex. What a Set does to
// the simulation is in sim_commit.cpp.
#include "sim/sim_driver.hpp"
#include "sim_driver_impl.hpp"

#include "mill_kinematics.hpp"
#include "mill_profile.hpp"
#include "program_transfer.hpp"
#include "sim_random.hpp"
#include "value_generators.hpp"

#include <nclink/values.hpp>
#include <nclink/version.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <utility>

namespace nclink {

namespace {

using sim::MillMethod;
using sim::MillRole;
using sim_detail::as_count;
using Item = sim_detail::Item;

std::string parent_type(const Model& model, const std::string& id) {
    const ObjectInfo* info = model.find(id);
    if (!info) return {};
    if (const Component* c = model.component(info->parent_id)) return sim::canonical_type(c->type);
    if (const Device* d = model.device(info->parent_id)) return sim::canonical_type(d->type);
    return {};
}

/// True when an ancestor component is an AXIS numbered A, B or C (table 9:
/// rotary axes, A1..Cn included).
bool under_rotary_axis(const Model& model, const std::string& id) {
    const ObjectInfo* info = model.find(id);
    for (int depth = 0; info && depth < 64; ++depth) {
        if (const Component* c = model.component(info->parent_id)) {
            if (sim::canonical_type(c->type) == "AXIS" && !c->number.empty()) {
                const char axis = static_cast<char>(std::toupper(static_cast<unsigned char>(c->number[0])));
                return axis == 'A' || axis == 'B' || axis == 'C';
            }
        }
        info = model.find(info->parent_id);
    }
    return false;
}

}  // namespace

sim::ItemTraits SimDriver::Impl::traits_of(const DataObject& object) const {
    sim::ItemTraits traits;
    traits.id = object.id;
    traits.name = object.name;
    traits.canonical = sim::canonical_type(object.type);
    traits.parent_type = parent_type(*model, object.id);
    traits.kind = object.kind;
    traits.rotary = under_rotary_axis(*model, object.id);
    return traits;
}

void SimDriver::Impl::build() {
    if (!options.clock) options.clock = std::make_shared<SystemClock>();
    if (!model) {
        broken = make_error(ErrorCode::unavailable, "simulator has no model");
        return;
    }
    if (model->devices().empty()) {
        broken = make_error(ErrorCode::unavailable, "model has no device");
        return;
    }
    device = options.device.empty() ? &model->devices().front() : model->device(options.device);
    if (!device) {
        broken = make_error(ErrorCode::node_not_exists, "model has no device '" + options.device + "'");
        return;
    }
    start = last = options.clock->now();
    wall_ms = options.clock->wall_ms();
    stream = sim::mix64(options.seed ^ 0x6d696c6cULL);
    profile = sim::recognise_mill(*model, *device);
    if (profile) {
        auto program = sim::parse_program(sim::builtin_program());
        if (!program.ok()) {  // the built-in program is ours: a failure is a bug, keep it visible
            broken = program.error();
            return;
        }
        mill = std::make_unique<sim::MillMachine>(std::move(program).value(), profile->config, options.autostart);
    }
    // One Item per data object of the device, sized once: in a gateway of a
    // thousand machines every byte of an Item counts a few hundred thousand
    // times (docs/performance.md, "Memory per machine").
    std::size_t count = 0;
    for (const DataObject& object : model->data_objects()) count += object.device_id == device->id ? 1 : 0;
    items.reserve(count);
    row_by_object.assign(model->data_objects().size(), no_row);
    for (const DataObject& object : model->data_objects()) {
        if (object.device_id != device->id) continue;
        const sim::ItemTraits traits = traits_of(object);
        Item item;
        item.object = &object;
        if (profile) {
            auto role = profile->items.find(object.id);
            if (role != profile->items.end()) item.role = role->second;
        }
        // An item whose value lives in `stored` never reads its generator
        // (value_of(), commit()): it gets none. A generated list or dict
        // (tool table, parameters) is not kept until a Set changes it: it is
        // a function of the seed, built again for each read, as a driver
        // reads a controller's table from the controller; a gateway machine
        // kept about 100 KB of tables it was seldom asked for.
        if (object.value) {
            item.use_stored = true;
            item.stored = *object.value;
        } else if (object.kind != DataKind::single && !item.role && traits.canonical != "WARNING") {
            item.use_stored = true;
            item.generated = true;
        } else {
            item.alarm = traits.canonical == "WARNING";
            item.generator = sim::make_generator(traits, options.seed, options.list_size);
        }
        row_by_object[static_cast<std::size_t>(&object - model->data_objects().data())] = static_cast<std::uint32_t>(items.size());
        items.push_back(std::move(item));
    }
}

std::optional<std::size_t> SimDriver::Impl::row_of_id(std::string_view id) const {
    const DataObject* object = model ? model->data_object(id) : nullptr;
    if (!object || row_by_object.empty()) return std::nullopt;
    const std::uint32_t row = row_by_object[static_cast<std::size_t>(object - model->data_objects().data())];
    if (row == no_row) return std::nullopt;
    return row;
}

void SimDriver::Impl::advance() {
    const auto now = options.clock->now();
    if (now > last) {
        const double dt = std::chrono::duration<double>(now - last).count();
        if (mill) mill->advance(dt);
        last = now;
        t = std::chrono::duration<double>(now - start).count();
    }
    wall_ms = options.clock->wall_ms();
}

Json SimDriver::Impl::alarm_value(const Item& item) const {
    std::vector<Json> active = alarms;
    if (active.empty() && !mill) {
        // Generic models show an alarm now and then, unless it was cleared.
        Json spontaneous = sim::generate(item.generator, t, wall_ms);
        const auto slot = static_cast<std::int64_t>(std::floor(t / item.generator.period));
        if (!spontaneous.empty() && slot != suppressed_slot) active.push_back(std::move(spontaneous));
    }
    if (item.object->kind == DataKind::list) return Json(active);
    if (item.object->kind == DataKind::dict) {
        Json out = Json::object();
        for (const Json& a : active) out[a.value("number", std::string("0"))] = a;
        return out;
    }
    return active.empty() ? Json::object() : active.back();
}

Json SimDriver::Impl::value_of(const Item& item) const {
    if (item.pinned) return *item.pinned;
    if (item.generated) return sim::make_collection(traits_of(*item.object), options.seed, options.list_size);
    if (item.use_stored) return item.stored;
    if (item.alarm) return alarm_value(item);
    if (item.role) {
        if (*item.role == MillRole::emergency_stop) return emergency;
        return sim::mill_reading(*item.role, *mill, t, stream);
    }
    return sim::generate(item.generator, t, wall_ms);
}

std::optional<SampleValue> SimDriver::Impl::sample_of(const Item& item, std::string& text) const {
    if (item.pinned || item.use_stored || item.alarm || !item.role || *item.role == MillRole::emergency_stop) return std::nullopt;
    return sim::mill_sample(*item.role, *mill, t, stream, text);
}

void SimDriver::Impl::add_alarm(const std::string& number, const std::string& text) {
    alarms.erase(
        std::remove_if(alarms.begin(), alarms.end(), [&](const Json& a) { return a.value("number", std::string()) == number; }),
        alarms.end());
    alarms.push_back(sim::warning_object(number, text, wall_ms));
    if (mill) mill->feed_hold();  // an alarm stops the feed, as on a real control
}

void SimDriver::Impl::suppress_spontaneous() {
    // The generic alarm of the current slot stays cleared (every WARNING item
    // shares the slot length).
    for (const Item& item : items)
        if (item.alarm) suppressed_slot = static_cast<std::int64_t>(std::floor(t / item.generator.period));
}

void SimDriver::Impl::release_mill_pins() {
    for (Item& item : items)
        if (item.role) item.pinned.reset();
}

SimDriver::SimDriver(std::shared_ptr<const Model> model, SimOptions options) : impl_(std::make_unique<Impl>()) {
    impl_->model = std::move(model);
    impl_->options = std::move(options);
    impl_->build();
}

SimDriver::~SimDriver() = default;

Result<std::unique_ptr<SimDriver>> SimDriver::create(std::shared_ptr<const Model> model, SimOptions options) {
    auto driver = std::make_unique<SimDriver>(std::move(model), std::move(options));
    if (driver->impl_->broken) return *driver->impl_->broken;
    return driver;
}

DriverInfo SimDriver::info() const {
    DriverInfo i;
    i.name = "nclink-sim";
    i.version = std::to_string(NCLINK_VERSION_MAJOR) + "." + std::to_string(NCLINK_VERSION_MINOR) + "." +
                std::to_string(NCLINK_VERSION_PATCH);
    i.concurrent = false;
    return i;
}

Result<void> SimDriver::open(const DriverContext& context) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (impl_->broken) return *impl_->broken;
    if (context.config.is_object()) {
        const Json& c = context.config;
        if (auto dir = c.find("program_dir"); dir != c.end() && !dir->is_null()) {
            if (!dir->is_string()) return make_error(ErrorCode::value_type, "nclink-sim: program_dir must be a string");
            impl_->options.program_dir = dir->get<std::string>();
        }
        if (auto rate = c.find("transfer_rate"); rate != c.end() && !rate->is_null()) {
            if (!rate->is_number_unsigned() && !(rate->is_number_integer() && rate->get<std::int64_t>() >= 0))
                return make_error(ErrorCode::value_type, "nclink-sim: transfer_rate must be a non-negative integer");
            impl_->options.transfer_rate = rate->get<std::uint64_t>();
        }
    }
    context.logger.info("nclink-sim: simulating device '{}' ({}) with {} data objects, seed {}", impl_->device->id,
                        impl_->mill ? "mill" : "generic", impl_->items.size(), impl_->options.seed);
    return ok_result();
}

// Handles (driver.hpp, "Handles"): a data item's handle is its row in
// impl_->items; a method's is method_handle_base plus its MillMethod. Ids
// are looked up in bind() only; a point without a handle (a driver called
// directly, before any bind) falls back to its id (row_of_id()).
namespace {
constexpr PointHandle method_handle_base = PointHandle{1} << 32;
}  // namespace

Result<void> SimDriver::bind(const std::vector<BindPoint>& points, std::vector<PointHandle>& handles) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    for (std::size_t i = 0; i < points.size() && i < handles.size(); ++i) {
        if (points[i].method) {
            if (!impl_->profile) continue;
            const auto m = impl_->profile->methods.find(points[i].id);
            if (m != impl_->profile->methods.end()) handles[i] = method_handle_base + static_cast<PointHandle>(m->second);
            continue;
        }
        // Not simulated: left by id, so the read answers 401 as before.
        if (const auto row = impl_->row_of_id(points[i].id)) handles[i] = *row;
    }
    return ok_result();
}

// The row in impl_->items of `point`, if simulated. Call with the mutex held.
std::optional<std::size_t> SimDriver::Impl::row_of(const PointRef& point) const {
    if (point.handle < items.size()) return static_cast<std::size_t>(point.handle);
    if (point.handle != no_handle) return std::nullopt;
    return row_of_id(point.id);
}

void SimDriver::read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    results.resize(points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
    if (impl_->broken) {
        for (auto& r : results) r = *impl_->broken;
        return;
    }
    impl_->advance();
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::optional<std::size_t> row = impl_->row_of(points[i]);
        if (!row) {
            results[i] = make_error(ErrorCode::node_not_exists, "no simulated data object '" + points[i].id + "'");
            continue;
        }
        results[i] = impl_->value_of(impl_->items[*row]);
    }
}

bool SimDriver::read_samples(const std::vector<PointRef>& points, SampleValue* out) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (impl_->broken) return true;  // the row stays null
    impl_->advance();
    // A text per point, overwritten by the next read (the sampler copies
    // the row first): its room is reused, so the mill's texts (status,
    // program, ...) cost no allocation per row.
    auto& texts = impl_->lent_texts;
    if (texts.size() < points.size()) texts.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::optional<std::size_t> row = impl_->row_of(points[i]);
        if (!row) continue;  // null: not a simulated item
        const Item& item = impl_->items[*row];
        if (auto sample = impl_->sample_of(item, texts[i])) {
            out[i] = *sample;
            continue;
        }
        const Json value = impl_->value_of(item);
        switch (value.type()) {
            case Json::value_t::boolean: out[i] = SampleValue::boolean(value.get<bool>()); break;
            case Json::value_t::number_integer: out[i] = SampleValue::int64(value.get<std::int64_t>()); break;
            case Json::value_t::number_unsigned: out[i] = SampleValue::uint64(value.get<std::uint64_t>()); break;
            case Json::value_t::number_float: out[i] = SampleValue::float64(value.get<double>()); break;
            case Json::value_t::string:
                texts[i] = value.get_ref<const std::string&>();
                out[i] = SampleValue::text(texts[i]);
                break;
            case Json::value_t::array:
            case Json::value_t::object:
                texts[i] = value.dump();
                out[i] = SampleValue::json(texts[i]);
                break;
            default: break;  // null stays null
        }
    }
    return true;
}

Result<void> SimDriver::write(const WriteRequest& request) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (impl_->broken) return *impl_->broken;
    impl_->advance();
    const std::optional<std::size_t> row = impl_->row_of(PointRef{request.id, request.kind, request.handle});
    if (!row) return make_error(ErrorCode::node_not_exists, "no simulated data object '" + request.id + "'");
    Item& item = impl_->items[*row];
    // A driver-level caller may give only the whole new value.
    Json params = request.params;
    if ((params.is_null() || (params.is_object() && params.empty())) && !request.new_value.is_null())
        params = Json{{"value", request.new_value}};
    auto parsed = parse_set(params, item.object->kind);
    if (!parsed.ok()) return std::move(parsed).error();
    Json value = impl_->value_of(item);
    auto applied = apply(parsed.value(), value, item.object->kind, true);
    if (!applied.ok()) return applied;
    return impl_->commit(item, std::move(value));
}

Result<Json> SimDriver::run_method(const PointRef& point, const Json& args, MethodControl& control) {
    const std::string& method_id = point.id;
    std::unique_lock<std::mutex> lock(impl_->mutex);
    if (impl_->broken) return *impl_->broken;
    std::optional<MillMethod> method;
    if (point.handle >= method_handle_base &&
        point.handle <= method_handle_base + static_cast<PointHandle>(MillMethod::program_transfer) && impl_->profile) {
        method = static_cast<MillMethod>(point.handle - method_handle_base);
    } else {
        if (!impl_->model->method(method_id))
            return make_error(ErrorCode::node_not_exists, "model has no method '" + method_id + "'");
        if (impl_->profile) {
            auto m = impl_->profile->methods.find(method_id);
            if (m != impl_->profile->methods.end()) method = m->second;
        }
    }
    if (!method) return make_error(ErrorCode::unavailable, "the simulator does not implement method '" + method_id + "'");
    impl_->advance();
    sim::MillMachine& mill = *impl_->mill;
    switch (*method) {
        case MillMethod::cycle_start: {
            if (impl_->emergency) return make_error(ErrorCode::permission_denied, "emergency stop is active");
            auto r = mill.cycle_start();
            if (!r.ok()) return std::move(r).error();
            break;
        }
        case MillMethod::feed_hold: mill.feed_hold(); break;
        case MillMethod::reset:
            mill.reset();
            impl_->alarms.clear();
            impl_->release_mill_pins();
            break;
        case MillMethod::program_transfer: {
            // Copies without the mutex: reads and sampling go on meanwhile.
            sim::TransferSettings settings;
            settings.program_dir = impl_->options.program_dir;
            settings.bytes_per_second = impl_->options.transfer_rate;
            settings.clock = impl_->options.clock;
            lock.unlock();
            return sim::transfer_program(settings, args, control);
        }
    }
    control.progress(100);
    return Json{{"status", sim::to_string(mill.status())}};
}

// The simulated machine has the configuration it simulates (tool table,
// parameters, coordinate systems...): it claims config objects that the model
// gives no fixed value, so the SDK does not answer them as unknown. Fixed
// values stay the SDK's.
bool SimDriver::claims(std::string_view id) const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (!impl_->model) return false;
    const DataObject* object = impl_->model->data_object(id);
    return object && object->config && !object->value.has_value() && impl_->row_of_id(id).has_value();
}

MachineLinkStatus SimDriver::link() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (impl_->broken) return {MachineLink::disconnected, impl_->broken->message};
    return {MachineLink::connected, {}};
}

bool SimDriver::is_mill() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->mill != nullptr;
}

std::vector<std::string> SimDriver::item_ids() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    std::vector<std::string> ids;
    ids.reserve(impl_->items.size());
    for (const Item& item : impl_->items) ids.push_back(item.object->id);
    return ids;
}

void SimDriver::raise_alarm(const std::string& number, const std::string& text) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (impl_->broken) return;
    impl_->advance();
    impl_->add_alarm(number, text);
}

void SimDriver::clear_alarm(std::string_view number) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (impl_->broken) return;
    impl_->advance();
    if (number.empty()) {
        impl_->alarms.clear();
    } else {
        auto& alarms = impl_->alarms;
        alarms.erase(std::remove_if(alarms.begin(), alarms.end(),
                                    [&](const Json& a) { return a.value("number", std::string()) == number; }),
                     alarms.end());
    }
    impl_->suppress_spontaneous();
}

}  // namespace nclink
