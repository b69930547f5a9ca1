// MTConnect 1.4 REST (part 1 8): /probe, /current, /sample, /assets and the
// per-device forms /{device}/..., served from the store; also used by the
// GB/T 18759.6 routes, whose probe/current/enquire are the same requests.
// Handlers run on HTTP worker threads; the store does the locking.
#pragma once

#include "bridge/bridge_store.hpp"
#include "bridge/mtconnect_documents.hpp"
#include "bridge/request_params.hpp"
#include "http/http_server.hpp"

#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

namespace nclink::bridge {

class MtConnectApi {
public:
    explicit MtConnectApi(const BridgeStore& store) : store_(store) {}

    /// Registers the routes under `prefix` ("" for the root).
    void install(http::HttpServer& server, const std::string& prefix = "");

    /// Requests; `device` "" = every device, else a name or uuid (NO_DEVICE when unknown).
    http::HttpResponse probe(const std::string& device) const;
    http::HttpResponse current(const std::string& device, const QueryParams& query) const;
    http::HttpResponse sample(const std::string& device, const QueryParams& query) const;
    /// An MTConnectError response with the status of the (first) error's code.
    http::HttpResponse error(const std::vector<MtError>& errors, int status = 0) const;
    /// The Streams document of the current values of `items` of `dev` (for the data-write answer).
    http::HttpResponse current_of(const std::string& dev, const std::vector<std::string>& nclink_ids) const;

private:
    struct Selection {
        std::vector<const DeviceEntry*> devices;
        std::vector<bool> items;  ///< by ItemIndex: wanted
    };
    std::optional<MtError> select(const BridgeState& st, const std::string& device, const std::optional<std::string>& path,
                                  Selection& out) const;
    HeaderInfo header(const BridgeState& st) const;
    std::string current_document(const BridgeState& st, const Selection& sel, std::optional<std::uint64_t> at) const;
    http::HttpResponse stream_current(const std::string& device, const CurrentParams& params) const;
    http::HttpResponse stream_sample(const std::string& device, const SampleParams& params) const;

    const BridgeStore& store_;

    /// The rendered elements of the latest structured observations (lists,
    /// tables: JSON text) by item: an observation never changes, and such a
    /// value, tens of kilobytes for a tool table, cost most of every
    /// /current when it was written again each time (docs/bridge.md "Figures").
    struct Rendered {
        std::uint64_t sequence = 0;
        std::string text;
    };
    mutable std::mutex rendered_mutex_;
    mutable std::unordered_map<ItemIndex, Rendered> rendered_;
};

/// Content type of MTConnect documents.
inline constexpr const char* kXmlType = "application/xml";

}  // namespace nclink::bridge
