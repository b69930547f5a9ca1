// An MTConnect agent (HTTP) or an SHDR adapter (TCP) served as an NC-Link
// terminal (docs/gateway.md "MTConnect and SHDR sources"). The model the
// adapter serves is generated from the MTConnect probe by
// `nclink map --from-mtconnect` (reverse_mapping.hpp); the driver reads the
// same probe at open() and answers each item of that model from the
// observations it follows.
//
// Configuration (the driver's `config`):
//   {"agent": "http://127.0.0.1:5000", "device": "<uuid|name|id>",
//    "interval_ms": 500, "count": 1000, "timeout_ms": 3000, "retry_ms": 1000}
//   {"shdr": "127.0.0.1:7878", "probe_file": "devices.xml", "device": "...",
//    "timeout_ms": 3000, "retry_ms": 1000, "ping_ms": 10000}
//
// Reads: the last observed value; an item whose value is UNAVAILABLE (or
// not observed yet) answers 202 Unavailable; an item the probe does not
// have (any more) answers 202 too, saying so. Writes: 301 Permission Denied
// (MTConnect is read-only). link(): connected while the source answers and
// the device's AVAILABILITY is not UNAVAILABLE; else disconnected with the
// reason (the SDK then answers 202 "machine disconnected").
//
// Threading: read() and write() on the SDK's driver worker (serialized, but
// safe concurrently too: info().concurrent is true); the source follows the
// agent on a thread of its own, started by open() and joined by close();
// link() and stats() from any thread.
#pragma once

#include "mtconnect/live_values.hpp"
#include "mtconnect/source_status.hpp"

#include <nclink/driver.hpp>

#include <chrono>
#include <memory>
#include <optional>
#include <string>

namespace nclink::mtconnect {

class AgentSource;
class ShdrSource;

struct DriverConfig {
    std::string agent;       ///< "http://host:port[/prefix]" (an agent), or
    std::string shdr;        ///< "host:port" (an SHDR adapter)
    std::string probe_file;  ///< SHDR: the Devices document that describes the adapter's keys
    std::string device;      ///< uuid, name or id of the Device ("" = the first)
    std::chrono::milliseconds interval{500};
    std::chrono::milliseconds retry{1000};
    std::chrono::milliseconds timeout{3000};
    std::chrono::milliseconds ping{10000};
    std::uint32_t count = 1000;
};

/// The driver's configuration from JSON; unknown keys, wrong types, neither
/// or both of agent/shdr are errors (413 for an unknown key, 405 for a type).
Result<DriverConfig> parse_driver_config(const Json& config);

class MtConnectDriver final : public Driver {
public:
    /// `config` null: read from open()'s DriverContext::config (the plugin form).
    explicit MtConnectDriver(std::optional<DriverConfig> config = std::nullopt);
    ~MtConnectDriver() override;

    DriverInfo info() const override;
    Result<void> open(const DriverContext& context) override;
    void close() override;
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override;
    Result<void> write(const WriteRequest& request) override;
    MachineLinkStatus link() const override;

    SourceCounters stats() const { return status_.counters(); }
    /// The mapping in force (after open()), for diagnostics and tests.
    std::shared_ptr<const ReverseModel> mapping() const { return values_.model(); }

private:
    std::optional<DriverConfig> config_;
    Logger logger_;
    LiveValues values_;
    SourceStatus status_;
    std::unique_ptr<AgentSource> agent_;
    std::unique_ptr<ShdrSource> shdr_;
};

}  // namespace nclink::mtconnect
