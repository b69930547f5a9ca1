// Certificates for the TLS tests, made at test time by openssl into a
// scratch directory (support/make-test-pki.sh), and the mosquitto listener
// and password lines that use them.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace nclink::test {

/// Why the TLS tests cannot run here ("openssl not found", ...), or nullopt.
std::optional<std::string> tls_tools_missing();

class TestPki {
public:
    /// Makes a CA, a broker certificate (localhost, 127.0.0.1) and a client
    /// certificate per common name, each also in an expired version.
    /// Throws std::runtime_error (with openssl's output) on failure.
    explicit TestPki(const std::vector<std::string>& client_names);
    ~TestPki();
    TestPki(const TestPki&) = delete;
    TestPki& operator=(const TestPki&) = delete;

    const std::string& dir() const { return dir_; }
    /// A file of the PKI: "ca.pem", "other-ca.pem", "server.pem",
    /// "server-expired.pem", "<name>.pem", "<name>.key", "<name>-expired.pem".
    std::string file(const std::string& name) const { return dir_ + "/" + name; }

    /// A mosquitto password_file with these users and passwords (mosquitto_passwd).
    std::string password_file(const std::map<std::string, std::string>& users) const;

private:
    std::string dir_;
};

struct TlsListener {
    int port = 0;                                   ///< 0 = a free one (filled in)
    bool require_certificate = false;               ///< mutual TLS; the certificate's CN is the user name
    std::string server_certificate = "server.pem";  ///< or "server-expired.pem"
};

/// mosquitto configuration lines of a TLS listener (MosquittoOptions::extra_config).
std::string tls_listener_config(const TestPki& pki, TlsListener& listener);

/// Runs a shell command; its exit status and everything it wrote on stdout
/// and stderr (for asserting what a program tells its user).
struct Command {
    int status = -1;
    std::string output;
};
Command run_command(const std::string& command);

}  // namespace nclink::test
