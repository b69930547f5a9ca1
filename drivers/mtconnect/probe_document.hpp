// An MTConnect Devices document (the agent's /probe; MTConnect 1.4 part 2)
// as plain values: the devices, their components and DataItems with what
// the reverse mapping needs. Read with libxml2; any version's namespace.
#pragma once

#include <nclink/result.hpp>

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::mtconnect {

/// One <DataItem>.
struct ProbeItem {
    std::string id;
    std::string name;
    std::string category;  ///< "SAMPLE", "EVENT", "CONDITION"
    std::string type;      ///< "POSITION"
    std::string sub_type;  ///< "ACTUAL", "x:TOOL", or ""
    std::string units;
    std::string native_units;
    std::string representation;                  ///< "" (VALUE), "TIME_SERIES", ...
    double sample_rate = 0;                      ///< @sampleRate (samples per second), 0 when absent
    std::string source;                          ///< <Source> text: the SHDR key when set (part 2, 7.2.2.4)
    std::vector<std::string> constraint_values;  ///< <Constraints><Value>s
};

/// A <Device> or a component element below it.
struct ProbeComponent {
    std::string element;  ///< "Device", "Linear", "Controller", "Axes", ...
    std::string id;
    std::string name;
    std::string uuid;                                           ///< Device only
    std::string description;                                    ///< <Description> text
    std::map<std::string, std::string> description_attributes;  ///< manufacturer, model, serialNumber
    std::vector<ProbeItem> items;
    std::vector<ProbeComponent> components;
};

struct ProbeDocument {
    std::string instance_id;  ///< Header@instanceId
    std::string version;      ///< Header@version
    std::vector<ProbeComponent> devices;
};

/// Reads an MTConnectDevices document. Errors (412 syntax_error): not XML,
/// another root (an MTConnectError document is reported with its
/// errorCode and text), no Header, no Devices, a DataItem without id,
/// category or type (named: the model would otherwise silently lack it).
Result<ProbeDocument> read_probe(std::string_view xml);

/// The device chosen by `selector` (its uuid, name or id; "" = the first),
/// nullptr when none matches.
const ProbeComponent* find_device(const ProbeDocument& probe, std::string_view selector);

}  // namespace nclink::mtconnect
