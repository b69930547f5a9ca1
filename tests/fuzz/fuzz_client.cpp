// Fuzz target for the client library's DTU decoding, end to end: a Client on
// the in-process loopback broker, a fake adapter/agent answering its
// requests with the fuzz input. The first byte picks what the input is (the
// answer to a Query, Set, Probe/Query, Register, Discovery, Method/Call, or
// a Sample DTU, Notify/State or Event arriving unasked); the rest is the
// payload, with every "@ID@" replaced by the request's real @id so answers
// are matched and decoded. After each input a well-formed exchange makes
// sure the client processed it (one dispatch thread, in order) and still
// works.
#include <nclink/client.hpp>
#include <nclink/testing/loopback_transport.hpp>
#include <nclink/topics.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

namespace {

using namespace nclink;
using namespace std::chrono_literals;

const std::string kDev = "fz-dev";
const std::string kEx = "fz-app";

/// The fake peer: records the @id of each request the client sends.
struct Peer {
    std::mutex mutex;
    std::condition_variable seen;
    std::string last_topic, last_id;
    std::uint64_t requests = 0;
    std::unique_ptr<Transport> transport;

    void on_message(const Message& m) {
        const Json dtu = Json::parse(m.payload, nullptr, false);
        std::lock_guard<std::mutex> lock(mutex);
        last_topic = m.topic;
        last_id.clear();
        if (dtu.is_object() && dtu.contains("@id") && dtu["@id"].is_string()) last_id = dtu["@id"].get<std::string>();
        ++requests;
        seen.notify_all();
    }
    /// Waits for the request after `before` and returns its @id ("" on timeout).
    std::string wait_request(std::uint64_t before) {
        std::unique_lock<std::mutex> lock(mutex);
        if (!seen.wait_for(lock, 5s, [&] { return requests > before; })) return {};
        return last_id;
    }
    std::uint64_t count() {
        std::lock_guard<std::mutex> lock(mutex);
        return requests;
    }
    void send(const std::string& topic, const std::string& payload) {
        (void)transport->publish(Message{topic, payload, 1, false});
    }
};

struct World {
    LoopbackBroker broker;
    Peer peer;
    std::unique_ptr<Client> client;

    World() {
        LoopbackOptions po;
        po.client_id = "fz-peer";
        peer.transport = make_loopback_transport(broker, po);
        peer.transport->set_message_handler([this](const Message& m) { peer.on_message(m); });
        (void)peer.transport->subscribe({"Query/Request/#", "Set/Request/#", "Probe/Query/Request/#", "Method/Call/#",
                                         "Register/Request", "Discovery/Request/#"});
        if (!peer.transport->start().ok()) std::abort();
        LoopbackOptions co;
        co.client_id = kEx;
        ClientOptions options;
        options.ex_cid = kEx;
        options.default_timeout = 2s;  // only when neither the input nor the sync answer matched
        client = Client::create(make_loopback_transport(broker, co), options).value();
        if (!client->start().ok()) std::abort();
        (void)client->wait_connected(5s);
        (void)client->subscribe_samples(kDev, [](const SampleDtu&) {});
        (void)client->subscribe_state(kDev, [](const NotifyState&) {});
    }
};

World& world() {
    static World* w = new World();  // never destroyed: libFuzzer exits without unwinding
    return *w;
}

std::string with_id(std::string_view payload, const std::string& id) {
    std::string out(payload);
    for (std::size_t at = out.find("@ID@"); at != std::string::npos; at = out.find("@ID@", at + id.size()))
        out.replace(at, 4, id);
    return out;
}

/// Sends a request of kind `which`, answers it with `payload`, then with a
/// well-formed NG (in case the fuzz answer did not match), and waits for the
/// completion.
void exchange(World& w, int which, std::string_view payload) {
    auto done = std::make_shared<std::promise<void>>();
    auto finished = done->get_future();
    auto complete = [done](auto&&) { done->set_value(); };
    const std::uint64_t before = w.peer.count();
    std::string reply_topic;
    switch (which) {
        case 0:
            w.client->query_async(kDev, {QueryItem{"pos", std::nullopt}}, complete);
            reply_topic = topics::query_response(kDev, kEx);
            break;
        case 1:
            w.client->set_async(kDev, {SetItem{"ovr", Json{{"value", 1}}, std::nullopt, std::nullopt}}, complete);
            reply_topic = topics::set_response(kDev, kEx);
            break;
        case 2:
            w.client->probe_async(kDev, complete);
            reply_topic = topics::probe_query_response(kDev, kEx);
            break;
        case 3:
            w.client->register_async(complete);
            reply_topic = topics::register_response(kEx);
            break;
        case 4:
            w.client->discover_async(complete);
            reply_topic = topics::discovery_response(kEx);
            break;
        default:
            w.client->call_method_async(
                kDev, "m", Json::object(), [](const MethodStatus&) {}, complete);
            reply_topic = topics::method_result(kDev, kEx);
            break;
    }
    const std::string id = w.peer.wait_request(before);
    w.peer.send(reply_topic, with_id(payload, id));
    if (which == 5) w.peer.send(topics::method_status(kDev, kEx), with_id(payload, id));
    Json sync = {{"@id", id}, {"code", "NG"}, {"error", 202}, {"reason", "Unavailable"}};
    if (which == 3) sync["cli_uuid"] = kEx;
    else sync["guid"] = kDev;
    if (which == 5) {
        sync["id"] = "m";
        sync["result"] = "error";
    }
    w.peer.send(reply_topic, sync.dump());
    if (finished.wait_for(10s) != std::future_status::ready) std::abort();  // the client wedged
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    World& w = world();
    if (size == 0) return 0;
    const int which = data[0] % 9;
    const std::string_view payload(reinterpret_cast<const char*>(data + 1), size - 1);
    if (which < 6) {
        exchange(w, which, payload);
        return 0;
    }
    // Unasked DTUs: a Sample, a Notify/State, an Event; then a Query round
    // trip shows they were processed and the client still answers.
    const std::string topic = which == 6   ? topics::sample(kDev, "ch1")
                              : which == 7 ? topics::notify_state(kDev)
                                           : topics::event(kDev, kEx);
    w.peer.send(topic, std::string(payload));
    exchange(w, 0, R"({"@id": "@ID@", "guid": "fz-dev", "code": "OK", "values": [{"id": "pos", "code": "OK", "values": [1]}]})");
    return 0;
}
