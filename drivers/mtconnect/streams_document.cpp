#include "mtconnect/streams_document.hpp"

#include "mtconnect/xml_read.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>

namespace nclink::mtconnect {

namespace {

bool to_u64(const std::string& text, std::uint64_t& out) {
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
    errno = 0;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
    if (errno != 0 || *end != '\0') return false;
    out = v;
    return true;
}

// Every element of a ComponentStream's Samples, Events and Condition is an
// observation (part 3, 5.4-5.6); the element name is its type.
void read_group(const xmlNode* group, bool condition, std::vector<StreamObservation>& out) {
    for (const xmlNode* o : children(group)) {
        StreamObservation obs;
        obs.item_id = attribute(o, "dataItemId");
        if (obs.item_id.empty()) continue;  // nothing to attach it to
        if (!to_u64(attribute(o, "sequence"), obs.sequence)) obs.sequence = 0;
        obs.element = std::string(local_name(o));
        obs.text = text_of(o);
        obs.condition = condition;
        obs.native_code = attribute(o, "nativeCode");
        out.push_back(std::move(obs));
    }
}

}  // namespace

Result<StreamsReply> read_streams(std::string_view xml) {
    auto parsed = parse_xml(xml, "streams");
    if (!parsed.ok()) return std::move(parsed).error();
    const xmlNode* root = xmlDocGetRootElement(parsed.value().get());
    StreamsReply reply;
    if (local_name(root) == "MTConnectError") {
        for (const xmlNode* errors : children(root, "Errors"))
            for (const xmlNode* e : children(errors, "Error")) reply.error_codes.push_back(attribute(e, "errorCode"));
        for (const xmlNode* e : children(root, "Error")) reply.error_codes.push_back(attribute(e, "errorCode"));
        if (reply.error_codes.empty()) reply.error_codes.push_back("UNKNOWN");
        reply.error_text = agent_errors_text(root);
        return reply;
    }
    if (local_name(root) != "MTConnectStreams")
        return make_error(ErrorCode::syntax_error,
                          "streams: expected an MTConnectStreams document, got <" + std::string(local_name(root)) + ">");
    const xmlNode* header = child(root, "Header");
    if (!header) return make_error(ErrorCode::syntax_error, "streams: MTConnectStreams without a Header");
    StreamsDocument& doc = reply.streams;
    doc.instance_id = attribute(header, "instanceId");
    if (doc.instance_id.empty() || !to_u64(attribute(header, "nextSequence"), doc.next_sequence) ||
        !to_u64(attribute(header, "firstSequence"), doc.first_sequence) ||
        !to_u64(attribute(header, "lastSequence"), doc.last_sequence))
        return make_error(ErrorCode::syntax_error,
                          "streams: the Header lacks instanceId, nextSequence, firstSequence or lastSequence");
    for (const xmlNode* streams : children(root, "Streams"))
        for (const xmlNode* device : children(streams, "DeviceStream"))
            for (const xmlNode* component : children(device, "ComponentStream")) {
                for (const xmlNode* g : children(component, "Samples")) read_group(g, false, doc.observations);
                for (const xmlNode* g : children(component, "Events")) read_group(g, false, doc.observations);
                for (const xmlNode* g : children(component, "Condition")) read_group(g, true, doc.observations);
            }
    std::stable_sort(doc.observations.begin(), doc.observations.end(),
                     [](const StreamObservation& a, const StreamObservation& b) { return a.sequence < b.sequence; });
    return reply;
}

}  // namespace nclink::mtconnect
