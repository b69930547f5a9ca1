// The fake machine the adapter-level tests run against (adapter, agent,
// events, sampling, methods, gateway): values in a map, optionally slow
// reads and writes, a count of writes. Shared, so it lives in tests/support.
#pragma once

#include <nclink/driver.hpp>

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace nclink::test {

/// Machine values in a map; optionally slow; counts writes.
class FakeDriver : public Driver {
public:
    FakeDriver() {
        values["pos"] = 12.5;
        values["status"] = "running";
        values["ovr"] = 100;
        values["tools"] = Json::array(
            {Json{{"id", "T1"}, {"length", 50.0}}, Json{{"id", "T2"}, {"length", 75.5}}, Json{{"id", "T3"}, {"length", 20.0}}});
        values["params"] = Json{{"p1", 1}, {"p2", 2.5}, {"name", "fast"}};
    }
    DriverInfo info() const override { return {"fake", "1", false}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        if (const auto d = delay.load(); d.count() > 0) std::this_thread::sleep_for(d);
        std::lock_guard<std::mutex> lock(mutex);
        for (std::size_t i = 0; i < points.size(); ++i) {
            auto it = values.find(points[i].id);
            if (it == values.end()) results[i] = make_error(ErrorCode::unavailable, "not wired");
            else results[i] = it->second;
        }
    }
    Result<void> write(const WriteRequest& request) override {
        if (const auto d = write_delay.load(); d.count() > 0) std::this_thread::sleep_for(d);
        std::lock_guard<std::mutex> lock(mutex);
        ++writes;
        if (request.new_value.is_null()) return make_error(ErrorCode::unavailable, "no new value");
        values[request.id] = request.new_value;
        return ok_result();
    }
    Json value(const std::string& id) {
        std::lock_guard<std::mutex> lock(mutex);
        return values[id];
    }

    std::mutex mutex;
    std::map<std::string, Json> values;
    std::atomic<std::chrono::milliseconds> delay{std::chrono::milliseconds(0)};  // set by tests while reads run
    std::atomic<std::chrono::milliseconds> write_delay{std::chrono::milliseconds(0)};
    int writes = 0;  // under mutex
    int write_count() {
        std::lock_guard<std::mutex> lock(mutex);
        return writes;
    }
};

}  // namespace nclink::test
