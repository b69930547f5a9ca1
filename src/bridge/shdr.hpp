// SHDR, the line protocol an MTConnect agent reads from its adapters
// (cppagent's "adapter" input), so an existing agent ingests NC-Link machines
// unchanged (docs/bridge.md "SHDR"):
//   2024-01-01T00:00:00.123Z|mill-01:x_position|12.5
//   2024-01-01T00:00:00.123Z|mill-01:system_alarm|fault|1001|||Spindle overload
//   2024-01-01T00:00:00.123Z|mill-01:tools||[{"id":"T1","len":1.5}]
// One line per change; the key is "<Device uuid>:<DataItem id>"; a MESSAGE
// (how list and dict items are mapped) as nativeCode|text; a SAMPLE whose
// nativeUnits an agent converts in those units; a value with '|'
// quoted (shdr_value); UNAVAILABLE
// when the adapter is offline; a full snapshot to every new connection; a
// "* PING" line is answered "* PONG <heartbeat ms>".
//
// The server uses plain sockets (a line protocol needs no HTTP): one accept
// thread and one thread per connection (at most max_connections).
#pragma once

#include "bridge/bridge_store.hpp"

#include <nclink/log.hpp>
#include <nclink/result.hpp>

#include <atomic>
#include <chrono>
#include <list>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace nclink::bridge {

/// A key part (device, DataItem id) as SHDR text: '|' would split the line
/// and line breaks end it, so '|' becomes '/', CR/LF/TAB and other control
/// characters become spaces.
std::string shdr_escape(std::string_view text);

/// A value as an SHDR field. Control characters (a line break would end the
/// line) become spaces. A value with '|', or starting with '"' or a space
/// (which the agent would take for a quote or trim), is sent in the adapter
/// protocol's quoted form, "text with \| and \" and \\", which the agent
/// reads back to the text; any other value goes as it is.
std::string shdr_value(std::string_view text);

/// The device part of a key: the Device uuid (unique; an agent looks it up
/// before the name), or its name when the uuid holds ':', '|' or a space.
std::string shdr_device_key(const MtDevice& device);

/// The SHDR line(s) of one observation (with "\n"); a condition gives one line per active alarm.
std::string shdr_lines(const DeviceEntry& device, const ItemEntry& item, const Observation& observation);

/// The DataItem as its SHDR lines carry it (ItemEntry::shdr_mt): a SAMPLE
/// whose nativeUnits an MTConnect agent converts itself, unconverted;
/// nullopt for every other item, which goes as the mapping describes it.
std::optional<MtDataItem> shdr_native_item(const MtDataItem& item);

/// "* PONG <ms>\n" for a "* PING" line; "" for any other line.
std::string shdr_answer(std::string_view line, std::chrono::milliseconds heartbeat);

class ShdrServer {
public:
    ShdrServer(const BridgeStore& store, std::string host, int port, std::chrono::milliseconds heartbeat, Logger logger,
               std::size_t max_connections = 16);
    ~ShdrServer();  ///< stop()s
    ShdrServer(const ShdrServer&) = delete;
    ShdrServer& operator=(const ShdrServer&) = delete;

    Result<void> start();
    int port() const noexcept { return port_; }
    void stop();

private:
    void accept_loop();
    void serve(int fd);

    const BridgeStore& store_;
    std::string host_;
    int port_;
    std::chrono::milliseconds heartbeat_;
    Logger logger_;
    std::size_t max_connections_;
    int listen_fd_ = -1;
    std::atomic<bool> running_{false};
    std::atomic<std::size_t> connections_{0};
    std::thread acceptor_;
    std::mutex threads_mutex_;
    std::list<std::thread> threads_;
};

}  // namespace nclink::bridge
