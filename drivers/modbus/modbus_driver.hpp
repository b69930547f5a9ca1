// A driver for machines and PLCs that speak Modbus TCP (libmodbus): every
// NC-Link data item named in the map (modbus_map.hpp) is read from, and
// written to, its register or coil. docs/drivers/modbus.md.
//
// Threading: serialized (info().concurrent is false): the SDK never calls
// read() and write() at once, which is what one Modbus TCP connection needs.
// link() may be called from any thread (an atomic).
//
// When the PLC is gone (connect refused, timeout, connection reset) every
// item of the failing call answers Unavailable (202) with "DEV_UNREACHABLE"
// in its detail, and reconnects are tried on later calls no more often than
// the backoff allows (doubling from backoff_ms.min to backoff_ms.max). Until
// the next attempt is due link() says disconnected, so the SDK answers the
// items 202 "machine disconnected" without calling the driver at all; once
// it is due link() says unknown again and the next read tries to reconnect.
#pragma once

#include "modbus/modbus_map.hpp"

#include <nclink/driver.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

namespace nclink::modbus {

class Connection;

class ModbusDriver final : public Driver {
public:
    using Clock = std::function<std::chrono::steady_clock::time_point()>;

    /// `config` null: the map comes from open()'s DriverContext::config (the
    /// plugin form). `clock` for tests of the backoff (default steady_clock).
    explicit ModbusDriver(std::optional<Config> config = std::nullopt, Clock clock = {});
    ~ModbusDriver() override;

    DriverInfo info() const override;
    Result<void> open(const DriverContext& context) override;
    void close() override;
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override;
    Result<void> write(const WriteRequest& request) override;
    MachineLinkStatus link() const override;

    /// Counters for tests and `nclink stats`-like diagnostics.
    struct Stats {
        std::uint64_t requests = 0;    ///< Modbus read/write requests sent
        std::uint64_t connects = 0;    ///< successful connects
        std::uint64_t failures = 0;    ///< requests or connects that failed
    };
    Stats stats() const;

private:
    Result<void> ensure_connected();
    void lost(const std::string& why);
    Error unreachable(const std::string& what) const;

    std::optional<Config> config_;
    Clock clock_;
    Logger logger_;
    std::unique_ptr<Connection> connection_;
    std::atomic<MachineLink> link_{MachineLink::unknown};
    std::chrono::steady_clock::time_point next_attempt_{};
    /// next_attempt_ for link() on any thread (steady_clock ticks).
    std::atomic<std::int64_t> next_attempt_ticks_{0};
    std::chrono::milliseconds backoff_{0};
    std::string last_failure_;
    std::atomic<std::uint64_t> requests_{0}, connects_{0}, failures_{0};
};

}  // namespace nclink::modbus
