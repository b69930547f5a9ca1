// Gateway mode: one process serving many machines (docs/gateway.md). Each
// machine is an NC-Link terminal of its own: its own model, driver, terminal
// id (GUID), MQTT connection and therefore its own last will, Notify/State
// and Register/Request. The gateway reads one file listing the machines and
// adds or removes a machine at run time without touching the others.
//
//   nclink::Gateway gateway(nclink::load_gateway_config("gateway.json").value(), make_driver, logger);
//   gateway.start();                       // every machine listed
//   gateway.add_machine(machine);          // one more, the others keep serving
//   gateway.remove_machine("mill-7");      // its offline state goes out
//   gateway.stop();
//
// Threading: every public call is thread-safe; add/remove of different
// machines may run concurrently with each other and with requests being
// served. The driver factory is called on the thread calling start() or
// add_machine().
#pragma once

#include <nclink/adapter.hpp>
#include <nclink/adapter_config.hpp>
#include <nclink/driver.hpp>
#include <nclink/export.hpp>
#include <nclink/json.hpp>
#include <nclink/log.hpp>
#include <nclink/result.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace nclink {

/// One machine of the gateway.
struct NCLINK_API MachineConfig {
    /// "id": the machine's name in the gateway (for add/remove and logs);
    /// default: its "dev_uuid", else the model file's name.
    std::string id;
    /// Everything else of the machine's entry: an adapter configuration
    /// (docs/configuration.md) laid over the gateway's "defaults": "model",
    /// "dev_uuid" (the GUID), "broker" (connection), "driver" {"plugin",
    /// "config"}, sampling, ...
    AdapterConfig adapter;
};

struct NCLINK_API GatewayConfig {
    /// "defaults": adapter keys every machine starts from (broker, sampling,
    /// log level, ...); a machine's own keys win.
    Json defaults = Json::object();
    /// "machines": the machines, in start order.
    std::vector<MachineConfig> machines;
    /// "start_threads": machines started (or stopped) at once; connecting
    /// is what takes time. 0 = 4.
    std::size_t start_threads = 0;
    /// "timer_threads": threads every machine's sampling scheduler, uploader
    /// and housekeeping share (include/nclink/shared_threads.hpp). 0 = the
    /// box's cores (at least 2).
    std::size_t timer_threads = 0;
    /// "request_threads": threads handling every machine's requests. 0 = the
    /// box's cores (at least 2).
    std::size_t request_threads = 0;
    /// "driver_threads": threads calling every machine's driver (one call
    /// at a time per driver unless it is concurrent). 0 = the box's cores
    /// (at least 2).
    std::size_t driver_threads = 0;
    /// "work_threads": threads running every machine's serial background
    /// work: its MQTT publishing (outbox), events engine, method status
    /// ticker and sample spool, each still in order per machine. 0 = the
    /// box's cores (at least 2).
    std::size_t work_threads = 0;
    /// "mqtt_client": "mosquitto" (default): every machine's broker
    /// connection is served by one epoll thread of the gateway over
    /// libmosquitto, so a packet costs the same at 10 or 1,000 machines;
    /// "paho" (the name kept from when single adapters ran on paho): each
    /// machine's connection with an I/O thread of its own, as a single
    /// adapter's. libnclink has no WebSocket client: ws:// and wss://
    /// brokers are refused (docs/building.md).
    std::string mqtt_client = "mosquitto";
    /// "mqtt_connect_max": with mqtt_client "mosquitto", machines that may
    /// wait for the broker's CONNACK at once; the others wait their turn
    /// (their connect timeout not yet running). 0 = no limit.
    std::size_t mqtt_connect_max = 64;
    LogLevel log_level = LogLevel::info;  ///< "log_level"
};

/// Reads a gateway configuration object. Unknown keys are refused (413),
/// wrong types 405, a machine entry as the adapter configuration would;
/// duplicate machine ids or GUIDs 413. Relative paths are taken against
/// `base_dir` ("" = as given).
NCLINK_API Result<GatewayConfig> gateway_config_from_json(const Json& json, const std::string& base_dir = "");
/// Reads a gateway configuration file; relative paths in it are taken
/// against the file's directory.
NCLINK_API Result<GatewayConfig> load_gateway_config(const std::string& path);
/// One machine entry (as in "machines") laid over `defaults`.
NCLINK_API Result<MachineConfig> machine_config_from_json(const Json& entry, const Json& defaults = Json::object(),
                                                          const std::string& base_dir = "");

/// Makes the driver of a machine whose configuration names no driver plugin
/// (a program linking its drivers). Returning null or an error refuses the
/// machine. Called on the thread calling Gateway::start() or add_machine().
using MachineDriverFactory = std::function<Result<std::shared_ptr<Driver>>(const MachineConfig&)>;

struct NCLINK_API MachineInfo {
    std::string id;
    std::string dev_uuid;
    AdapterState state = AdapterState::initial;
    bool registered = false;
};

/// What Gateway::reload() did, by machine id.
struct NCLINK_API GatewayReload {
    std::vector<std::string> added;      ///< newly listed, started
    std::vector<std::string> removed;    ///< no longer listed, stopped
    std::vector<std::string> restarted;  ///< changed in a key only a start applies: stopped and started again
    std::vector<std::string> applied;    ///< changed only in what applies at once (log_level)
    std::vector<std::string> errors;     ///< one line per machine that could not be added or restarted
};

class NCLINK_API Gateway {
public:
    explicit Gateway(GatewayConfig config, MachineDriverFactory drivers = {}, Logger logger = {});
    ~Gateway();  ///< stop()s
    Gateway(const Gateway&) = delete;
    Gateway& operator=(const Gateway&) = delete;

    /// Starts every configured machine (start_threads at a time). A machine
    /// that cannot start (model refused, driver missing) is left out and
    /// named in the error; the others serve. Call once.
    Result<void> start();
    /// Stops every machine (each publishes its offline state). Idempotent.
    void stop(std::chrono::milliseconds flush_timeout = std::chrono::milliseconds(2000));

    /// Starts one more machine. 413 for an id or GUID already served; the
    /// start errors of Adapter::start() otherwise. Thread-safe.
    Result<void> add_machine(MachineConfig machine);
    /// Stops one machine: its offline state goes out and its connection
    /// closes; the others are untouched. 401 for an unknown id. Thread-safe.
    Result<void> remove_machine(const std::string& id, std::chrono::milliseconds flush_timeout = std::chrono::milliseconds(2000));

    /// Serves `next` (a re-read gateway file): machines no longer listed are
    /// removed, new ones added, a changed machine is reloaded when only its
    /// log_level changed and otherwise restarted by itself; unchanged
    /// machines are not touched. A machine that fails to restart stays
    /// stopped and is named in `errors`. Thread-safe; not concurrently with
    /// another reload().
    GatewayReload reload(GatewayConfig next);
    std::vector<MachineInfo> machines() const;
    /// The machine's adapter (for its statistics, push channels, ...), or
    /// null. Shared: it stays valid after a remove, stopped.
    std::shared_ptr<Adapter> machine(const std::string& id) const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace nclink
