// A Modbus TCP server for the driver's tests: libmodbus' own server side on a
// loopback port, one client at a time, with registers the test sets and
// reads. stop() closes the port (the PLC disappears); start() opens it again
// on the same port (it comes back).
#pragma once

#include <modbus.h>
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace nclink::test {

class TestPlc {
public:
    explicit TestPlc(int port) : port_(port) {
        map_ = modbus_mapping_new(256, 256, 512, 512);
        if (!map_) throw std::runtime_error("modbus_mapping_new failed");
        start();
    }
    ~TestPlc() {
        stop();
        modbus_mapping_free(map_);
    }
    TestPlc(const TestPlc&) = delete;
    TestPlc& operator=(const TestPlc&) = delete;

    void start() {
        if (thread_.joinable()) return;
        ctx_ = modbus_new_tcp("127.0.0.1", port_);
        listen_ = modbus_tcp_listen(ctx_, 1);
        if (listen_ < 0) throw std::runtime_error("test PLC cannot listen");
        running_ = true;
        thread_ = std::thread([this] { serve(); });
    }

    void stop() {
        if (!thread_.joinable()) return;
        running_ = false;
        thread_.join();
        ::close(listen_);
        // Not modbus_close(): the context still names the last client's
        // socket, which serve() closed already (its number may be reused).
        modbus_free(ctx_);
        ctx_ = nullptr;
    }

    void set_holding(int address, std::uint16_t value) {
        std::lock_guard lock(mutex_);
        map_->tab_registers[address] = value;
    }
    std::uint16_t holding(int address) {
        std::lock_guard lock(mutex_);
        return map_->tab_registers[address];
    }
    void set_input(int address, std::uint16_t value) {
        std::lock_guard lock(mutex_);
        map_->tab_input_registers[address] = value;
    }
    void set_coil(int address, bool value) {
        std::lock_guard lock(mutex_);
        map_->tab_bits[address] = value ? 1 : 0;
    }
    bool coil(int address) {
        std::lock_guard lock(mutex_);
        return map_->tab_bits[address] != 0;
    }
    void set_discrete(int address, bool value) {
        std::lock_guard lock(mutex_);
        map_->tab_input_bits[address] = value ? 1 : 0;
    }
    /// Requests answered so far (reads and writes).
    int requests() const { return requests_.load(); }
    int port() const { return port_; }

private:
    void serve() {
        std::uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
        while (running_) {
            pollfd p{listen_, POLLIN, 0};
            if (::poll(&p, 1, 20) <= 0) continue;
            int listen = listen_;
            const int client = modbus_tcp_accept(ctx_, &listen);
            if (client < 0) continue;
            while (running_) {
                pollfd c{client, POLLIN, 0};
                const int ready = ::poll(&c, 1, 20);
                if (ready == 0) continue;
                if (ready < 0) break;
                const int n = modbus_receive(ctx_, query);
                if (n == 0) continue;  // not for this unit
                if (n < 0) break;      // client gone
                std::lock_guard lock(mutex_);
                // Counted before the reply goes out: the driver may look at
                // the count as soon as it has the answer.
                ++requests_;
                modbus_reply(ctx_, query, n, map_);
            }
            ::close(client);
        }
    }

    int port_;
    modbus_t* ctx_ = nullptr;
    modbus_mapping_t* map_ = nullptr;
    int listen_ = -1;
    std::atomic<bool> running_{false};
    std::atomic<int> requests_{0};
    std::mutex mutex_;
    std::thread thread_;
};

}  // namespace nclink::test
