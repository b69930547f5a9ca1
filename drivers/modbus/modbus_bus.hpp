// A Modbus RTU serial line shared by every machine whose map names its
// device (docs/drivers/modbus.md, "Modbus RTU"). A serial line is one
// conversation at a time (Modbus over Serial Line 2.1: one master, which
// asks one slave and waits for its answer before the next request), and a
// device can be opened once, so the machines on one line share one
// libmodbus RTU context and take turns.
//
// Threading: the bus has no thread of its own. Each transaction runs on the
// thread of the driver call that needs it (an SDK driver worker or the
// sampling thread of that machine), holding the bus's turn for the one
// request and its answer. Turns are given in the order they were asked for
// (a ticket queue, not a bare mutex), so a machine waits at most for the
// transactions queued before its own: a slave that does not answer holds
// the line for its response timeout once, never for longer.
#pragma once

#include "modbus/modbus_map.hpp"

#include <nclink/result.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

typedef struct _modbus modbus_t;

namespace nclink::modbus {

/// What one slave's transaction asks of the line.
struct SlaveSettings {
    int slave = 1;
    std::chrono::milliseconds response_timeout{500};
    std::chrono::milliseconds byte_timeout{100};
};

/// How a transaction ended, for the caller's error code.
enum class Outcome {
    ok,         ///< answered
    exception,  ///< the slave answered with a Modbus exception (illegal address, ...)
    no_answer,  ///< no (complete) answer within the timeouts: the slave is silent
    bad_frame,  ///< an answer arrived damaged (CRC, wrong slave or function, wrong length)
    line_down,  ///< the device cannot be opened, or failed (unplugged): the bus closed it
};

class Bus {
public:
    explicit Bus(SerialLine line);
    ~Bus();
    Bus(const Bus&) = delete;
    Bus& operator=(const Bus&) = delete;

    const SerialLine& line() const { return line_; }

    struct Reply {
        Outcome outcome = Outcome::ok;
        int value = 0;       ///< `request`'s return value when ok
        std::string detail;  ///< libmodbus's words for a failure
    };
    /// Runs one request on the line, in turn: opens the device if it is not
    /// open, sets the slave address and timeouts, waits for the silence
    /// between frames, runs `request` (a libmodbus call returning -1 with
    /// errno on failure), and after a failure discards what is left on the
    /// line so the next transaction starts clean.
    Reply transact(const SlaveSettings& slave, const std::function<int(modbus_t*)>& request);
    /// Opens the device now if it is not open (in turn): ok, or line_down
    /// with the reason. Lets a driver report a missing device at start.
    Reply open();

    struct Stats {
        std::uint64_t transactions = 0;  ///< requests sent on the line
        std::uint64_t opens = 0;         ///< times the device was opened
        std::uint64_t waits = 0;         ///< turns that had to wait for another
    };
    Stats stats() const;

private:
    void take_turn();
    void end_turn();
    bool open_device(std::string& why);
    void close_device();

    SerialLine line_;
    std::chrono::microseconds gap_;
    // The ticket queue: turns are served in ticket order.
    mutable std::mutex queue_mutex_;
    std::condition_variable queue_cv_;
    std::uint64_t next_ticket_ = 0;
    std::uint64_t serving_ = 0;
    Stats stats_;
    // Held only by the thread whose turn it is.
    modbus_t* ctx_ = nullptr;
    std::chrono::steady_clock::time_point quiet_since_{};
};

/// The buses of one process (or of one plugin): a device named by several
/// maps is one Bus. Thread-safe. A bus lives while a driver holds it.
class BusRegistry {
public:
    /// The bus of `line.device` (its resolved path, so a symlink and its
    /// target are one line), created on first use. A machine whose line
    /// settings differ from those the bus was opened with is refused: one
    /// wire cannot run at two speeds.
    Result<std::shared_ptr<Bus>> attach(const SerialLine& line);

private:
    std::mutex mutex_;
    std::map<std::string, std::weak_ptr<Bus>> buses_;
};

}  // namespace nclink::modbus
