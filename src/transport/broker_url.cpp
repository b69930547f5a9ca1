// Why a broker URL is unusable, in words a user can act on: the form it
// needs, and what in the given text departs from it.
#include <nclink/mqtt_transport.hpp>

#include "transport/tcp_nodelay.hpp"

#include <fmt/format.h>

namespace nclink {

namespace {
constexpr const char* kForm = "SCHEME://HOST[:PORT] with SCHEME tcp, mqtt, ssl, mqtts, ws or wss, e.g. tcp://127.0.0.1:1883";
}

Result<void> check_broker_url(const std::string& url) {
    std::string host, scheme;
    int port = 0;
    if (transport_detail::parse_broker_url(url, host, port, scheme)) return ok_result();
    std::string why;
    const auto sep = url.find("://");
    if (url.empty()) why = "it is empty";
    else if (sep == std::string::npos) why = fmt::format("it has no scheme (did you mean tcp://{}?)", url);
    else if (const std::string s = url.substr(0, sep);
             s != "tcp" && s != "mqtt" && s != "ssl" && s != "mqtts" && s != "ws" && s != "wss")
        why = fmt::format("unknown scheme '{}'", s);
    else why = "no host, or a port that is not a number from 1 to 65535";
    return make_error(ErrorCode::value_type, fmt::format("unusable broker URL '{}': {}; expected {}", url, why, kForm));
}

}  // namespace nclink
