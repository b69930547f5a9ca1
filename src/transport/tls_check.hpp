// Why a TLS connection to the broker fails, in one line a user can act on.
//
// paho reports a failed TLS handshake as a bare "TCP/TLS connect failure":
// a wrong CA, an expired certificate (ours or the broker's) and a host name
// mismatch all look the same. After such a failure the transport asks these
// functions, which check the configured files and repeat the handshake with
// OpenSSL directly (same trust store, same client certificate, same host
// check) to name the cause (docs/security.md, "Errors").
#pragma once

#include <nclink/mqtt_transport.hpp>

#include <chrono>
#include <optional>
#include <string>

namespace nclink::transport_detail {

/// A problem with the configured files themselves (unreadable, not PEM, a
/// client certificate expired or not yet valid, a key that does not match
/// the certificate), or std::nullopt.
std::optional<std::string> tls_file_problem(const MqttTlsOptions& tls);

/// Repeats the TLS handshake with host:port. std::nullopt when it succeeds
/// (the failure was elsewhere); otherwise why it failed, e.g. "the broker's
/// certificate did not verify: certificate has expired".
std::optional<std::string> tls_handshake_problem(const std::string& host, int port, const MqttTlsOptions& tls,
                                                 std::chrono::milliseconds timeout);

}  // namespace nclink::transport_detail
