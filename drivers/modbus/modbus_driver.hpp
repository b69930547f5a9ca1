// A driver for machines and PLCs that speak Modbus TCP or Modbus RTU on a
// serial line (libmodbus): every NC-Link data item named in the map
// (modbus_map.hpp) is read from, and written to, its register or coil.
// docs/drivers/modbus.md.
//
// Threading: serialized (info().concurrent is false): the SDK never calls
// read() and write() at once, which is what one Modbus TCP connection needs.
// link() may be called from any thread (an atomic). On RTU several drivers
// (machines) may share one serial line (modbus_bus.hpp): each request runs on
// the calling driver's thread while it holds the line's turn, so the
// machines' requests never interleave on the wire.
//
// When the PLC is gone (connect refused, timeout, connection reset) every
// item of the failing call answers Unavailable (202) with "DEV_UNREACHABLE"
// in its detail, and reconnects are tried on later calls no more often than
// the backoff allows (doubling from backoff_ms.min to backoff_ms.max). Until
// the next attempt is due link() says disconnected, so the SDK answers the
// items 202 "machine disconnected" without calling the driver at all; once
// it is due link() says unknown again and the next read tries to reconnect.
// On RTU a slave that does not answer within timeout_ms answers Timeout (203)
// for the items of that call, then backs off the same way (so a silent slave
// takes the shared line for one timeout per backoff, not one per read); a
// damaged answer (bad CRC) answers 202 for that request only; a device that
// cannot be opened or fails answers 202 DEV_UNREACHABLE like a lost PLC.
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

class Bus;
class BusRegistry;
class Connection;

class ModbusDriver : public Driver {
public:
    using Clock = std::function<std::chrono::steady_clock::time_point()>;

    /// `config` null: the map comes from open()'s DriverContext::config (the
    /// plugin form). `clock` for tests of the backoff (default steady_clock).
    /// `buses`: where RTU drivers find the serial line they share; drivers
    /// given the same registry share a device their maps both name. Null: a
    /// registry of this driver's own (it shares its line with no one).
    explicit ModbusDriver(std::optional<Config> config = std::nullopt, Clock clock = {},
                          std::shared_ptr<BusRegistry> buses = nullptr);
    ~ModbusDriver() override;

    DriverInfo info() const override;
    Result<void> open(const DriverContext& context) override;
    void close() override;
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override;
    Result<void> write(const WriteRequest& request) override;
    MachineLinkStatus link() const override;

    /// Counters for tests and `nclink stats`-like diagnostics.
    struct Stats {
        std::uint64_t requests = 0;  ///< Modbus read/write requests sent
        std::uint64_t connects = 0;  ///< successful connects
        std::uint64_t failures = 0;  ///< requests or connects that failed
    };
    Stats stats() const;

    /// The serial line an RTU driver uses (null for TCP, or before open()).
    std::shared_ptr<Bus> bus() const { return bus_; }

private:
    Result<void> ensure_connected();
    void lost(const std::string& why);
    void answered();
    Error unreachable(const std::string& what) const;
    Error no_answer() const;

    std::optional<Config> config_;
    Clock clock_;
    std::shared_ptr<BusRegistry> buses_;
    std::shared_ptr<Bus> bus_;
    std::atomic<bool> rtu_{false};
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
