// Security end to end (docs/security.md) against a real mosquitto with a TLS
// listener, a password file and the ACL nclink-agent generates: certificates
// made by openssl at test time (support/test_pki.hpp). The adapter (the
// simulated mill), the agent, the client library and the CLI connect with
// server verification and with mutual TLS; a wrong CA, an expired
// certificate and a bad password each end in one clear line and a non-zero
// exit; the broker and the agent keep applications away from what they have
// no right to, and from everything when they did not register.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>

#include "support/inbox.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/test_pki.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

const std::string kDev = kSimMillDevice;
const std::string kAgentUser = "nclink-agent";

std::string password_of(const std::string& user) { return "pw-" + user; }

/// Every terminal of these tests has a certificate (CN = its terminal id).
TestPki& pki() {
    static TestPki made({kDev, kAgentUser, "mes", "viewer", "outsider"});
    return made;
}

bool skip_without_tools() {
    if (auto missing = tls_tools_missing()) {
        WARN("TLS tests skipped: " << *missing);
        return true;
    }
    return false;
}

std::string program(const std::string& name) { return std::string(NCLINK_BINARY_DIR) + "/bin/" + name; }
bool built(const std::string& name) { return ::access(program(name).c_str(), X_OK) == 0; }

/// The last non-empty line a program wrote.
std::string last_line(const std::string& output) {
    std::string text = output;
    while (!text.empty() && text.back() == '\n') text.pop_back();
    const auto nl = text.rfind('\n');
    return nl == std::string::npos ? text : text.substr(nl + 1);
}

/// The deployment of docs/security.md: the agent's access policy (viewer
/// reads only; mes does everything; registration closed to the listed
/// terminals, so "outsider", with a broker account, is not one of them), the
/// ACL generated from it, passwords for every terminal, and a TLS listener
/// with server verification or mutual TLS (the certificate's CN is the user).
struct Site {
    explicit Site(bool mutual_tls, std::string server_certificate = "server.pem")
        : mutual(mutual_tls), scratch("nclink-itest-security-") {
        std::filesystem::create_directories(scratch.path);
        policy.access.default_rights = access_read;
        policy.access.applications["viewer"]["*"] = access_read;
        policy.access.applications["mes"]["*"] = access_all;
        policy.registration.open = false;
        policy.registration.terminals[kDev] = TerminalEntry{"adapter", ""};
        policy.registration.terminals["mes"] = TerminalEntry{"application", ""};
        policy.registration.terminals["viewer"] = TerminalEntry{"application", ""};
        policy.acl_agent_user = kAgentUser;
        const std::string acl = (scratch.path / "nclink.acl").string();
        std::ofstream(acl) << mosquitto_acl(policy);

        MosquittoOptions options;
        options.acl_file = acl;
        std::map<std::string, std::string> users;
        for (const auto& user : {kDev, kAgentUser, std::string("mes"), std::string("viewer"), std::string("outsider")})
            users[user] = password_of(user);
        options.password_file = pki().password_file(users);
        listener.require_certificate = mutual;
        listener.server_certificate = std::move(server_certificate);
        options.extra_config = tls_listener_config(pki(), listener);
        broker = std::make_unique<MosquittoBroker>(options);
    }

    /// ssl:// with the address the broker's certificate names (IP SAN).
    std::string url() const { return "ssl://127.0.0.1:" + std::to_string(listener.port); }

    /// TLS options of terminal `user`: the test CA, and with mutual TLS its certificate.
    MqttTlsOptions tls(const std::string& user, const std::string& ca = "ca.pem") const {
        MqttTlsOptions t;
        t.ca_file = pki().file(ca);
        if (mutual) {
            t.cert_file = pki().file(user + ".pem");
            t.key_file = pki().file(user + ".key");
        }
        return t;
    }
    /// Broker credentials of `user` (mutual TLS: the certificate is the credential).
    void credentials(const std::string& user, MqttOptions& m) const {
        m.broker_url = url();
        m.username = user;
        if (!mutual) m.password = password_of(user);
        m.tls = tls(user);
    }
    /// The CLI's connection options for `user`.
    std::string cli_options(const std::string& user) const {
        std::string out = "--broker " + url() + " --device " + kDev + " --client-id " + user + " --username " + user +
                          " --ca-file " + pki().file("ca.pem") + " --timeout 10000";
        if (mutual) return out + " --cert " + pki().file(user + ".pem") + " --key " + pki().file(user + ".key");
        const std::string file = (scratch.path / ("password-" + user)).string();
        std::ofstream(file) << password_of(user) << "\n";
        return out + " --password-file " + file;
    }

    std::unique_ptr<Agent> start_agent() {
        AgentConfig c = policy;
        c.broker_url = url();
        c.client_id = "agent-a";
        c.username = kAgentUser;
        if (!mutual) c.password = password_of(kAgentUser);
        c.tls = tls(kAgentUser);
        c.request_timeout = 3000ms;
        auto agent = std::make_unique<Agent>(std::move(c));
        REQUIRE(agent->start().ok());
        REQUIRE(eventually([&] { return agent->stats().transport.connects >= 1; }, 20s));
        std::this_thread::sleep_for(300ms);  // SUBACKs come asynchronously
        return agent;
    }

    std::unique_ptr<Adapter> start_adapter() {
        AdapterConfig c;
        c.broker_url = url();
        c.username = kDev;
        if (!mutual) c.password = password_of(kDev);
        c.tls = tls(kDev);
        c.model_path = sim_mill_path();
        c.persistence_dir = (scratch.path / "adapter").string();
        c.register_timeout = 500ms;
        sim = sim_for(c.model_path);
        auto adapter = started_adapter(c, sim);
        REQUIRE(eventually([&] { return adapter->stats().transport.connects >= 1; }, 20s));
        return adapter;
    }

    std::unique_ptr<Client> start_client(const std::string& user) {
        return started_client(url(), user, 10s, [&](MqttOptions& m, ClientOptions&) { credentials(user, m); });
    }

    bool mutual;
    ScratchDir scratch;
    AgentConfig policy;
    TlsListener listener;
    std::unique_ptr<MosquittoBroker> broker;
    std::shared_ptr<SimDriver> sim;
};

/// The current value of `item`, read through `client`.
Json value_of(Client& client, const std::string& item) {
    auto read = client.query(kDev, {QueryItem{item, std::nullopt}});
    REQUIRE(read.ok());
    REQUIRE((*read)[0].values);
    return *(*read)[0].values;
}

/// The code an NG answer carries, however the client reports it.
int error_of(const Result<std::vector<SetResult>>& r) {
    if (!r) return to_int(r.error().code);
    return r->empty() || r->front().status.ok ? 0 : r->front().status.error.value_or(-1);
}

void everyone_connects(bool mutual) {
    Site site(mutual);
    auto agent = site.start_agent();
    auto adapter = site.start_adapter();
    REQUIRE(eventually([&] { return adapter->stats().registered; }, 20s));  // through the agent, over TLS

    auto mes = site.start_client("mes");
    auto registered = mes->register_terminal();
    REQUIRE(registered.ok());
    CHECK(registered->kind == RegisterOutcome::Kind::accepted);
    auto read = mes->query(kDev, {QueryItem{"x_position", std::nullopt}});
    REQUIRE(read.ok());
    CHECK((*read)[0].status.ok);

    mes->stop();  // the CLI below connects as mes: one connection per client id
    if (!built("nclink")) {
        WARN("bin/nclink not built (target nclink_cli): its TLS connection not tested");
    } else {
        const Command cli = run_command(program("nclink") + " query " + site.cli_options("mes") + " x_position");
        INFO(cli.output);
        CHECK(cli.status == 0);
        CHECK(cli.output.find("x_position = ") != std::string::npos);
    }
    adapter->stop();
    agent->stop();
}

}  // namespace

TEST_CASE("TLS with server verification and passwords: adapter, agent, client and CLI connect") {
    if (skip_without_tools()) return;
    everyone_connects(false);
}

TEST_CASE("mutual TLS: adapter, agent, client and CLI connect with their certificates") {
    if (skip_without_tools()) return;
    everyone_connects(true);
}

TEST_CASE("a wrong CA, expired certificates and a bad password: one clear line and a non-zero exit") {
    if (skip_without_tools()) return;
    Site site(true);
    Site expired_broker(false, "server-expired.pem");
    const std::string ca = pki().file("ca.pem");

    SECTION("the client library says why") {
        auto refused = [&](const std::string& url, MqttTlsOptions tls, const std::string& user, const std::string& password) {
            MqttOptions m;
            m.broker_url = url;
            m.username = user;
            m.password = password;
            m.tls = std::move(tls);
            ClientOptions o;
            o.ex_cid = user;
            auto client = Client::create(std::move(m), std::move(o)).value();
            auto connected = client->connect(10s);
            REQUIRE_FALSE(connected.ok());
            CHECK(connected.error().code == ErrorCode::permission_denied);
            CHECK(client->stats().transport.refused);
            return connected.error().message;
        };
        CHECK_THAT(refused(site.url(), site.tls("mes", "other-ca.pem"), "mes", ""),
                   Catch::Contains("the broker's certificate did not verify: "));
        CHECK_THAT(refused(expired_broker.url(), expired_broker.tls("mes"), "mes", password_of("mes")),
                   Catch::Contains("the broker's certificate did not verify: certificate has expired"));
        MqttTlsOptions expired_client = site.tls("mes");
        expired_client.cert_file = pki().file("mes-expired.pem");
        CHECK_THAT(refused(site.url(), expired_client, "mes", ""), Catch::Contains("mes-expired.pem expired on"));
    }

    SECTION("the CLI, nclink-agent and nclink-sim exit with the reason") {
        Site passwords(false);
        struct Case {
            std::string what, broker, tls_args, user, password, expect;
        };
        const std::string mes_cert = " --cert " + pki().file("mes.pem") + " --key " + pki().file("mes.key");
        const std::vector<Case> cases = {
            {"wrong CA", site.url(), "--ca-file " + pki().file("other-ca.pem") + mes_cert, "mes", "",
             "the broker's certificate did not verify: "},
            {"expired broker certificate", expired_broker.url(), "--ca-file " + ca, "mes", password_of("mes"),
             "the broker's certificate did not verify: certificate has expired"},
            {"expired client certificate", site.url(),
             "--ca-file " + ca + " --cert " + pki().file("mes-expired.pem") + " --key " + pki().file("mes.key"), "mes", "",
             "mes-expired.pem expired on"},
            {"bad password", passwords.url(), "--ca-file " + ca, "mes", "not-the-password",
             "the broker refused the connection: not authorized"},
        };
        for (const auto& c : cases) {
            if (!built("nclink")) {
                WARN("bin/nclink not built (target nclink_cli): its exits not tested");
                break;
            }
            INFO(c.what);
            const std::string pw_file = (site.scratch.path / "cli-password").string();
            std::ofstream(pw_file) << c.password << "\n";
            const Command cli = run_command(program("nclink") + " query --broker " + c.broker + " --device " + kDev +
                                            " --client-id " + c.user + " --username " + c.user + " --password-file " + pw_file +
                                            " --timeout 10000 " + c.tls_args + " x_position");
            INFO(cli.output);
            CHECK(cli.status == 1);
            CHECK(std::count(cli.output.begin(), cli.output.end(), '\n') == 1);  // one line, nothing else
            CHECK_THAT(cli.output, Catch::StartsWith("nclink query: cannot connect to " + c.broker + ": "));
            CHECK_THAT(cli.output, Catch::Contains(c.expect));
        }

        // The agent and the adapter program with a bad password, and with a wrong CA.
        for (const bool bad_password : {true, false}) {
            if (!built("nclink-agent") || !built("nclink-sim")) {
                WARN("bin/nclink-agent or bin/nclink-sim not built: their exits not tested");
                break;
            }
            INFO((bad_password ? "bad password" : "wrong CA"));
            const std::string tls = Json{{"ca_file", pki().file(bad_password ? "ca.pem" : "other-ca.pem")}}.dump();
            const std::string agent_conf = (site.scratch.path / "agent.json").string();
            std::ofstream(agent_conf) << R"({"broker": {"url": ")" << passwords.url()
                                      << R"(", "username": "nclink-agent", "password": "nope", "tls": )" << tls << "}}";
            const Command agent = run_command(program("nclink-agent") + " --config " + agent_conf);
            INFO(agent.output);
            CHECK(agent.status == 1);
            CHECK_THAT(last_line(agent.output), Catch::StartsWith("nclink-agent: cannot connect to " + passwords.url()));
            CHECK_THAT(last_line(agent.output),
                       Catch::Contains(bad_password ? "not authorized" : "the broker's certificate did not verify"));

            const std::string sim_conf = (site.scratch.path / "sim.json").string();
            std::ofstream(sim_conf) << R"({"broker": {"url": ")" << passwords.url() << R"(", "username": ")" << kDev
                                    << R"(", "password": "nope", "tls": )" << tls << R"(}, "model": ")" << sim_mill_path()
                                    << R"(", "persistence_dir": ")" << (site.scratch.path / "sim").string() << R"("})";
            const Command sim = run_command(program("nclink-sim") + " --config " + sim_conf);
            INFO(sim.output);
            CHECK(sim.status == 1);
            CHECK_THAT(last_line(sim.output), Catch::StartsWith("nclink-sim: cannot connect to " + passwords.url()));
            CHECK_THAT(last_line(sim.output),
                       Catch::Contains(bad_password ? "not authorized" : "the broker's certificate did not verify"));
        }
    }
}

TEST_CASE("the generated ACL keeps an application from Set, methods and Sample topics it has no right to") {
    if (skip_without_tools()) return;
    Site site(false);
    auto agent = site.start_agent();
    auto adapter = site.start_adapter();
    REQUIRE(eventually([&] { return adapter->stats().registered; }, 20s));
    auto viewer = site.start_client("viewer");
    REQUIRE(viewer->register_terminal().ok());
    auto mes = site.start_client("mes");
    REQUIRE(mes->register_terminal().ok());

    // Sample topics: viewer may read them (its right), "outsider" may not
    // (not registered: no default rights for it in the ACL).
    MqttOptions m;
    site.credentials("outsider", m);
    m.client_id = "outsider";
    auto outsider = make_mqtt_transport(m).value();
    Inbox outsider_inbox;
    outsider_inbox.attach(*outsider);
    REQUIRE(outsider->subscribe({"Sample/#"}, 1).ok());
    REQUIRE(outsider->start().ok());
    REQUIRE(eventually([&] { return outsider->state() == LinkState::connected; }, 20s));
    std::atomic<int> viewer_samples{0};
    REQUIRE(viewer->subscribe_samples(kDev, [&](const SampleDtu&) { ++viewer_samples; }).ok());
    REQUIRE(eventually([&] { return viewer_samples > 3; }, 20s));
    std::this_thread::sleep_for(300ms);
    {
        std::lock_guard<std::mutex> lock(outsider_inbox.mutex);
        CHECK(outsider_inbox.messages.empty());
    }

    const Json before = value_of(*mes, "feed_override");
    const auto requests_before = adapter->stats().requests;
    const auto denied_before = agent->stats().denied;
    // Set: the agent answers 301 and the broker keeps the request from the adapter.
    auto set = viewer->set(kDev, {SetItem{"feed_override", Json{{"value", 42}}, std::nullopt, std::nullopt}});
    CHECK(error_of(set) == 301);
    // A method: the same.
    auto call = viewer->call_method(kDev, "feed_hold", Json::object());
    if (call.ok()) CHECK(call->status.error == 301);
    else CHECK(call.error().code == ErrorCode::permission_denied);
    std::this_thread::sleep_for(500ms);
    CHECK(adapter->stats().requests == requests_before);
    CHECK(agent->stats().denied == denied_before + 2);
    CHECK(value_of(*mes, "feed_override") == before);

    // What viewer may do still works, and mes may do the rest.
    auto read = viewer->query(kDev, {QueryItem{"x_position", std::nullopt}});
    REQUIRE(read.ok());
    CHECK((*read)[0].status.ok);
    auto allowed = mes->set(kDev, {SetItem{"feed_override", Json{{"value", 42}}, std::nullopt, std::nullopt}});
    REQUIRE(allowed.ok());
    CHECK((*allowed)[0].status.ok);

    // Posing as mes on its request topic is stopped by the broker (%u).
    REQUIRE(outsider
                ->publish(Message{
                    topics::set_request(kDev, "mes"),
                    Json{{"@id", "spoof"}, {"values", {{{"id", "feed_override"}, {"params", {{"value", 7}}}}}}}.dump(), 1, false})
                .ok());
    std::this_thread::sleep_for(500ms);
    CHECK(value_of(*mes, "feed_override") != Json::array({7}));
    outsider->stop();
    viewer->stop();
    mes->stop();
    adapter->stop();
    agent->stop();
}

TEST_CASE("registration required: an unregistered application is refused") {
    if (skip_without_tools()) return;
    Site site(true);
    auto agent = site.start_agent();
    auto adapter = site.start_adapter();
    REQUIRE(eventually([&] { return adapter->stats().registered; }, 20s));

    // "outsider" has a certificate the broker accepts, but is not on the
    // agent's registration allowlist.
    auto outsider = site.start_client("outsider");
    auto registered = outsider->register_terminal();
    REQUIRE(registered.ok());
    CHECK(registered->kind == RegisterOutcome::Kind::refused);
    CHECK(registered->status.error == 301);

    const auto requests_before = adapter->stats().requests;
    auto read = outsider->query(kDev, {QueryItem{"x_position", std::nullopt}}, RequestOptions{});
    if (read.ok()) CHECK((*read)[0].status.error == 301);
    else CHECK(read.error().code == ErrorCode::permission_denied);
    std::this_thread::sleep_for(300ms);
    CHECK(adapter->stats().requests == requests_before);  // the broker did not pass it on either

    // A listed application that registered is served.
    auto mes = site.start_client("mes");
    REQUIRE(mes->register_terminal().ok());
    auto served = mes->query(kDev, {QueryItem{"x_position", std::nullopt}});
    REQUIRE(served.ok());
    CHECK((*served)[0].status.ok);
    outsider->stop();
    mes->stop();
    adapter->stop();
    agent->stop();
}
