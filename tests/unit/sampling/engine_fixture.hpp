// A SamplingEngine on fake time with a recording driver and sink, for the
// sampling unit tests. Most tests drive the engine by hand
// (run_sampling_once / run_upload_once after advancing the ManualClock);
// threaded tests use a ManualSleeper.
#pragma once

#include "sampling/sampling_engine.hpp"
#include "sampling/sleeper.hpp"
#include "support/wait.hpp"

#include <nclink/dtu.hpp>
#include <nclink/topics.hpp>

#include <catch2/catch.hpp>

#include <map>
#include <mutex>
#include <set>
#include <thread>

namespace nclink::test {

/// Each point reads as a function of how often it was read; ids in `failing` answer 202.
class CountingDriver : public Driver {
public:
    DriverInfo info() const override { return {"counting", "1", false}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        std::lock_guard<std::mutex> lock(mutex);
        ++reads;
        threads.insert(std::this_thread::get_id());
        for (std::size_t i = 0; i < points.size(); ++i) {
            const auto& id = points[i].id;
            if (failing.count(id)) {
                results[i] = make_error(ErrorCode::unavailable, "not now");
            } else if (texts.count(id)) {
                results[i] = Json(texts[id]);
            } else if (doubles.count(id)) {
                results[i] = Json(doubles[id]);
            } else {
                results[i] = Json(static_cast<std::int64_t>(++counters[id]));
            }
        }
    }
    std::mutex mutex;
    std::set<std::string> failing;
    std::map<std::string, std::string> texts;
    std::map<std::string, double> doubles;
    std::map<std::string, std::int64_t> counters;
    std::set<std::thread::id> threads;
    int reads = 0;
};

struct EngineFixture {
    /// `other_driver`: read that driver instead of the CountingDriver.
    /// `model`/`values`: the snapshot whose chapter-7 rules sampled values are checked against.
    explicit EngineFixture(SamplingConfig config = {}, bool manual_sleeper = false, std::shared_ptr<Driver> other_driver = nullptr,
                           std::shared_ptr<const feature_detail::ModelState> model = nullptr,
                           feature_detail::ValueGuard* values = nullptr, double phase = 0) {
        driver = std::make_shared<CountingDriver>();
        runner = std::make_unique<driver_detail::DriverRunner>(other_driver ? other_driver : std::shared_ptr<Driver>(driver),
                                                               driver_detail::DriverRunner::Options{}, Logger{});
        sampling_detail::EngineDeps deps;
        deps.driver = runner.get();
        deps.clock = clock;
        sleeper = std::make_shared<sampling_detail::ManualSleeper>(clock);
        deps.sleeper = sleeper;
        (void)manual_sleeper;
        deps.config = config;
        deps.dev = "dev1";
        deps.sink = [this](Message m) {
            std::lock_guard<std::mutex> lock(mutex);
            sent.push_back(std::move(m));
        };
        deps.tap = &tap;
        if (model) deps.model = [model] { return model; };
        deps.values = values;
        deps.phase = phase;
        engine = std::make_unique<sampling_detail::SamplingEngine>(std::move(deps));
    }
    ~EngineFixture() {
        engine->stop();
        engine.reset();
        runner->stop();
    }

    static sampling_detail::ChannelSpec spec(const std::string& id, std::vector<std::string> ids, double sample_ms,
                                             double upload_ms) {
        sampling_detail::ChannelSpec s;
        s.id = id;
        for (auto& i : ids) s.points.push_back(PointRef{i, DataKind::single});
        s.sample_interval_ms = sample_ms;
        s.upload_interval_ms = upload_ms;
        s.topic = topics::sample("dev1", id);
        return s;
    }

    /// Advances fake time in `step` increments up to `total`, sampling after each.
    void step(std::chrono::nanoseconds step_by, std::chrono::nanoseconds total) {
        for (std::chrono::nanoseconds t{0}; t < total; t += step_by) {
            clock->advance(step_by);
            engine->run_sampling_once();
        }
    }

    std::vector<Json> dtus(const std::string& topic) {
        std::lock_guard<std::mutex> lock(mutex);
        std::vector<Json> out;
        for (const auto& m : sent)
            if (m.topic == topic) out.push_back(Json::parse(m.payload));
        return out;
    }
    /// All rows of `topic`, per column, concatenated over DTUs.
    std::vector<std::vector<Json>> columns(const std::string& topic) {
        std::vector<std::vector<Json>> cols;
        for (const auto& d : dtus(topic)) {
            const auto& data = d.at("data");
            if (cols.empty()) cols.resize(data.size());
            REQUIRE(cols.size() == data.size());
            for (std::size_t c = 0; c < data.size(); ++c)
                for (const auto& v : data[c].at("data")) cols[c].push_back(v);
        }
        return cols;
    }
    ChannelStats stats(const std::string& id) {
        for (auto& s : engine->stats())
            if (s.id == id) return s;
        FAIL("no stats for " << id);
        return {};
    }

    std::shared_ptr<ManualClock> clock = std::make_shared<ManualClock>(1'700'000'000'000);
    std::shared_ptr<sampling_detail::ManualSleeper> sleeper;
    std::shared_ptr<CountingDriver> driver;
    std::unique_ptr<driver_detail::DriverRunner> runner;
    feature_detail::SampleTap tap;
    std::mutex mutex;
    std::vector<Message> sent;
    std::unique_ptr<sampling_detail::SamplingEngine> engine;
};

}  // namespace nclink::test
