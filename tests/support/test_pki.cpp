#include "support/test_pki.hpp"

#include "support/mosquitto_broker.hpp"

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace nclink::test {
namespace {

bool on_path(const std::string& program) { return std::system(("command -v " + program + " >/dev/null 2>&1").c_str()) == 0; }

std::string shell_quoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

}  // namespace

std::optional<std::string> tls_tools_missing() {
    if (!on_path("openssl")) return "openssl not found (tools/install-deps.sh installs it)";
    if (!on_path("mosquitto_passwd")) return "mosquitto_passwd not found (package mosquitto)";
    for (const char* path : {"/usr/sbin/mosquitto", "/usr/bin/mosquitto", "/usr/local/sbin/mosquitto"})
        if (::access(path, X_OK) == 0) return std::nullopt;
    return "mosquitto not found (tools/install-deps.sh installs it)";
}

Command run_command(const std::string& command) {
    Command run;
    std::FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
    if (pipe == nullptr) return run;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, n);
    const int status = ::pclose(pipe);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
}

TestPki::TestPki(const std::vector<std::string>& client_names) {
    char pattern[] = "/tmp/nclink-pki-XXXXXX";
    if (!::mkdtemp(pattern)) throw std::runtime_error("mkdtemp failed");
    dir_ = pattern;
    // mosquitto started as root reads its files as user mosquitto.
    ::chmod(dir_.c_str(), 0755);
    std::string command =
        "bash " + shell_quoted(std::string(NCLINK_TEST_SUPPORT_DIR) + "/make-test-pki.sh") + " " + shell_quoted(dir_);
    for (const auto& name : client_names) command += " " + shell_quoted(name);
    const Command made = run_command(command);
    if (made.status != 0) throw std::runtime_error("making the test PKI failed:\n" + made.output);
}

TestPki::~TestPki() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
}

std::string TestPki::password_file(const std::map<std::string, std::string>& users) const {
    static int counter = 0;
    const std::string path = dir_ + "/passwd-" + std::to_string(++counter);
    { std::ofstream create(path); }
    for (const auto& [user, password] : users) {
        const Command added =
            run_command("mosquitto_passwd -b " + shell_quoted(path) + " " + shell_quoted(user) + " " + shell_quoted(password));
        if (added.status != 0) throw std::runtime_error("mosquitto_passwd failed: " + added.output);
    }
    ::chmod(path.c_str(), 0644);  // mosquitto_passwd leaves it 0600; the broker reads it as user mosquitto
    return path;
}

std::string tls_listener_config(const TestPki& pki, TlsListener& listener) {
    if (listener.port == 0) listener.port = free_loopback_port();
    std::ostringstream out;
    out << "listener " << listener.port << " 127.0.0.1\n"
        << "cafile " << pki.file("ca.pem") << "\n"
        << "certfile " << pki.file(listener.server_certificate) << "\n"
        << "keyfile " << pki.file("server.key") << "\n";
    if (listener.require_certificate) out << "require_certificate true\nuse_identity_as_username true\n";
    return out.str();
}

}  // namespace nclink::test
