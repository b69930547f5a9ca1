#include "transport/broker_list.hpp"

#include "transport/tcp_nodelay.hpp"  // parse_broker_url()

#include <nclink/mqtt_transport.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace nclink::transport_detail {

namespace {

bool is_tls_scheme(const std::string& scheme) { return scheme == "ssl" || scheme == "mqtts" || scheme == "wss"; }

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::optional<BrokerAddress> parsed(const std::string& url) {
    BrokerAddress a;
    a.url = url;
    if (!parse_broker_url(url, a.host, a.port, a.scheme)) return std::nullopt;
    return a;
}

// Host and port: "tcp://plant:1883" and "mqtt://PLANT" are one broker.
bool same_broker(const BrokerAddress& a, const BrokerAddress& b) { return a.port == b.port && lower(a.host) == lower(b.host); }

}  // namespace

std::string failover_entry_url(const std::string& entry, const std::string& primary_url) {
    if (entry.find("://") != std::string::npos) return entry;
    const auto sep = primary_url.find("://");
    return (sep == std::string::npos ? std::string("tcp") : primary_url.substr(0, sep)) + "://" + entry;
}

std::optional<std::string> failover_entry_problem(const std::string& primary_url, const std::vector<std::string>& failover,
                                                  std::size_t index) {
    const std::string& entry = failover.at(index);
    const std::string url = failover_entry_url(entry, primary_url);
    if (auto usable = check_broker_url(url); !usable) return usable.error().message;
    const BrokerAddress address = *parsed(url);
    const auto primary = parsed(primary_url);
    if (!primary) return std::nullopt;  // the primary URL's own error is reported for it
    if (is_tls_scheme(address.scheme) != is_tls_scheme(primary->scheme))
        return fmt::format(
            "'{}' {} TLS and url '{}' {}: every broker of the list is reached the same way (the same tls settings and "
            "credentials), so its entries use TLS exactly when url does",
            url, is_tls_scheme(address.scheme) ? "uses" : "does not use", primary_url,
            is_tls_scheme(primary->scheme) ? "does" : "does not");
    if (same_broker(address, *primary)) return fmt::format("'{}' names the broker of url '{}' again", url, primary_url);
    for (std::size_t i = 0; i < index; ++i) {
        const auto earlier = parsed(failover_entry_url(failover[i], primary_url));
        if (earlier && same_broker(address, *earlier))
            return fmt::format("'{}' names the broker of failover entry {} ('{}') again", url, i, failover[i]);
    }
    return std::nullopt;
}

Result<std::vector<BrokerAddress>> broker_list(const std::string& primary_url, const std::vector<std::string>& failover) {
    std::vector<BrokerAddress> out;
    if (auto usable = check_broker_url(primary_url); !usable) return std::move(usable).error();
    out.push_back(*parsed(primary_url));
    for (std::size_t i = 0; i < failover.size(); ++i) {
        if (auto problem = failover_entry_problem(primary_url, failover, i))
            return make_error(ErrorCode::value_type, fmt::format("failover entry {} '{}': {}", i, failover[i], *problem));
        out.push_back(*parsed(failover_entry_url(failover[i], primary_url)));
    }
    return out;
}

}  // namespace nclink::transport_detail
