#include "bridge/mtconnect_documents.hpp"

#include <fmt/format.h>

#include <chrono>
#include <ctime>
#include <map>

namespace nclink::bridge {
namespace {

constexpr std::string_view kStreamsNs = "urn:mtconnect.org:MTConnectStreams:1.4";
constexpr std::string_view kErrorNs = "urn:mtconnect.org:MTConnectError:1.4";
constexpr std::string_view kDevicesNs = "urn:mtconnect.org:MTConnectDevices:1.4";

void root(std::string& out, std::string_view element, std::string_view ns, std::string_view schema) {
    out += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<";
    out += element;
    out += fmt::format(
        " xmlns=\"{0}\" xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" "
        "xsi:schemaLocation=\"{0} http://schemas.mtconnect.org/schemas/{1}_1.4.xsd\">\n",
        ns, schema);
}

// Text as XML: most of it (ids, numbers, timestamps) needs no escaping, so
// only text with a character xml_escape would change goes through it.
void append_escaped(std::string& out, std::string_view text) {
    for (unsigned char c : text) {
        if (c < 0x20 || c >= 0x7f || c == '&' || c == '<' || c == '>' || c == '"' || c == '\'') {
            out += xml_escape(text);
            return;
        }
    }
    out.append(text);
}

void attr(std::string& out, std::string_view name, std::string_view value) {
    out += ' ';
    out += name;
    out += "=\"";
    append_escaped(out, value);
    out += '"';
}

std::string common_header(const HeaderInfo& h) {
    std::string out = "  <Header";
    attr(out, "creationTime", h.creation_time);
    attr(out, "sender", h.sender.empty() ? "nclink-bridge" : h.sender);
    attr(out, "instanceId", std::to_string(h.instance_id));
    attr(out, "version", kMtVersion);
    attr(out, "bufferSize", std::to_string(h.buffer_size));
    return out;
}

void append_observation(std::string& out, const MtDataItem& item, const Observation& o) {
    const bool condition = item.category == MtCategory::condition;
    const std::string timestamp = iso_time(o.time_ms);
    for (const auto& ob : mtconnect_observations(item, o.value)) {
        out += "          <";
        out += ob.element;
        attr(out, "dataItemId", item.id);
        if (!item.name.empty()) attr(out, "name", item.name);
        attr(out, "sequence", std::to_string(o.sequence));
        if (!item.sub_type.empty()) attr(out, "subType", item.sub_type);
        attr(out, "timestamp", timestamp);
        if (condition) {
            attr(out, "type", item.type);
            if (!ob.native_code.empty()) attr(out, "nativeCode", ob.native_code);
        }
        if (ob.value.empty()) {
            out += "/>\n";
        } else {
            out += '>';
            append_escaped(out, ob.value);
            out += "</";
            out += ob.element;
            out += ">\n";
        }
    }
}

}  // namespace

std::string observation_elements(const MtDataItem& item, const Observation& observation) {
    std::string out;
    append_observation(out, item, observation);
    return out;
}

std::string iso_time(std::int64_t ms) {
    const std::time_t seconds = static_cast<std::time_t>(ms >= 0 ? ms / 1000 : (ms - 999) / 1000);
    const int millis = static_cast<int>(ms - static_cast<std::int64_t>(seconds) * 1000);
    std::tm tm{};
    gmtime_r(&seconds, &tm);
    return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour,
                       tm.tm_min, tm.tm_sec, millis);
}

std::int64_t now_ms() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string error_document(const HeaderInfo& header, const std::vector<MtError>& errors) {
    std::string out;
    root(out, "MTConnectError", kErrorNs, "MTConnectError");
    out += common_header(header);
    out += "/>\n  <Errors>\n";
    for (const auto& e : errors) {
        out += "    <Error";
        attr(out, "errorCode", to_string(e.code));
        out += '>';
        out += xml_escape(e.message);
        out += "</Error>\n";
    }
    out += "  </Errors>\n</MTConnectError>\n";
    return out;
}

std::string devices_header(const HeaderInfo& header) {
    std::string out = common_header(header);
    attr(out, "assetBufferSize", "1024");  // the schema wants at least 1; assetCount says there are none
    attr(out, "assetCount", "0");
    out += "/>";
    return out;
}

std::string devices_document(const HeaderInfo& header, const std::vector<const std::string*>& device_documents) {
    std::string out;
    root(out, "MTConnectDevices", kDevicesNs, "MTConnectDevices");
    out += devices_header(header);
    out += "\n  <Devices>\n";
    for (const std::string* doc : device_documents) {
        // The Device elements between <Devices> and </Devices> of a mapped document.
        const auto open = doc->find("<Devices>");
        const auto close = doc->rfind("</Devices>");
        if (open == std::string::npos || close == std::string::npos || close < open) continue;
        const auto begin = open + std::string_view("<Devices>").size();
        out.append(*doc, begin, close - begin);
        if (out.back() != '\n') out += '\n';
    }
    out += "  </Devices>\n</MTConnectDevices>\n";
    return out;
}

MtDataItem availability_item(const MtDevice& device, const std::string& device_component_id) {
    MtDataItem item;
    item.id = device.availability_id;
    item.name = "avail";
    item.category = MtCategory::event;
    item.type = "AVAILABILITY";
    item.element = "Availability";
    item.component_id = device_component_id;
    item.component_element = "Device";
    item.component_name = device.name;
    item.device_uuid = device.uuid;
    item.value_form = MtValueForm::text;
    return item;
}

std::string streams_document(const HeaderInfo& header, const std::vector<StreamEntry>& entries) {
    // device -> component -> category -> rendered observations
    struct Component {
        std::string element, name, id;
        std::string groups[3];
    };
    struct Device {
        const MtDevice* device = nullptr;
        std::vector<Component> components;
        std::map<std::string, std::size_t> by_id;
    };
    std::vector<Device> devices;
    std::map<const MtDevice*, std::size_t> device_index;

    for (const auto& e : entries) {
        if (!e.device || !e.item || !e.observation) continue;
        auto [dit, added] = device_index.emplace(e.device, devices.size());
        if (added) devices.push_back(Device{e.device, {}, {}});
        Device& d = devices[dit->second];
        auto [cit, cadded] = d.by_id.emplace(e.item->component_id, d.components.size());
        if (cadded)
            d.components.push_back(Component{e.item->component_element, e.item->component_name, e.item->component_id, {}});
        Component& c = d.components[cit->second];
        const int group = e.item->category == MtCategory::sample ? 0 : e.item->category == MtCategory::event ? 1 : 2;
        if (e.rendered) c.groups[group] += *e.rendered;
        else append_observation(c.groups[group], *e.item, *e.observation);
    }

    // One allocation for the whole document: growing a document of tens of
    // kilobytes by doubling copied it several times, and the freed blocks
    // made the allocator hand memory back to the kernel on every request.
    std::size_t size = 1024;
    for (const auto& d : devices) {
        size += 256 + d.device->name.size() + d.device->uuid.size();
        for (const auto& c : d.components)
            size += 256 + c.element.size() + c.name.size() + c.id.size() + c.groups[0].size() + c.groups[1].size() +
                    c.groups[2].size();
    }
    std::string out;
    out.reserve(size);
    root(out, "MTConnectStreams", kStreamsNs, "MTConnectStreams");
    out += common_header(header);
    attr(out, "nextSequence", std::to_string(header.next_sequence));
    attr(out, "firstSequence", std::to_string(header.first_sequence));
    attr(out, "lastSequence", std::to_string(header.last_sequence));
    out += "/>\n";
    if (devices.empty()) {
        out += "  <Streams/>\n</MTConnectStreams>\n";
        return out;
    }
    out += "  <Streams>\n";
    static const char* const kGroups[3] = {"Samples", "Events", "Condition"};
    for (const auto& d : devices) {
        out += "    <DeviceStream";
        attr(out, "name", d.device->name);
        attr(out, "uuid", d.device->uuid);
        out += ">\n";
        for (const auto& c : d.components) {
            out += "      <ComponentStream";
            attr(out, "component", c.element);
            if (!c.name.empty()) attr(out, "name", c.name);
            attr(out, "componentId", c.id);
            out += ">\n";
            for (int g = 0; g < 3; ++g) {
                if (c.groups[g].empty()) continue;
                out += fmt::format("        <{}>\n", kGroups[g]);
                out += c.groups[g];
                out += fmt::format("        </{}>\n", kGroups[g]);
            }
            out += "      </ComponentStream>\n";
        }
        out += "    </DeviceStream>\n";
    }
    out += "  </Streams>\n</MTConnectStreams>\n";
    return out;
}

}  // namespace nclink::bridge
