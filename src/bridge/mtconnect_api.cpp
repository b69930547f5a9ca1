#include "bridge/mtconnect_api.hpp"

#include "bridge/mtconnect_documents.hpp"
#include "bridge/path_filter.hpp"

#include <random>

namespace nclink::bridge {
namespace {

http::HttpResponse xml(std::string body, int status = 200) { return http::text_response(std::move(body), kXmlType, status); }

std::string boundary() {
    std::random_device rd;
    return fmt::format("{:016x}{:08x}", (static_cast<std::uint64_t>(rd()) << 32) | rd(), rd());
}

// One part of a multipart/x-mixed-replace stream (part 1 8.3.2.2).
std::string part(const std::string& boundary, const std::string& document) {
    return fmt::format("--{}\r\nContent-type: {}\r\nContent-length: {}\r\n\r\n{}\r\n", boundary, kXmlType, document.size(),
                       document);
}

}  // namespace

HeaderInfo MtConnectApi::header(const BridgeState& st) const {
    HeaderInfo h;
    h.creation_time = iso_time(now_ms());
    h.sender = store_.sender();
    h.instance_id = store_.instance_id();
    h.buffer_size = store_.buffer_size();
    h.first_sequence = st.buffer.first_sequence();
    h.last_sequence = st.buffer.last_sequence();
    h.next_sequence = st.buffer.next_sequence();
    return h;
}

http::HttpResponse MtConnectApi::error(const std::vector<MtError>& errors, int status) const {
    HeaderInfo h = store_.read([&](const BridgeState& st) { return header(st); });
    const int code = status ? status : (errors.empty() ? 400 : http_status(errors.front().code));
    return xml(error_document(h, errors), code);
}

std::optional<MtError> MtConnectApi::select(const BridgeState& st, const std::string& device,
                                            const std::optional<std::string>& path, Selection& out) const {
    if (!device.empty()) {
        const DeviceEntry* d = st.find_device(device);
        if (!d || !d->model) return MtError{MtErrorCode::no_device, "no device named '" + device.substr(0, 200) + "'"};
        out.devices.push_back(d);
    } else {
        for (const auto& d : st.devices)
            if (d.model) out.devices.push_back(&d);
    }
    out.items.assign(st.items.size(), false);
    if (!path) {
        for (const DeviceEntry* d : out.devices)
            for (ItemIndex i : d->items) out.items[i] = true;
        return std::nullopt;
    }
    bool any = false;
    std::optional<MtError> last_error;
    for (const DeviceEntry* d : out.devices) {
        std::set<std::string> ids;
        if (auto e = select_data_items(d->devices_xml, *path, ids)) {
            if (e->code != MtErrorCode::invalid_path || e->message.find("no valid XPath") != std::string::npos) return e;
            last_error = e;  // selects nothing in this device; maybe in another
            continue;
        }
        for (const auto& id : ids) {
            auto it = d->by_mtconnect_id.find(id);
            if (it == d->by_mtconnect_id.end()) continue;
            out.items[it->second] = true;
            any = true;
        }
    }
    if (!any) return last_error ? *last_error : MtError{MtErrorCode::invalid_path, "the path selects no data item"};
    return std::nullopt;
}

std::string MtConnectApi::current_document(const BridgeState& st, const Selection& sel, std::optional<std::uint64_t> at) const {
    std::vector<std::optional<Observation>> at_values;
    if (at) at_values = st.buffer.values_at(*at);
    // A reference to one or the other (a ?: of a const and a non-const vector would copy).
    const std::vector<std::optional<Observation>>& values =
        at ? static_cast<const decltype(at_values)&>(at_values) : st.buffer.latest();
    std::lock_guard<std::mutex> lock(rendered_mutex_);  // the entries point into rendered_
    std::vector<StreamEntry> entries;
    for (const DeviceEntry* d : sel.devices)
        for (ItemIndex i : d->items) {
            if (!sel.items[i] || i >= values.size() || !values[i]) continue;
            const Observation& o = *values[i];
            StreamEntry entry{&d->mt, &st.items[i].mt, &o, nullptr};
            if (o.value.is_structured()) {
                Rendered& r = rendered_[i];
                if (r.text.empty() || r.sequence != o.sequence) {
                    r.sequence = o.sequence;
                    r.text = observation_elements(st.items[i].mt, o);
                }
                entry.rendered = &r.text;
            }
            entries.push_back(entry);
        }
    HeaderInfo h = header(st);
    if (at) h.next_sequence = *at + 1;
    return streams_document(h, entries);
}

http::HttpResponse MtConnectApi::probe(const std::string& device) const {
    return store_.read([&](const BridgeState& st) -> http::HttpResponse {
        Selection sel;
        if (auto e = select(st, device, std::nullopt, sel)) {
            HeaderInfo h = header(st);
            return xml(error_document(h, {*e}), http_status(e->code));
        }
        std::vector<const std::string*> docs;
        for (const DeviceEntry* d : sel.devices) docs.push_back(&d->devices_xml);
        return xml(devices_document(header(st), docs));
    });
}

http::HttpResponse MtConnectApi::current(const std::string& device, const QueryParams& query) const {
    CurrentParams params;
    if (auto e = parse_current_params(query, store_.buffer_size(), params)) return error({*e});
    if (params.interval) return stream_current(device, params);
    return store_.read([&](const BridgeState& st) -> http::HttpResponse {
        Selection sel;
        std::optional<MtError> e = select(st, device, params.path, sel);
        if (!e && params.at) e = check_at(*params.at, st.buffer.first_sequence(), st.buffer.last_sequence());
        if (e) return xml(error_document(header(st), {*e}), http_status(e->code));
        return xml(current_document(st, sel, params.at));
    });
}

http::HttpResponse MtConnectApi::current_of(const std::string& dev, const std::vector<std::string>& ids) const {
    return store_.read([&](const BridgeState& st) -> http::HttpResponse {
        Selection sel;
        if (auto e = select(st, dev, std::nullopt, sel)) return xml(error_document(header(st), {*e}), http_status(e->code));
        sel.items.assign(st.items.size(), false);
        for (const auto& id : ids) {
            auto it = sel.devices.front()->by_nclink_id.find(id);
            if (it != sel.devices.front()->by_nclink_id.end()) sel.items[it->second] = true;
        }
        return xml(current_document(st, sel, std::nullopt));
    });
}

http::HttpResponse MtConnectApi::sample(const std::string& device, const QueryParams& query) const {
    SampleParams params;
    if (auto e = parse_sample_params(query, store_.buffer_size(), params)) return error({*e});
    if (params.interval) return stream_sample(device, params);
    return store_.read([&](const BridgeState& st) -> http::HttpResponse {
        Selection sel;
        std::optional<MtError> e = select(st, device, params.path, sel);
        const std::uint64_t from = params.from.value_or(st.buffer.first_sequence());
        if (!e) e = check_from(from, st.buffer.first_sequence(), st.buffer.next_sequence());
        if (e) return xml(error_document(header(st), {*e}), http_status(e->code));
        auto range = st.buffer.range(from, params.count, [&](ItemIndex i) { return i < sel.items.size() && sel.items[i]; });
        std::vector<StreamEntry> entries;
        entries.reserve(range.observations.size());
        for (const auto& o : range.observations) {
            const ItemEntry& item = st.items[o.item];
            entries.push_back(StreamEntry{&st.devices[item.device].mt, &item.mt, &o});
        }
        HeaderInfo h = header(st);
        h.next_sequence = range.next_sequence;
        return xml(streams_document(h, entries));
    });
}

http::HttpResponse MtConnectApi::stream_current(const std::string& device, const CurrentParams& params) const {
    // Validate once before streaming, so a bad device or path is a plain error.
    std::optional<MtError> e = store_.read([&](const BridgeState& st) {
        Selection sel;
        return select(st, device, params.path, sel);
    });
    if (e) return error({*e});
    const std::string b = boundary();
    http::HttpResponse r;
    r.content_type = "multipart/x-mixed-replace;boundary=" + b;
    const BridgeStore* store = &store_;
    const MtConnectApi* self = this;
    r.stream = [store, self, device, params, b](http::StreamSink& sink) {
        const auto interval = std::max(params.interval.value_or(std::chrono::milliseconds(0)), std::chrono::milliseconds(10));
        while (!sink.stopping()) {
            std::string doc = store->read([&](const BridgeState& st) {
                Selection sel;
                if (self->select(st, device, params.path, sel))
                    return error_document(self->header(st), {MtError{MtErrorCode::no_device, "device gone"}});
                return self->current_document(st, sel, std::nullopt);
            });
            if (!sink.write(part(b, doc))) return;
            if (!sink.sleep_for(interval)) return;
        }
    };
    return r;
}

http::HttpResponse MtConnectApi::stream_sample(const std::string& device, const SampleParams& params) const {
    std::uint64_t start = 0;
    std::optional<MtError> e = store_.read([&](const BridgeState& st) -> std::optional<MtError> {
        Selection sel;
        if (auto err = select(st, device, params.path, sel)) return err;
        start = params.from.value_or(st.buffer.next_sequence());
        return check_from(start, st.buffer.first_sequence(), st.buffer.next_sequence());
    });
    if (e) return error({*e});
    const std::string b = boundary();
    http::HttpResponse r;
    r.content_type = "multipart/x-mixed-replace;boundary=" + b;
    const BridgeStore* store = &store_;
    const MtConnectApi* self = this;
    r.stream = [store, self, device, params, b, start](http::StreamSink& sink) {
        std::uint64_t from = start;
        auto last_sent = std::chrono::steady_clock::now() - params.heartbeat;
        const auto interval = params.interval.value_or(std::chrono::milliseconds(0));
        while (!sink.stopping()) {
            bool out_of_range = false;
            std::size_t found = 0;
            std::uint64_t next = from;
            std::string doc = store->read([&](const BridgeState& st) -> std::string {
                if (from < st.buffer.first_sequence()) {
                    out_of_range = true;
                    return error_document(self->header(st),
                                          {MtError{MtErrorCode::out_of_range, "the client fell behind the buffer"}});
                }
                Selection sel;
                self->select(st, device, params.path, sel);
                auto range = st.buffer.range(from, params.count, [&](ItemIndex i) { return i < sel.items.size() && sel.items[i]; });
                found = range.observations.size();
                next = range.next_sequence;
                std::vector<StreamEntry> entries;
                for (const auto& o : range.observations) {
                    const ItemEntry& item = st.items[o.item];
                    entries.push_back(StreamEntry{&st.devices[item.device].mt, &item.mt, &o});
                }
                HeaderInfo h = self->header(st);
                h.next_sequence = range.next_sequence;
                return streams_document(h, entries);
            });
            const auto now = std::chrono::steady_clock::now();
            if (out_of_range) {
                sink.write(part(b, doc));
                return;
            }
            from = next;
            if (found > 0 || now - last_sent >= params.heartbeat) {
                if (!sink.write(part(b, doc))) return;
                last_sent = now;
                if (interval.count() > 0 && !sink.sleep_for(interval)) return;
            }
            if (found < params.count) {
                // Nothing more buffered: wait for new observations (in slices, to notice a stop).
                store->wait_for_change(from - 1, std::numeric_limits<std::uint64_t>::max(), std::chrono::milliseconds(100));
            }
        }
    };
    return r;
}

void MtConnectApi::install(http::HttpServer& server, const std::string& prefix) {
    server.get(prefix + "/probe", [this](const http::HttpRequest&) { return probe(""); });
    server.get(prefix + "/", [this](const http::HttpRequest&) { return probe(""); });
    server.get(prefix + "/current", [this](const http::HttpRequest& r) { return current("", r.query); });
    server.get(prefix + "/sample", [this](const http::HttpRequest& r) { return sample("", r.query); });
    server.get(prefix + "/{device}/probe", [this](const http::HttpRequest& r) { return probe(r.path_param("device")); });
    server.get(prefix + "/{device}", [this](const http::HttpRequest& r) { return probe(r.path_param("device")); });
    server.get(prefix + "/{device}/current",
               [this](const http::HttpRequest& r) { return current(r.path_param("device"), r.query); });
    server.get(prefix + "/{device}/sample", [this](const http::HttpRequest& r) { return sample(r.path_param("device"), r.query); });
    auto no_assets = [this](const http::HttpRequest&) {
        return error({MtError{MtErrorCode::unsupported, "this agent keeps no assets (NC-Link has none)"}});
    };
    server.get(prefix + "/assets", no_assets);
    server.get(prefix + "/asset/{id}", no_assets);
    server.get(prefix + "/assets/{id}", no_assets);
    server.get(prefix + "/{device}/assets", no_assets);
}

}  // namespace nclink::bridge
