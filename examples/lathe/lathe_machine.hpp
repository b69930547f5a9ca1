// The machine behind the lathe example: a 2-axis lathe simulated in memory,
// standing in for the vendor's controller API (what a real port calls
// instead: a fieldbus, shared memory, the CNC's own library). Not part of
// what a vendor writes for nclink; lathe_driver.hpp is.
#pragma once

#include <atomic>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>

namespace acme {

class LatheMachine {
public:
    ~LatheMachine() { stop(); }

    // The controller API the driver reads (any thread).
    double x() const { return x_.load(); }
    double z() const { return z_.load(); }
    double spindle_speed() const { return running_.load() ? 1800.0 * spindle_override_.load() / 100.0 : 0.0; }
    int spindle_override() const { return spindle_override_.load(); }
    void set_spindle_override(int percent) { spindle_override_ = percent; }
    int feed_override() const { return feed_override_.load(); }
    void set_feed_override(int percent) { feed_override_ = percent; }
    bool running() const { return running_.load(); }
    long parts() const { return parts_.load(); }
    int line() const { return line_.load(); }

    /// Turns a part every few seconds: X plunges and returns while Z feeds.
    void start() {
        if (thread_.joinable()) return;
        running_ = true;
        thread_ = std::thread([this] {
            const auto begin = std::chrono::steady_clock::now();
            while (running_.load()) {
                const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
                const double phase = std::fmod(t, 4.0) / 4.0;
                x_ = 40.0 - 15.0 * std::sin(phase * 3.14159265);
                z_ = -120.0 * phase;
                line_ = 10 + static_cast<int>(phase * 20) * 10;
                if (phase < last_phase_) ++parts_;
                last_phase_ = phase;
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            }
        });
    }
    void stop() {
        running_ = false;
        if (thread_.joinable()) thread_.join();
    }

private:
    std::atomic<double> x_{40.0}, z_{0.0};
    std::atomic<int> spindle_override_{100}, feed_override_{100}, line_{0};
    std::atomic<long> parts_{0};
    std::atomic<bool> running_{false};
    double last_phase_ = 0;
    std::thread thread_;
};

}  // namespace acme
