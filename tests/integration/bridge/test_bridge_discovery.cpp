// nclink-bridge without --device, as programs: mosquitto, the nclink-agent
// program, two nclink-sim programs built from the same model (two simulated
// mills with different terminal ids) and the nclink-bridge program. The
// bridge must find both adapters by itself, serve them in one MTConnect
// document with document-unique ids (validated with xmllint against the 1.4
// schemas), and follow an adapter that goes away and comes back.
//
// The second mill's retained Notify/State is cleared before the bridge starts,
// so the only way the bridge can learn of it is the agent's Discovery (8.2.3);
// the first mill is found through its retained state (8.2.16).
#include "integration/bridge/bridge_itest.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/topics.hpp>

#include <catch2/catch.hpp>
#include <httplib.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

extern char** environ;

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::encoded;
using nclink::test::eventually;
using nclink::test::validates;

namespace {

const std::string kMillA = "nclink-sim-mill-a";
const std::string kMillB = "nclink-sim-mill-b";

RequestOptions timeout(std::chrono::milliseconds ms) {
    RequestOptions o;
    o.timeout = ms;
    return o;
}

std::string bin(const std::string& name) { return std::string(NCLINK_BINARY_DIR) + "/bin/" + name; }

/// A program of the build, its output in `log`; killed (SIGKILL) and reaped on destruction.
class Program {
public:
    Program(const std::vector<std::string>& args, const std::string& log) {
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        posix_spawn_file_actions_adddup2(&actions, 1, 2);
        std::vector<char*> argv;
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        const int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        if (rc != 0) pid_ = -1;
    }
    ~Program() { stop(SIGKILL); }
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;

    bool running() const { return pid_ > 0; }
    /// Sends `signal` and waits until the program exited.
    void stop(int signal = SIGTERM) {
        if (pid_ <= 0) return;
        ::kill(pid_, signal);
        int status = 0;
        ::waitpid(pid_, &status, 0);
        pid_ = -1;
    }

private:
    pid_t pid_ = -1;
};

struct DiscoveryRig {
    DiscoveryRig() : scratch("nclink-itest-bridge-discovery-") {
        std::filesystem::create_directories(scratch.path);
        agent = std::make_unique<Program>(std::vector<std::string>{bin("nclink-agent"), "--broker", broker.url(), "--state-dir",
                                                                   (scratch.path / "agent").string()},
                                          log("agent"));
        REQUIRE(agent->running());
        // A client of the test that asks the agent what it knows (Discovery, 8.2.3).
        checker = nclink::test::started_client(broker.url(), "discovery-checker");
        REQUIRE(eventually([&] { return checker->discover(timeout(500ms)).ok(); }, 20s));
        start_mill(mill_a, kMillA);
        start_mill(mill_b, kMillB);
        REQUIRE(eventually([&] { return agent_says_online({kMillA, kMillB}); }, 20s));

        // Forget mill B's retained state: from now on only Discovery names it.
        MqttOptions m;
        m.broker_url = broker.url();
        m.client_id = "nclink-itest-state-cleaner";
        auto cleaner = make_mqtt_transport(m).value();
        REQUIRE(cleaner->start().ok());
        REQUIRE(eventually([&] { return cleaner->state() == LinkState::connected; }));
        REQUIRE(cleaner->publish(Message{topics::notify_state(kMillB), "", 1, true}).ok());
        std::this_thread::sleep_for(200ms);  // the QoS 1 publish reaches the broker before we disconnect
        cleaner->stop();

        http_port = nclink::test::free_loopback_port();
        shdr_port = nclink::test::free_loopback_port();
        bridge =
            std::make_unique<Program>(std::vector<std::string>{bin("nclink-bridge"), "--broker", broker.url(), "--http",
                                                               "127.0.0.1:" + std::to_string(http_port), "--shdr",
                                                               "127.0.0.1:" + std::to_string(shdr_port), "--buffer-size", "8192"},
                                      log("bridge"));
        REQUIRE(bridge->running());
        http = std::make_unique<httplib::Client>("127.0.0.1", http_port);
        http->set_read_timeout(10, 0);
    }
    ~DiscoveryRig() {
        bridge.reset();
        checker->stop();
        mill_a.reset();
        mill_b.reset();
        agent.reset();
    }

    std::string log(const std::string& name) const { return (scratch.path / (name + ".log")).string(); }

    void start_mill(std::unique_ptr<Program>& mill, const std::string& guid) {
        mill = std::make_unique<Program>(std::vector<std::string>{bin("nclink-sim"), "--broker", broker.url(), "--guid", guid},
                                         log(guid));
        REQUIRE(mill->running());
    }

    bool agent_says_online(const std::set<std::string>& wanted) {
        auto list = checker->discover(timeout(1000ms));
        if (!list) return false;
        std::set<std::string> online;
        for (const auto& e : *list)
            if (e.status == "online") online.insert(e.guid);
        for (const auto& w : wanted)
            if (!online.count(w)) return false;
        return true;
    }

    std::string get(const std::string& path) {
        auto r = http->Get(path.c_str());
        return r && r->status == 200 ? r->body : std::string();
    }

    /// The text of the Availability observation of `dev` in a Streams document.
    static std::string availability(const std::string& streams, const std::string& dev) {
        std::smatch m;
        const std::regex re("<Availability dataItemId=\"" + dev + "\\.[^\"]*_avail\"[^>]*>([A-Z]+)</Availability>");
        return std::regex_search(streams, m, re) ? std::string(m[1]) : std::string();
    }

    nclink::test::MosquittoBroker broker;
    nclink::test::ScratchDir scratch;
    std::unique_ptr<Program> agent, mill_a, mill_b, bridge;
    std::unique_ptr<Client> checker;
    int http_port = 0, shdr_port = 0;
    std::unique_ptr<httplib::Client> http;
};

std::vector<std::string> all_matches(const std::string& text, const std::string& pattern) {
    std::vector<std::string> out;
    const std::regex re(pattern);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
        out.push_back((*it)[1]);
    return out;
}

/// Every value of an ID-typed attribute (id in Devices; none in Streams) is unique.
bool ids_unique(const std::string& xml, const std::string& attribute) {
    const auto ids = all_matches(xml, " " + attribute + "=\"([^\"]*)\"");
    return !ids.empty() && std::set<std::string>(ids.begin(), ids.end()).size() == ids.size();
}

}  // namespace

TEST_CASE("bridge without devices follows every adapter the agent discovers, two mills of one model in one document") {
    DiscoveryRig rig;
    std::string current;
    REQUIRE(eventually(
        [&] {
            current = rig.get("/current");
            return DiscoveryRig::availability(current, kMillA) == "AVAILABLE" &&
                   DiscoveryRig::availability(current, kMillB) == "AVAILABLE";
        },
        30s));

    // Both devices in /probe; the ids of the one document are unique, and it validates.
    const std::string probe = rig.get("/probe");
    REQUIRE_FALSE(probe.empty());
    CHECK(probe.find("uuid=\"" + kMillA + "\"") != std::string::npos);
    CHECK(probe.find("uuid=\"" + kMillB + "\"") != std::string::npos);
    CHECK(ids_unique(probe, "id"));
    CHECK(probe.find(" id=\"" + kMillA + ".x_position\"") != std::string::npos);
    CHECK(probe.find(" id=\"" + kMillB + ".x_position\"") != std::string::npos);
    CHECK(validates(probe, "Devices"));
    CHECK(validates(rig.get("/" + kMillB + "/probe"), "Devices"));

    // /current: both DeviceStreams, valid, values of both mills.
    REQUIRE(eventually([&] {
        current = rig.get("/current?path=" + encoded("//DataItem[@type=\"POSITION\"]"));
        return current.find("dataItemId=\"" + kMillA + ".x_position\"") != std::string::npos &&
               current.find("dataItemId=\"" + kMillB + ".x_position\"") != std::string::npos &&
               current.find(">UNAVAILABLE</Position>") == std::string::npos;
    }));
    current = rig.get("/current");
    CHECK(current.find("<DeviceStream name=") != current.rfind("<DeviceStream name="));  // two of them
    CHECK(current.find("uuid=\"" + kMillA + "\"") != std::string::npos);
    CHECK(current.find("uuid=\"" + kMillB + "\"") != std::string::npos);
    CHECK(validates(current, "Streams"));
    CHECK(validates(rig.get("/sample?count=500"), "Streams"));

    // path= by a document id selects exactly that device's item.
    const std::string one = rig.get("/current?path=" + encoded("//DataItem[@id=\"" + kMillB + ".x_position\"]"));
    CHECK(all_matches(one, "dataItemId=\"([^\"]*)\"") == std::vector<std::string>{kMillB + ".x_position"});
    CHECK(validates(one, "Streams"));
    // The per-device form names a device by its uuid.
    const std::string only_b = rig.get("/" + kMillB + "/current");
    CHECK(only_b.find("uuid=\"" + kMillB + "\"") != std::string::npos);
    CHECK(only_b.find("uuid=\"" + kMillA + "\"") == std::string::npos);

    // SHDR carries both devices under distinct keys.
    {
        int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(static_cast<std::uint16_t>(rig.shdr_port));
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
        std::string text;
        const auto deadline = std::chrono::steady_clock::now() + 10s;
        auto both = [&] {
            return text.find(":" + kMillA + ".x_position|") != std::string::npos &&
                   text.find(":" + kMillB + ".x_position|") != std::string::npos;
        };
        while (!both() && std::chrono::steady_clock::now() < deadline) {
            pollfd p{fd, POLLIN, 0};
            if (::poll(&p, 1, 100) <= 0) continue;
            char buffer[4096];
            const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
            if (n <= 0) break;
            text.append(buffer, static_cast<std::size_t>(n));
        }
        ::close(fd);
        CHECK(both());
    }

    // Mill B goes away (killed: the broker sends its last will): only its items turn UNAVAILABLE.
    rig.mill_b->stop(SIGKILL);
    REQUIRE(eventually(
        [&] {
            current = rig.get("/current");
            return DiscoveryRig::availability(current, kMillB) == "UNAVAILABLE";
        },
        20s));
    CHECK(DiscoveryRig::availability(current, kMillA) == "AVAILABLE");
    const std::string b_positions = rig.get("/" + kMillB + "/current?path=" + encoded("//DataItem[@type=\"POSITION\"]"));
    CHECK(b_positions.find(">UNAVAILABLE</Position>") != std::string::npos);
    CHECK(validates(current, "Streams"));

    // ... and comes back: available again, with values.
    rig.start_mill(rig.mill_b, kMillB);
    REQUIRE(eventually(
        [&] {
            current = rig.get("/" + kMillB + "/current?path=" + encoded("//DataItem[@id=\"" + kMillB + ".x_position\"]"));
            return DiscoveryRig::availability(rig.get("/current"), kMillB) == "AVAILABLE" &&
                   current.find("<Position") != std::string::npos && current.find(">UNAVAILABLE</Position>") == std::string::npos;
        },
        30s));
    CHECK(validates(rig.get("/probe"), "Devices"));
}
