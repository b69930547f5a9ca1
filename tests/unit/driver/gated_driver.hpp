// A driver whose read() and write() block until the test opens its gate,
// counting the calls inside it at once: for the DriverRunner tests (own
// workers and pool).
#pragma once

#include <nclink/driver.hpp>

#include <atomic>
#include <condition_variable>
#include <mutex>

namespace nclink::test {

class GatedDriver : public Driver {
public:
    explicit GatedDriver(bool concurrent, bool open = false) : concurrent_(concurrent), open_(open) {}
    DriverInfo info() const override { return {"gated", "1", concurrent_}; }

    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        const int now = ++inside;
        int seen = max_inside.load();
        while (now > seen && !max_inside.compare_exchange_weak(seen, now)) {
        }
        {
            std::unique_lock<std::mutex> lock(mutex_);
            gate_.wait(lock, [&] { return open_; });
        }
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = Json(points[i].id);
        --inside;
        ++reads;
    }
    Result<void> write(const WriteRequest&) override {
        ++inside;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            gate_.wait(lock, [&] { return open_; });
        }
        --inside;
        ++writes;
        return {};
    }
    void close() override { closed = true; }

    void release() {
        std::lock_guard<std::mutex> lock(mutex_);
        open_ = true;
        gate_.notify_all();
    }

    std::atomic<int> inside{0}, max_inside{0}, reads{0}, writes{0};
    std::atomic<bool> closed{false};

private:
    bool concurrent_;
    std::mutex mutex_;
    std::condition_variable gate_;
    bool open_;
};

}  // namespace nclink::test
