// An MTConnect Streams document (the agent's /current and /sample;
// MTConnect 1.4 part 3) or the Error document the agent answers instead
// (part 1, 8.4), as plain values. Read with libxml2.
#pragma once

#include <nclink/result.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::mtconnect {

/// One observation: a Sample, an Event, or one state of a Condition.
struct StreamObservation {
    std::string item_id;  ///< dataItemId
    std::uint64_t sequence = 0;
    std::string element;      ///< "Position", "Execution"; conditions: "Normal", "Warning", "Fault", "Unavailable"
    std::string text;         ///< the element's text (a value, "UNAVAILABLE", or a condition's message)
    bool condition = false;   ///< inside <Condition>
    std::string native_code;  ///< conditions (and MESSAGE events): nativeCode
};

struct StreamsDocument {
    std::string instance_id;
    std::uint64_t next_sequence = 0;
    std::uint64_t first_sequence = 0;
    std::uint64_t last_sequence = 0;
    /// In sequence order (the document lists them per component).
    std::vector<StreamObservation> observations;
};

/// What the agent answered: a Streams document, or its errors.
struct StreamsReply {
    StreamsDocument streams;
    /// The errorCode of every <Error> ("OUT_OF_RANGE", "NO_DEVICE", ...);
    /// empty when the answer was a Streams document.
    std::vector<std::string> error_codes;
    std::string error_text;  ///< "OUT_OF_RANGE: ..." for the log
    bool is_error() const noexcept { return !error_codes.empty(); }
};

/// Reads /current, /sample or an Error document. Errors (412): not XML, an
/// unexpected root, a Header without instanceId or sequence numbers.
Result<StreamsReply> read_streams(std::string_view xml);

}  // namespace nclink::mtconnect
