// Fast Sample DTU encoder (8.2.15 / 8.2.21) for the upload hot path.
//
// Writes
//   {"@id"?, "guid", "id", "beginTime": "<ms>", "data": [{"data":[...]}, ...], "privateInfo"?}
// straight into a reusable buffer: one `data` entry per channel point, in the
// channel's order, each holding that point's values in time order. No DOM is
// built and numbers cost no allocation (docs/sampling.md "Benchmarks" shows why this matters).
//
// Number formatting: doubles use std::to_chars (shortest text that round-trips
// exactly); integral doubles therefore print without a fraction ("414"), except
// -0.0 which prints "-0.0" so its sign survives a round trip. NaN and +-Inf are
// not JSON and are encoded as `null` (as nlohmann::json::dump does).
// Strings are escaped per RFC 8259 (quote, backslash, control characters);
// valid UTF-8 passes through unchanged, invalid bytes become U+FFFD.
#pragma once

#include <nclink/export.hpp>
#include <nclink/json.hpp>
#include <nclink/sample_value.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace nclink {

/// The scalar keys of a Sample DTU. Views are only read during encode().
struct NCLINK_API SampleDtuHeader {
    std::string_view guid;               ///< device GUID (dev)
    std::string_view channel_id;         ///< sample channel id ("id")
    std::int64_t begin_time_ms = 0;      ///< time of the first row, ms since epoch (sent as a string)
    const Json* msg_id = nullptr;        ///< optional "@id" (rare: dumped by nlohmann)
    const Json* private_info = nullptr;  ///< optional "privateInfo" (rare: dumped by nlohmann)
};

/// Column-major block: point p (0..points-1), row r (0..rows-1) is
/// values[p * rows + r]. Every point has the same number of rows.
struct NCLINK_API SampleBlock {
    const SampleValue* values = nullptr;
    std::size_t points = 0;
    std::size_t rows = 0;
};

/// Row-major block, as a sampler fills it: row r (0..rows-1), point p
/// (0..points-1) is values[r * points + p]. Encoded exactly as the
/// SampleBlock of its transpose, without transposing it first.
struct NCLINK_API SampleRows {
    const SampleValue* values = nullptr;
    std::size_t points = 0;
    std::size_t rows = 0;
};

/// One point's values in time order (columns may differ in length).
struct NCLINK_API SampleColumn {
    const SampleValue* values = nullptr;
    std::size_t size = 0;
};

/// Not thread-safe: one encoder per uploader thread. The returned view points
/// into the encoder's buffer and is valid until the next encode() or destruction.
/// The buffer only grows, so steady-state encoding does not allocate.
class NCLINK_API SampleEncoder {
public:
    explicit SampleEncoder(std::size_t initial_capacity = 16 * 1024);

    std::string_view encode(const SampleDtuHeader& header, const SampleBlock& block);
    std::string_view encode(const SampleDtuHeader& header, const SampleRows& rows);
    std::string_view encode(const SampleDtuHeader& header, const SampleColumn* columns, std::size_t count);

    /// Bytes currently reserved (for tests and statistics).
    std::size_t capacity() const noexcept { return buffer_.size(); }

private:
    std::string buffer_;
};

/// Appends `text` as a quoted, escaped JSON string (the encoder's escaper).
NCLINK_API void append_json_string(std::string& out, std::string_view text);
/// Appends a double as the encoder prints it (shortest round-trip, null for NaN/Inf).
NCLINK_API void append_json_double(std::string& out, double value);
/// Appends one SampleValue as the encoder prints it.
NCLINK_API void append_sample_value(std::string& out, const SampleValue& value);

}  // namespace nclink
