#include "bridge/gbt_api.hpp"

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <libxml/xmlerror.h>

#include <memory>

namespace nclink::bridge {
namespace {

void ignore_structured(void*, xmlErrorPtr) {}

std::string prop(const xmlNode* node, const char* name) {
    xmlChar* v = xmlGetProp(node, reinterpret_cast<const xmlChar*>(name));
    if (!v) return {};
    std::string out(reinterpret_cast<const char*>(v));
    xmlFree(v);
    return out;
}

std::string text_of(const xmlNode* node) {
    xmlChar* v = xmlNodeGetContent(node);
    if (!v) return {};
    std::string out(reinterpret_cast<const char*>(v));
    xmlFree(v);
    return out;
}

bool named(const xmlNode* n, const char* name) {
    return n->type == XML_ELEMENT_NODE && xmlStrcmp(n->name, reinterpret_cast<const xmlChar*>(name)) == 0;
}

// A value's text as JSON when it reads as JSON (numbers, true/false, null,
// quoted strings, arrays, objects), else as a string.
Json value_of(const std::string& text) {
    Json parsed = Json::parse(text, nullptr, false);
    if (!parsed.is_discarded()) return parsed;
    return Json(text);
}

}  // namespace

std::optional<MtError> GbtApi::parse_write(const std::string& body, WriteRequest& out) {
    xmlSetStructuredErrorFunc(nullptr, ignore_structured);
    std::unique_ptr<xmlDoc, void (*)(xmlDocPtr)> doc(
        xmlReadMemory(body.data(), static_cast<int>(body.size()), "write.xml", "UTF-8", XML_PARSE_NONET), xmlFreeDoc);
    if (!doc) return MtError{MtErrorCode::invalid_request, "the data-write request is no well-formed XML"};
    const xmlNode* root = xmlDocGetRootElement(doc.get());
    if (!root || !named(root, "DataWriteRequest"))
        return MtError{MtErrorCode::invalid_request, "the data-write request must be a DataWriteRequest element"};
    const xmlNode* operation = nullptr;
    for (const xmlNode* n = root->children; n; n = n->next) {
        if (named(n, "Header")) {
            out.version = prop(n, "version");
            out.send_time = prop(n, "sendTime");
            out.sender = prop(n, "sender");
            out.operation = prop(n, "operationId");
            out.security = prop(n, "security");
        } else if (named(n, "Operation")) {
            operation = n;
        }
    }
    if (!operation) return MtError{MtErrorCode::invalid_request, "the data-write request has no Operation"};
    out.command = prop(operation, "command");
    out.description = prop(operation, "description");
    if (out.command.empty()) out.command = "SET";
    if (out.command != "SET")
        return MtError{MtErrorCode::unsupported,
                       "operation command '" + out.command.substr(0, 64) + "' is not supported (SET only)"};
    for (const xmlNode* n = operation->children; n; n = n->next) {
        if (!named(n, "Value")) continue;
        WriteRequest::Value v;
        v.item = prop(n, "dataItemId");
        if (v.item.empty()) return MtError{MtErrorCode::invalid_request, "a Value has no dataItemId"};
        v.value = value_of(text_of(n));
        out.values.push_back(std::move(v));
    }
    if (out.values.empty()) return MtError{MtErrorCode::invalid_request, "the Operation has no Value"};
    return std::nullopt;
}

http::HttpResponse GbtApi::write(const std::string& device, const std::string& body) const {
    WriteRequest request;
    if (auto e = parse_write(body, request)) return mtconnect_.error({*e});
    // Resolve the device (the only one when none is named) and every item; refuse non-setable ones.
    std::string dev;
    std::vector<SetItem> items;
    std::vector<std::string> ids;
    std::optional<MtError> refusal;
    store_.read([&](const BridgeState& st) {
        const DeviceEntry* d = nullptr;
        if (!device.empty()) {
            d = st.find_device(device);
        } else {
            for (const auto& candidate : st.devices)
                if (candidate.model) {
                    if (d) {
                        refusal = MtError{MtErrorCode::invalid_request, "several devices: name one in the URL"};
                        return 0;
                    }
                    d = &candidate;
                }
        }
        if (!d || !d->model) {
            refusal = MtError{MtErrorCode::no_device, "no device '" + device.substr(0, 200) + "'"};
            return 0;
        }
        dev = d->dev;
        for (const auto& v : request.values) {
            auto it = d->by_nclink_id.find(v.item);
            if (it == d->by_nclink_id.end()) {
                auto by_mt = d->by_mtconnect_id.find(v.item);
                if (by_mt != d->by_mtconnect_id.end() && !st.items[by_mt->second].availability)
                    it = d->by_nclink_id.find(st.items[by_mt->second].nclink_id);
            }
            if (it == d->by_nclink_id.end()) {
                refusal = MtError{MtErrorCode::invalid_request, "no data item '" + v.item.substr(0, 200) + "' (NC-Link 401)"};
                return 0;
            }
            const ItemEntry& item = st.items[it->second];
            if (!item.setable) {
                refusal = MtError{MtErrorCode::invalid_request,
                                  "data item '" + item.nclink_id + "' is not setable (NC-Link 301 PERMISSION_DENIED)"};
                return 0;
            }
            items.push_back(SetItem{item.nclink_id, Json{{"value", v.value}}, std::nullopt, std::nullopt});
            ids.push_back(item.nclink_id);
        }
        return 0;
    });
    if (refusal) return mtconnect_.error({*refusal});
    auto result = follower_.set(dev, items);
    if (!result)
        return mtconnect_.error({MtError{MtErrorCode::internal_error, "NC-Link Set failed: " + result.error().describe()}},
                                result.error().code == ErrorCode::timeout ? 504 : 502);
    std::vector<MtError> errors;
    for (const auto& r : *result)
        if (!r.status.ok)
            errors.push_back(MtError{MtErrorCode::invalid_request, "NC-Link refused " + r.id + ": " + r.status.reason.value_or("NG") +
                                                                       " (" + std::to_string(r.status.error.value_or(0)) + ")"});
    if (!errors.empty()) return mtconnect_.error(errors);
    return mtconnect_.current_of(dev, ids);
}

void GbtApi::install(http::HttpServer& server, const std::string& prefix) {
    server.get(prefix + "/probe", [this](const http::HttpRequest&) { return mtconnect_.probe(""); });
    server.get(prefix + "/current", [this](const http::HttpRequest& r) { return mtconnect_.current("", r.query); });
    server.get(prefix + "/enquire", [this](const http::HttpRequest& r) { return mtconnect_.sample("", r.query); });
    server.get(prefix + "/{device}/probe", [this](const http::HttpRequest& r) { return mtconnect_.probe(r.path_param("device")); });
    server.get(prefix + "/{device}/current",
               [this](const http::HttpRequest& r) { return mtconnect_.current(r.path_param("device"), r.query); });
    server.get(prefix + "/{device}/enquire",
               [this](const http::HttpRequest& r) { return mtconnect_.sample(r.path_param("device"), r.query); });
    auto write_any = [this](const http::HttpRequest& r) { return write("", r.body); };
    auto write_one = [this](const http::HttpRequest& r) { return write(r.path_param("device"), r.body); };
    server.route("POST", prefix + "/write", write_any);
    server.route("PUT", prefix + "/write", write_any);
    server.route("POST", prefix + "/{device}/write", write_one);
    server.route("PUT", prefix + "/{device}/write", write_one);
}

}  // namespace nclink::bridge
