// The brokers an MQTT transport connects to: MqttOptions::broker_url, then
// each entry of failover_urls, checked and written out in full; and which of
// them a transport is on. One piece for the configuration readers (a bad
// entry is an error naming it) and both transports (libmosquitto and paho),
// so they take the same lists and move through them the same way.
#pragma once

#include <nclink/result.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace nclink::transport_detail {

struct BrokerAddress {
    std::string url;  ///< SCHEME://HOST[:PORT]; a "host:port" entry has the scheme of broker_url
    std::string scheme;
    std::string host;
    int port = 0;
};

/// A failover entry as a URL: "host[:port]" (no "://") gets the scheme of
/// `primary_url`; a URL stays as it is.
std::string failover_entry_url(const std::string& entry, const std::string& primary_url);

/// Why entry `index` of `failover` cannot be used next to `primary_url`,
/// in words a user can act on; nullopt when it can. An entry must be a
/// usable broker URL (check_broker_url()), use TLS exactly when
/// `primary_url` does (TLS settings and credentials are the same for every
/// broker of the list), and name a broker (host and port) that neither
/// `primary_url` nor an earlier entry names.
std::optional<std::string> failover_entry_problem(const std::string& primary_url, const std::vector<std::string>& failover,
                                                  std::size_t index);

/// `primary_url` and every entry of `failover`, in order. A value_type error
/// naming the first unusable one: the primary URL as check_broker_url()
/// says, an entry as "failover entry N 'TEXT': <problem>".
Result<std::vector<BrokerAddress>> broker_list(const std::string& primary_url, const std::vector<std::string>& failover);

/// Which broker of the list a transport is on. Not thread-safe: the thread
/// that connects (libmosquitto's loop, paho's supervisor) owns it.
class BrokerRotation {
public:
    explicit BrokerRotation(std::vector<BrokerAddress> brokers) : brokers_(std::move(brokers)) {}

    const BrokerAddress& current() const { return brokers_[at_]; }
    std::size_t size() const { return brokers_.size(); }
    /// To the next broker (after the last, the first). False, and no move,
    /// when the list has one broker.
    bool advance() {
        if (brokers_.size() < 2) return false;
        at_ = (at_ + 1) % brokers_.size();
        return true;
    }

private:
    std::vector<BrokerAddress> brokers_;  // never empty
    std::size_t at_ = 0;
};

}  // namespace nclink::transport_detail
