#include "transport/tls_check.hpp"

#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/ssl.h>
#include <openssl/x509v3.h>

#include <fmt/format.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <memory>

namespace nclink::transport_detail {
namespace {

template <class T, void (*Free)(T*)>
struct Deleter {
    void operator()(T* p) const { Free(p); }
};
using Bio = std::unique_ptr<BIO, Deleter<BIO, BIO_free_all>>;
using X509Ptr = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using Ctx = std::unique_ptr<SSL_CTX, Deleter<SSL_CTX, SSL_CTX_free>>;
using Ssl = std::unique_ptr<SSL, Deleter<SSL, SSL_free>>;

std::string asn1_time_text(const ASN1_TIME* t) {
    Bio bio(BIO_new(BIO_s_mem()));
    if (!bio || !ASN1_TIME_print(bio.get(), t)) return "?";
    char* data = nullptr;
    const long n = BIO_get_mem_data(bio.get(), &data);
    return std::string(data, static_cast<std::size_t>(n));
}

/// The reason of the oldest OpenSSL error queued, then clears the queue.
std::string openssl_reason() {
    const unsigned long e = ERR_peek_error();
    std::string out;
    if (e) {
        const char* reason = ERR_reason_error_string(e);
        out = reason ? reason : fmt::format("OpenSSL error {:#x}", e);
    }
    ERR_clear_error();
    return out.empty() ? "unknown TLS error" : out;
}

std::optional<std::string> unreadable(const std::string& what, const std::string& path) {
    if (path.empty()) return std::nullopt;
    if (::access(path.c_str(), R_OK) != 0) return fmt::format("cannot read the {} {}", what, path);
    return std::nullopt;
}

/// A TCP socket connected to host:port within `timeout`, or -1.
int connect_tcp(const std::string& host, int port, std::chrono::milliseconds timeout) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0) return -1;
    int fd = -1;
    for (addrinfo* a = found; a && fd < 0; a = a->ai_next) {
        fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
        if (fd < 0) continue;
        const int flags = ::fcntl(fd, F_GETFL);
        ::fcntl(fd, F_SETFL, flags | O_NONBLOCK);
        bool ok = ::connect(fd, a->ai_addr, a->ai_addrlen) == 0;
        if (!ok && errno == EINPROGRESS) {
            pollfd p{fd, POLLOUT, 0};
            int err = 0;
            socklen_t len = sizeof err;
            ok = ::poll(&p, 1, static_cast<int>(timeout.count())) == 1 &&
                 ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len) == 0 && err == 0;
        }
        ::fcntl(fd, F_SETFL, flags);
        if (!ok) {
            ::close(fd);
            fd = -1;
        }
    }
    ::freeaddrinfo(found);
    if (fd >= 0) {
        timeval tv{static_cast<time_t>(timeout.count() / 1000), static_cast<suseconds_t>((timeout.count() % 1000) * 1000)};
        ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    }
    return fd;
}

bool is_ip_literal(const std::string& host) {
    unsigned char buf[sizeof(in6_addr)];
    return ::inet_pton(AF_INET, host.c_str(), buf) == 1 || ::inet_pton(AF_INET6, host.c_str(), buf) == 1;
}

}  // namespace

std::optional<std::string> tls_file_problem(const MqttTlsOptions& tls) {
    if (auto p = unreadable("CA file", tls.ca_file)) return p;
    if (auto p = unreadable("client certificate", tls.cert_file)) return p;
    if (auto p = unreadable("client key", tls.key_file)) return p;
    if (!tls.ca_file.empty()) {
        Bio bio(BIO_new_file(tls.ca_file.c_str(), "r"));
        X509Ptr ca(bio ? PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr) : nullptr);
        ERR_clear_error();
        if (!ca) return fmt::format("the CA file {} holds no PEM certificate", tls.ca_file);
    }
    if (tls.cert_file.empty()) return std::nullopt;
    Bio bio(BIO_new_file(tls.cert_file.c_str(), "r"));
    X509Ptr cert(bio ? PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr) : nullptr);
    ERR_clear_error();
    if (!cert) return fmt::format("the client certificate {} is not a PEM certificate", tls.cert_file);
    if (X509_cmp_current_time(X509_get0_notAfter(cert.get())) <= 0)
        return fmt::format("the client certificate {} expired on {}", tls.cert_file,
                           asn1_time_text(X509_get0_notAfter(cert.get())));
    if (X509_cmp_current_time(X509_get0_notBefore(cert.get())) > 0)
        return fmt::format("the client certificate {} is not valid before {}", tls.cert_file,
                           asn1_time_text(X509_get0_notBefore(cert.get())));
    return std::nullopt;
}

std::optional<std::string> tls_handshake_problem(const std::string& host, int port, const MqttTlsOptions& tls,
                                                 std::chrono::milliseconds timeout) {
    ERR_clear_error();
    Ctx ctx(SSL_CTX_new(TLS_client_method()));
    if (!ctx) return "cannot set up TLS: " + openssl_reason();
    if (!tls.ca_file.empty()) {
        if (SSL_CTX_load_verify_locations(ctx.get(), tls.ca_file.c_str(), nullptr) != 1)
            return fmt::format("cannot load the CA file {}: {}", tls.ca_file, openssl_reason());
    } else {
        SSL_CTX_set_default_verify_paths(ctx.get());
    }
    if (!tls.key_password.empty()) SSL_CTX_set_default_passwd_cb_userdata(ctx.get(), const_cast<char*>(tls.key_password.c_str()));
    if (!tls.cert_file.empty() && SSL_CTX_use_certificate_chain_file(ctx.get(), tls.cert_file.c_str()) != 1)
        return fmt::format("cannot load the client certificate {}: {}", tls.cert_file, openssl_reason());
    const std::string& key = tls.key_file.empty() ? tls.cert_file : tls.key_file;
    if (!key.empty() && SSL_CTX_use_PrivateKey_file(ctx.get(), key.c_str(), SSL_FILETYPE_PEM) != 1)
        return fmt::format("cannot load the client key {}: {}", key, openssl_reason());
    if (!key.empty() && SSL_CTX_check_private_key(ctx.get()) != 1)
        return fmt::format("the client key {} does not match the certificate {}", key, tls.cert_file);
    SSL_CTX_set_verify(ctx.get(), tls.verify_server ? SSL_VERIFY_PEER : SSL_VERIFY_NONE, nullptr);

    const int fd = connect_tcp(host, port, timeout);
    if (fd < 0) return std::nullopt;  // not a TLS problem: the broker is not reachable
    Ssl ssl(SSL_new(ctx.get()));
    if (!ssl) {
        ::close(fd);
        return "cannot set up TLS: " + openssl_reason();
    }
    SSL_set_fd(ssl.get(), fd);
    if (!is_ip_literal(host)) SSL_set_tlsext_host_name(ssl.get(), host.c_str());
    if (tls.verify_server) {
        if (is_ip_literal(host)) X509_VERIFY_PARAM_set1_ip_asc(SSL_get0_param(ssl.get()), host.c_str());
        else SSL_set1_host(ssl.get(), host.c_str());
    }
    std::optional<std::string> problem;
    if (SSL_connect(ssl.get()) != 1) {
        const long verify = SSL_get_verify_result(ssl.get());
        if (tls.verify_server && verify != X509_V_OK)
            problem = fmt::format("the broker's certificate did not verify: {}", X509_verify_cert_error_string(verify));
        else problem = "the TLS handshake failed: " + openssl_reason();
    } else {
        // TLS 1.3: the broker judges our certificate after our side of the
        // handshake is done; its verdict (an alert) is the first thing read.
        // A broker content with it waits for CONNECT: nothing comes, and a
        // short wait ends the check.
        timeval tv{0, 500000};
        ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        char byte = 0;
        const int got = SSL_read(ssl.get(), &byte, 1);
        if (got <= 0 && SSL_get_error(ssl.get(), got) == SSL_ERROR_SSL)
            problem = "the broker refused our certificate: " + openssl_reason();
        else SSL_shutdown(ssl.get());
    }
    ERR_clear_error();
    ::close(fd);
    return problem;
}

}  // namespace nclink::transport_detail
