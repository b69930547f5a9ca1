// The MTConnect 1.4 response documents the bridge serves: the Header of each
// (part 1 6.5: Devices, Streams and Error headers with exactly the attributes
// MTConnect{Devices,Streams,Error}_1.4.xsd require), the Streams document
// built from observations, the Error document, and the Devices document
// assembled from the mapping library's per-adapter documents (docs/mapping.md).
// Pure functions.
#pragma once

#include "bridge/observation_buffer.hpp"
#include "bridge/request_params.hpp"

#include <nclink/mapping.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::bridge {

inline constexpr std::string_view kMtVersion = "1.4.0";

struct HeaderInfo {
    std::string creation_time;  ///< xs:dateTime, UTC
    std::string sender;
    std::uint64_t instance_id = 1;
    std::size_t buffer_size = 0;
    // Streams only:
    std::uint64_t first_sequence = 1;
    std::uint64_t last_sequence = 0;
    std::uint64_t next_sequence = 1;
};

/// "2024-01-01T00:00:00.123Z" for ms since the epoch (UTC, part 1 5.1.3.4).
std::string iso_time(std::int64_t ms_since_epoch);
/// The current wall-clock time in ms since the epoch.
std::int64_t now_ms();

/// An MTConnectError document with one Error per entry.
std::string error_document(const HeaderInfo& header, const std::vector<MtError>& errors);

/// The Devices Header element (assetCount 0, assetBufferSize 1024: the bridge
/// keeps no assets).
std::string devices_header(const HeaderInfo& header);
/// An MTConnectDevices document holding the Device elements of each mapped
/// document in `device_documents` (as map_to_mtconnect wrote them), under our Header.
std::string devices_document(const HeaderInfo& header, const std::vector<const std::string*>& device_documents);

/// One observation to put in a Streams document.
struct StreamEntry {
    const MtDevice* device = nullptr;  ///< DeviceStream name/uuid
    const MtDataItem* item = nullptr;  ///< DataItem id/type/element/component
    const Observation* observation = nullptr;
    /// When set: observation_elements(*item, *observation), rendered before.
    const std::string* rendered = nullptr;
};

/// The element(s) of one observation as a Streams document holds them
/// (one per line; a condition may give several).
std::string observation_elements(const MtDataItem& item, const Observation& observation);

/// An MTConnectStreams document. Entries are grouped by device, then
/// component (each in order of first appearance), then Samples / Events /
/// Condition; within a group they keep their order (pass them by sequence).
std::string streams_document(const HeaderInfo& header, const std::vector<StreamEntry>& entries);

/// The DataItem description of a device's AVAILABILITY item as the mapping
/// writes it in the Devices document (id MtDevice::availability_id, name
/// "avail"); its observations hold "AVAILABLE" or null (UNAVAILABLE).
MtDataItem availability_item(const MtDevice& device, const std::string& device_component_id);

}  // namespace nclink::bridge
