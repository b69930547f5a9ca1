// The Modbus map of the Modbus driver (docs/drivers/modbus.md): which
// register or coil holds which NC-Link data item, how its raw words become
// the item's value (type, word order, scale, offset, enumeration), and how the
// reads of one call are batched. Pure: no I/O, so every rule is unit tested.
#pragma once

#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace nclink::modbus {

/// The four Modbus data tables. Coils and holding registers are writable.
enum class Table { coil, discrete_input, holding_register, input_register };

/// How the words of a register value are read.
enum class RegType { boolean, int16, uint16, int32, uint32, int64, float32, float64 };

/// Which word comes first in a value of two or four registers. "big": the
/// first register holds the most significant word (Modbus' own order for
/// bytes, used by most PLCs); "little": the least significant word first.
enum class WordOrder { big, little };

struct Point {
    std::string id;  ///< the NC-Link data item id
    Table table = Table::holding_register;
    std::uint16_t address = 0;  ///< 0-based (the protocol address, not 4xxxx)
    RegType type = RegType::uint16;
    WordOrder word_order = WordOrder::big;
    double scale = 1.0;  ///< value = raw * scale + offset
    double offset = 0.0;
    /// raw value -> NC-Link word (a STATUS item, "free"/"running"/...).
    std::map<std::int64_t, std::string> enumeration;
    /// "text": true: the number goes out as its decimal text, for items
    /// chapter 7 gives string values (PART_COUNT, LINE_NUMBER: table 13).
    bool as_text = false;
    bool writable() const { return table == Table::coil || table == Table::holding_register; }
    /// Registers (or bits) the point spans.
    unsigned width() const;
};

/// A Modbus RTU serial line (Modbus over Serial Line V1.02; libmodbus's RTU
/// backend). Every machine naming the same device shares the line, so these
/// settings must agree between them (modbus_bus.hpp).
struct SerialLine {
    std::string device;  ///< "/dev/ttyUSB0", "/dev/serial/by-id/..."
    int baud = 19200;    ///< 2.5.1: 19200 is the required default rate
    char parity = 'E';   ///< 'N', 'E' or 'O'; 2.5.1: even is the default
    int data_bits = 8;   ///< 5..8 (RTU frames carry 8)
    int stop_bits = 1;   ///< 1 or 2
    /// Silence kept on the line between the end of one transaction and the
    /// next request (2.5.1.1: at least 3.5 character times, a fixed 1.75 ms
    /// above 19200 baud). 0 in the map: computed from the line settings.
    std::chrono::microseconds frame_gap{0};

    /// 3.5 character times at these settings (1750 us above 19200 baud).
    std::chrono::microseconds minimum_frame_gap() const;
    /// "/dev/ttyUSB0 19200 8E1".
    std::string describe() const;
    /// Same baud, parity, data and stop bits and gap (the device aside).
    bool same_settings(const SerialLine& other) const;
};

struct Config {
    std::string host = "127.0.0.1";
    int port = 502;
    int unit_id = 1;                         ///< TCP unit id, or the RTU slave address
    std::chrono::milliseconds timeout{500};  ///< one request's response timeout
    /// RTU: the serial line (`device` in the map); none: Modbus TCP to host:port.
    std::optional<SerialLine> serial;
    /// RTU: the longest silence between two bytes of one answer (libmodbus's
    /// byte timeout) before the answer counts as cut off.
    std::chrono::milliseconds byte_timeout{100};
    std::chrono::milliseconds backoff_min{200};    ///< first wait before reconnecting
    std::chrono::milliseconds backoff_max{10000};  ///< longest wait (doubling)
    /// Unused registers (bits) a batched read may span to cover two points
    /// in one request instead of two.
    unsigned max_gap = 8;
    std::vector<Point> points;
    std::map<std::string, std::size_t> by_id;  ///< id -> index in points

    const Point* find(const std::string& id) const;
    /// "10.0.0.5:502", or "rtu /dev/ttyUSB0 slave 3" for a serial line.
    std::string endpoint() const;
};

/// Reads the driver's configuration (the adapter's `driver.config`); every
/// mistake is reported with its JSON path ("points/x_position/type: ...").
Result<Config> parse_config(const Json& json);

/// One Modbus read request: `count` registers/bits of `table` from `start`,
/// answering the points listed (indices into the caller's point list).
struct ReadSpan {
    Table table = Table::holding_register;
    std::uint16_t start = 0;
    std::uint16_t count = 0;
    std::vector<std::size_t> members;
};

/// Batches points into as few requests as the protocol allows: points of one
/// table whose addresses lie within max_gap of each other share a request,
/// up to 125 registers or 2000 bits per request (Modbus application protocol
/// 6.1-6.4). `points[i]` null = not a Modbus point (skipped).
std::vector<ReadSpan> plan_reads(const std::vector<const Point*>& points, unsigned max_gap);

/// The point's value from its registers (`words` starts at the point's
/// address) or its bit: scaled, or its enumeration word. An unknown enum
/// value is an error (the machine reports a state the map does not name).
Result<Json> decode(const Point& point, const std::uint16_t* words);
Json decode_bit(const Point& point, bool bit);

/// The registers to write for `value` (the inverse of decode), range-checked
/// against the raw type; for a coil, `bit` is set instead and words is empty.
struct Encoded {
    std::vector<std::uint16_t> words;
    bool bit = false;
};
Result<Encoded> encode(const Point& point, const Json& value);

}  // namespace nclink::modbus
