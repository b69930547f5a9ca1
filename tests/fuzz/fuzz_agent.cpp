// Fuzz target for the agent's DTU decoding, end to end: an Agent on the
// in-process loopback broker gets the fuzz input on one of the topics it
// watches (the first byte picks which; its top bit marks it retained), then
// a Discovery round trip shows it processed the input (in order) and still
// answers. A crash, a sanitizer report or a wedged agent (no answer within
// 10 s) is a failure.
#include <nclink/agent.hpp>
#include <nclink/testing/loopback_transport.hpp>
#include <nclink/topics.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

namespace {

using namespace nclink;
using namespace std::chrono_literals;

const std::string kDev = "fz-dev";
const std::string kEx = "fz-app";
const std::string kSync = "fz-sync";

struct World {
    LoopbackBroker broker;
    std::unique_ptr<Agent> agent;
    std::unique_ptr<Transport> peer;
    std::mutex mutex;
    std::condition_variable answered;
    std::string last_answer;
    std::uint64_t round = 0;

    World() {
        LoopbackOptions po;
        po.client_id = "fz-peer";
        peer = make_loopback_transport(broker, po);
        peer->set_message_handler([this](const Message& m) {
            const Json dtu = Json::parse(m.payload, nullptr, false);
            std::lock_guard<std::mutex> lock(mutex);
            if (dtu.is_object() && dtu.contains("@id") && dtu["@id"].is_string()) last_answer = dtu["@id"].get<std::string>();
            answered.notify_all();
        });
        (void)peer->subscribe({topics::discovery_response(kSync)});
        if (!peer->start().ok()) std::abort();

        AgentConfig config;
        config.client_id = "fz-agent";
        config.request_timeout = 50ms;
        config.share_group.clear();  // the loopback broker has no shared subscriptions
        config.registration.terminals["fz-listed"] = TerminalEntry{"application", "pw"};
        config.access.applications["fz-viewer"]["*"] = access_read;
        agent = std::make_unique<Agent>(config, Logger{});
        LoopbackOptions ao;
        ao.client_id = "fz-agent";
        agent->use_transport(make_loopback_transport(broker, ao));
        if (!agent->start().ok()) std::abort();
    }

    void sync() {
        // Asked again each second: the first rounds may go out before the
        // agent's (asynchronous) subscription is in place.
        const std::string id = "sync-" + std::to_string(++round);
        for (int attempt = 0; attempt < 10; ++attempt) {
            (void)peer->publish(Message{topics::discovery_request(kSync), Json{{"@id", id}, {"guid", kSync}}.dump(), 1, false});
            std::unique_lock<std::mutex> lock(mutex);
            if (answered.wait_for(lock, 1s, [&] { return last_answer == id; })) return;
        }
        std::abort();  // the agent wedged: no answer for 10 s
    }
};

World& world() {
    static World* w = new World();  // never destroyed: libFuzzer exits without unwinding
    return *w;
}

std::string topic_for(int which) {
    switch (which) {
        case 0: return topics::register_request();
        case 1: return topics::discovery_request(kEx);
        case 2: return topics::probe_version(kDev);
        case 3: return topics::notify_state(kDev);
        case 4: return topics::query_request(kDev, kEx);
        case 5: return topics::query_response(kDev, kEx);
        case 6: return topics::probe_query_response(kDev, "nclink-agent");
        case 7: return topics::register_response(kDev);
        case 8: return topics::set_request(kDev, "fz-viewer");
        default: return topics::method_call(kDev, kEx);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    World& w = world();
    if (size == 0) return 0;
    const bool retained = (data[0] & 0x80) != 0;
    const std::string topic = topic_for((data[0] & 0x7f) % 10);
    const std::string payload(reinterpret_cast<const char*>(data + 1), size - 1);
    (void)w.peer->publish(Message{topic, payload, 1, retained});
    if (retained) (void)w.peer->publish(Message{topic, "", 1, true});  // clear it again
    w.sync();
    return 0;
}
