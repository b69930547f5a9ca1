// GB/T 18759.6-2016 HTTP interface under a prefix (docs/bridge.md "GB/T
// 18759.6"): probe (6.2.2), current (6.2.3, table 7: Path, At, Count),
// enquire (6.2.4, table 8: Path, Interval, From, Count) answered with the
// same documents as MTConnect (their headers carry every attribute of tables
// 9-11), and the data-write request (6.2.5, figure 9) mapped to an NC-Link
// Set of setable items.
#pragma once

#include "bridge/follower.hpp"
#include "bridge/mtconnect_api.hpp"

namespace nclink::bridge {

class GbtApi {
public:
    GbtApi(const BridgeStore& store, const MtConnectApi& mtconnect, Follower& follower)
        : store_(store), mtconnect_(mtconnect), follower_(follower) {}
    void install(http::HttpServer& server, const std::string& prefix = "/gbt18759");

    /// A data-write request body (figure 9) as parsed.
    struct WriteRequest {
        std::string version, send_time, sender, operation, security;
        std::string command;  ///< "SET" (the only command the bridge carries out)
        std::string description;
        struct Value {
            std::string item;  ///< dataItemId: the NC-Link id (or its MTConnect form)
            Json value;
        };
        std::vector<Value> values;
    };
    /// Parses the XML body; INVALID_REQUEST with a reason when it is not one.
    static std::optional<MtError> parse_write(const std::string& body, WriteRequest& out);

private:
    http::HttpResponse write(const std::string& device, const std::string& body) const;

    const BridgeStore& store_;
    const MtConnectApi& mtconnect_;
    Follower& follower_;
};

}  // namespace nclink::bridge
