// Follows an SHDR adapter over TCP (shdr_line.hpp for the line format): the
// keys are described by a Devices document (`probe_file`), whose DataItems
// the reverse mapping turns into the NC-Link model exactly as for an agent.
//
// - "* PING" is sent every `ping`; an adapter that answers "* PONG <ms>"
//   is taken as gone when nothing (no data, no PONG) arrived for twice <ms>;
//   one that never answers is trusted to TCP alone (older adapters).
// - A lost connection (closed, reset, silent past the heartbeat) makes every
//   item UNAVAILABLE (an agent does the same) and link() disconnected; the
//   source connects again every `retry`. An adapter sends its whole state to
//   each new connection.
// - Lines for another device, unknown keys and malformed lines are skipped
//   (counted in the log at debug level), never fatal.
//
// Threading: one thread of its own (start()/stop() from the driver).
#pragma once

#include "mtconnect/live_values.hpp"
#include "mtconnect/source_status.hpp"

#include <nclink/log.hpp>
#include <nclink/result.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace nclink::mtconnect {

struct ShdrOptions {
    std::string address;     ///< "host:port"
    std::string probe_file;  ///< the Devices document describing the keys
    std::string device;      ///< uuid, name or id ("" = the first device)
    std::chrono::milliseconds retry{1000};
    std::chrono::milliseconds timeout{3000};  ///< connect timeout
    std::chrono::milliseconds ping{10000};
};

class ShdrSource {
public:
    ShdrSource(ShdrOptions options, LiveValues& values, SourceStatus& status, Logger logger);
    ~ShdrSource();  ///< stop()s
    ShdrSource(const ShdrSource&) = delete;
    ShdrSource& operator=(const ShdrSource&) = delete;

    /// Reads the probe file (errors: unreadable, not a Devices document) and
    /// starts following the adapter; an adapter not there yet is retried.
    Result<void> start();
    void stop();

    /// One data line applied to the values (exposed for tests); returns the
    /// number of values it set.
    std::size_t apply_line(const std::string& line);

private:
    void run();
    void follow(int fd);
    bool for_this_device(const std::string& device) const;

    ShdrOptions options_;
    std::string host_;
    int port_ = 0;
    LiveValues& values_;
    SourceStatus& status_;
    Logger logger_;
    std::string uuid_, name_, id_;  ///< the Device's, to match key prefixes
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
    int wake_pipe_[2] = {-1, -1};
    std::thread thread_;
};

}  // namespace nclink::mtconnect
