// An adapter whose driver has methods the test steps by hand, on the
// in-process loopback and a ManualClock, and an application side that talks
// DTUs on topics.
#pragma once

#include "support/adapter_fixture.hpp"

#include <condition_variable>
#include <stdexcept>

namespace nclink::test {

/// quick: returns at once. steps: `count` steps (args), each waiting for a
/// permit from the test, checkpoint() before each. fail: 301. throws: throws.
/// Reads answer pos = 1.5 at once, also while a method waits.
class MethodDriver : public Driver {
public:
    DriverInfo info() const override { return {"method-fake", "1", false}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = Json(1.5);
    }
    Result<Json> run_method(const PointRef& method, const Json& args, MethodControl& control) override {
        const std::string& id = method.id;
        {
            std::lock_guard<std::mutex> lock(mutex);
            calls.push_back({id, args});
        }
        if (id == "quick") {
            control.progress(100);
            return Json{{"ok", true}};
        }
        if (id == "fail") return make_error(ErrorCode::permission_denied, "door open");
        if (id == "throws") throw std::runtime_error("boom");
        if (id == "steps") {
            const int count = args.value("count", 10);
            int step = 0;
            while (step < count) {
                if (!control.checkpoint()) return Json{{"stopped_at", step}};
                std::unique_lock<std::mutex> lock(mutex);
                // Polls cancelled(): a cancel does not wake this condition variable.
                const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
                while (permits == 0 && !control.cancelled()) {
                    if (std::chrono::steady_clock::now() > give_up)
                        return make_error(ErrorCode::timeout, "the test never released the step");
                    wake.wait_for(lock, std::chrono::milliseconds(2));
                }
                if (control.cancelled()) return Json{{"stopped_at", step}};
                --permits;
                ++step;
                control.progress(100.0 * step / count);
            }
            return Json{{"steps", step}};
        }
        return Driver::run_method(method, args, control);
    }
    void release(int n = 1) {
        {
            std::lock_guard<std::mutex> lock(mutex);
            permits += n;
        }
        wake.notify_all();
    }
    std::size_t call_count() {
        std::lock_guard<std::mutex> lock(mutex);
        return calls.size();
    }
    std::vector<std::pair<std::string, Json>> calls_made() {
        std::lock_guard<std::mutex> lock(mutex);
        return calls;
    }

    std::mutex mutex;
    std::condition_variable wake;
    int permits = 0;
    std::vector<std::pair<std::string, Json>> calls;
};

struct MethodsFixture {
    explicit MethodsFixture(AdapterConfig extra = {}) : config(std::move(extra)) {
        config.model_path = std::string(NCLINK_TEST_DATA_DIR) + "/methods-test-model.json";
        config.persistence_dir = scratch_dir("methods");
        config.register_timeout = std::chrono::milliseconds(200);
        config.sampling.enabled = false;  // not under test (its threads wait on the ManualClock)
        driver = std::make_shared<MethodDriver>();
        LoopbackOptions app_options;
        app_options.client_id = "app";
        app = std::make_unique<AppSide>(make_loopback_transport(broker, app_options));
        app->subscribe("#");
        adapter = std::make_unique<Adapter>(config, driver);
        LoopbackOptions o;
        o.client_id = "adapter";
        adapter->use_transport(make_loopback_transport(broker, o));
        adapter->use_clock(clock);
        auto started = adapter->start();
        INFO((started.ok() ? std::string() : started.error().describe()));
        REQUIRE(started.ok());
        REQUIRE(eventually([&] { return adapter->state() == AdapterState::normal; }));
    }
    ~MethodsFixture() {
        driver->release(1000);  // no method left waiting for a permit
        if (adapter) adapter->stop();
        std::error_code ec;
        std::filesystem::remove_all(config.persistence_dir, ec);
    }

    /// Publishes a Method/Call from `ex` (no ex: the short topic); returns its @id.
    std::string call(const std::string& method, const Json& args = nullptr, const std::string& ex = "app") {
        const std::string id = "c" + std::to_string(++counter);
        Json dtu{{"@id", id}, {"guid", "test-dev"}, {"id", method}};
        if (!args.is_null()) dtu["args"] = args;
        app->send(ex.empty() ? topics::method_call("test-dev") : topics::method_call("test-dev", ex), dtu.dump());
        return id;
    }
    Json control(const std::string& method, const std::string& action, const std::string& ex = "app",
                 const Json& private_info = nullptr) {
        Json dtu{{"@id", "k" + std::to_string(++counter)}, {"guid", "test-dev"}, {"id", method}, {"action", action}};
        if (!private_info.is_null()) dtu["privateInfo"] = private_info;
        return app->request(topics::method_control_request("test-dev", ex), topics::method_control_response("test-dev", ex), dtu);
    }
    /// The DTUs on `topic` whose @id is `id`, parsed.
    std::vector<Json> dtus(const std::string& topic, const std::string& id) {
        std::vector<Json> out;
        for (const auto& m : app->on(topic)) {
            Json j = Json::parse(m.payload);
            if (j.value("@id", std::string()) == id) out.push_back(std::move(j));
        }
        return out;
    }
    std::vector<Json> statuses(const std::string& id, const std::string& ex = "app") {
        return dtus(ex.empty() ? topics::method_status("test-dev") : topics::method_status("test-dev", ex), id);
    }
    /// Waits for the Method/Result of call `id`.
    Json result(const std::string& id, const std::string& ex = "app") {
        const std::string topic = ex.empty() ? topics::method_result("test-dev") : topics::method_result("test-dev", ex);
        REQUIRE(eventually([&] { return !dtus(topic, id).empty(); }));
        return dtus(topic, id).front();
    }
    /// Waits until call `id` has published `n` statuses; returns the n-th.
    Json status(const std::string& id, std::size_t n, const std::string& ex = "app") {
        REQUIRE(eventually([&] { return statuses(id, ex).size() >= n; }));
        return statuses(id, ex)[n - 1];
    }
    /// Waits for a status of call `id` saying `phase`.
    Json wait_phase(const std::string& id, const std::string& phase) {
        Json found;
        REQUIRE(eventually([&] {
            for (const auto& s : statuses(id))
                if (s["status"] == phase) found = s;
            return !found.is_null();
        }));
        return found;
    }

    AdapterConfig config;
    LoopbackBroker broker;
    std::shared_ptr<ManualClock> clock = std::make_shared<ManualClock>();
    std::shared_ptr<MethodDriver> driver;
    std::unique_ptr<AppSide> app;
    std::unique_ptr<Adapter> adapter;
    int counter = 0;
};

}  // namespace nclink::test
