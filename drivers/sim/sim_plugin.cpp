// nclink-sim.so: the simulator as a driver plugin (ABI version 2: handles
// from bind(), typed sample reads and link() cross the boundary). A plugin driver is default
// constructed, so the model and options come from its open() configuration:
//   {"model": "models/sim-mill.json", "seed": 1, "list_size": 64,
//    "device": "mill", "autostart": true, "program_dir": "/var/nc/prog",
//    "transfer_rate": 32768}   (the last two read by SimDriver::open)
#include <nclink/driver_plugin_export.hpp>
#include "sim/sim_driver.hpp"

#include <memory>
#include <string>

namespace {

class SimPluginDriver final : public nclink::Driver {
public:
    nclink::DriverInfo info() const override { return nclink::SimDriver(nullptr).info(); }

    nclink::Result<void> open(const nclink::DriverContext& context) override {
        const nclink::Json& c = context.config;
        if (!c.is_object() || !c.contains("model") || !c["model"].is_string())
            return nclink::make_error(nclink::ErrorCode::parameter_missing,
                                      R"(nclink-sim needs {"model": "<path to a model file>"} as configuration)");
        const std::string path = c["model"].get<std::string>();
        auto loaded = nclink::load_model_file(path);
        if (!loaded.ok()) {
            std::string why = "cannot simulate " + path;
            for (const auto& p : loaded.problems)
                if (p.severity == nclink::Severity::fatal) why += "; " + (p.pointer.empty() ? "/" : p.pointer) + ": " + p.message;
            return nclink::make_error(nclink::ErrorCode::unavailable, why);
        }
        nclink::SimOptions options;
        try {
            options.seed = c.value("seed", options.seed);
            options.list_size = c.value("list_size", options.list_size);
            options.device = c.value("device", options.device);
            options.autostart = c.value("autostart", options.autostart);
        } catch (const nclink::Json::exception& e) {
            return nclink::make_error(nclink::ErrorCode::value_type, std::string("nclink-sim configuration: ") + e.what());
        }
        auto created = nclink::SimDriver::create(loaded.model, std::move(options));
        if (!created.ok()) return std::move(created).error();
        sim_ = std::move(created).value();
        return sim_->open(context);
    }

    void close() override {
        if (sim_) sim_->close();
    }

    nclink::Result<void> bind(const std::vector<nclink::BindPoint>& points, std::vector<nclink::PointHandle>& handles) override {
        return sim_ ? sim_->bind(points, handles) : nclink::ok_result();
    }

    void read(const std::vector<nclink::PointRef>& points, std::vector<nclink::Result<nclink::Json>>& results) override {
        if (sim_) sim_->read(points, results);
    }

    bool read_samples(const std::vector<nclink::PointRef>& points, nclink::SampleValue* out) override {
        return sim_ && sim_->read_samples(points, out);
    }

    bool claims(std::string_view id) const override { return sim_ && sim_->claims(id); }

    nclink::MachineLinkStatus link() const override { return sim_ ? sim_->link() : nclink::MachineLinkStatus{}; }

    nclink::Result<void> write(const nclink::WriteRequest& request) override {
        if (!sim_) return nclink::make_error(nclink::ErrorCode::unavailable, "nclink-sim is not open");
        return sim_->write(request);
    }

    nclink::Result<nclink::Json> run_method(const nclink::PointRef& method, const nclink::Json& args,
                                            nclink::MethodControl& control) override {
        if (!sim_) return nclink::make_error(nclink::ErrorCode::unavailable, "nclink-sim is not open");
        return sim_->run_method(method, args, control);
    }

private:
    std::unique_ptr<nclink::SimDriver> sim_;
};

}  // namespace

NCLINK_EXPORT_DRIVER(SimPluginDriver)
