// Shared helpers of the simulator tests: models, a manual clock, reads.
#pragma once

#include <nclink/clock.hpp>
#include <nclink/model.hpp>
#include "sim/sim_driver.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

namespace sim_test {

inline std::shared_ptr<const nclink::Model> load(const std::string& file) {
    auto r = nclink::load_model_file(std::string(NCLINK_MODELS_DIR) + "/" + file);
    REQUIRE(r.ok());
    return r.model;
}

struct Rig {
    std::shared_ptr<nclink::ManualClock> clock = std::make_shared<nclink::ManualClock>();
    std::unique_ptr<nclink::SimDriver> driver;

    explicit Rig(const std::string& model_file, std::uint64_t seed = 1, bool autostart = true) {
        nclink::SimOptions options;
        options.seed = seed;
        options.clock = clock;
        options.autostart = autostart;
        auto created = nclink::SimDriver::create(load(model_file), options);
        REQUIRE(created.ok());
        driver = std::move(created).value();
    }

    void advance_ms(std::int64_t ms) { clock->advance(std::chrono::milliseconds(ms)); }

    std::vector<nclink::Result<nclink::Json>> read(const std::vector<std::string>& ids) {
        std::vector<nclink::PointRef> points;
        for (const auto& id : ids) points.push_back({id, nclink::DataKind::single});
        std::vector<nclink::Result<nclink::Json>> results(
            points.size(), nclink::Result<nclink::Json>(nclink::make_error(nclink::ErrorCode::unavailable)));
        driver->read(points, results);
        return results;
    }

    nclink::Json value(const std::string& id) {
        auto r = read({id});
        INFO(id);
        REQUIRE(r[0].ok());
        return r[0].value();
    }

    nclink::Json all() {
        nclink::Json out = nclink::Json::object();
        const auto ids = driver->item_ids();
        auto results = read(ids);
        for (std::size_t i = 0; i < ids.size(); ++i) {
            INFO(ids[i]);
            REQUIRE(results[i].ok());
            out[ids[i]] = results[i].value();
        }
        return out;
    }

    nclink::Result<void> set(const std::string& id, nclink::Json params) {
        nclink::WriteRequest w;
        w.id = id;
        w.params = std::move(params);
        return driver->write(w);
    }

    nclink::Result<nclink::Json> call(const std::string& method) {
        struct Control final : nclink::MethodControl {
            void progress(double) override {}
            bool cancelled() const override { return false; }
            bool checkpoint() override { return true; }
        } control;
        return driver->run_method(nclink::PointRef{method}, nclink::Json::object(), control);
    }
};

}  // namespace sim_test
