// A scripted stand-in for an adapter (or agent) on the loopback broker: it
// subscribes to a device's request topics and answers as the test says.
#pragma once

#include <nclink/client.hpp>
#include <nclink/dtu.hpp>
#include <nclink/testing/loopback_transport.hpp>
#include <nclink/topics.hpp>

#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace nclink::test {

class FakeAdapter {
public:
    /// Returns the messages to publish in answer to `request` (none = silence).
    using Script = std::function<std::vector<Message>(const Message& request)>;

    FakeAdapter(LoopbackBroker& broker, std::string dev, Script script, std::vector<std::string> filters = {},
                std::optional<Message> will = std::nullopt)
        : dev_(std::move(dev)), script_(std::move(script)) {
        LoopbackOptions o;
        o.client_id = "adapter-" + dev_;
        o.last_will = std::move(will);
        transport_ = make_loopback_transport(broker, o);
        transport_->set_message_handler([this](const Message& m) { handle(m); });
        if (filters.empty()) filters = topics::adapter_subscriptions(dev_);
        REQUIRE(transport_->subscribe(filters, 1).ok());
        REQUIRE(transport_->start().ok());
        REQUIRE(eventually([&] { return transport_->state() == LinkState::connected; }));
    }
    ~FakeAdapter() { transport_->stop(std::chrono::milliseconds(200)); }

    void publish(Message m) { REQUIRE(transport_->publish(std::move(m)).ok()); }

    std::vector<Message> requests() {
        std::lock_guard<std::mutex> lock(mutex_);
        return requests_;
    }
    std::size_t request_count() {
        std::lock_guard<std::mutex> lock(mutex_);
        return requests_.size();
    }

    const std::string& dev() const { return dev_; }
    Transport& transport() { return *transport_; }

private:
    void handle(const Message& m) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            requests_.push_back(m);
        }
        if (!script_) return;
        for (auto& reply : script_(m)) (void)transport_->publish(std::move(reply));
    }

    std::string dev_;
    Script script_;
    std::unique_ptr<Transport> transport_;
    std::mutex mutex_;
    std::vector<Message> requests_;
};

/// A response to `request` on its mirror topic, "@id" echoed, guid = dev.
inline Message reply_to(const Message& request, Json body, const std::string& dev) {
    const Json req = Json::parse(request.payload);
    if (req.contains("@id")) body["@id"] = req["@id"];
    if (!body.contains("guid")) body["guid"] = dev;
    return Message{response_topic(request.topic).value_or("no/response/topic"), body.dump(), 1, false};
}

/// Answers every Query with `"v-<id>"` per item and every Set with OK.
inline std::vector<Message> echo_script(const Message& request, const std::string& dev) {
    const auto topic = parse_topic(request.topic);
    if (!topic) return {};
    const Json req = Json::parse(request.payload);
    if (topic->kind == TopicKind::query_request) {
        Json values = Json::array();
        for (const auto& item : req["ids"])
            values.push_back({{"id", item["id"]}, {"code", "OK"}, {"values", Json::array({"v-" + item["id"].get<std::string>()})}});
        return {reply_to(request, {{"values", values}}, dev)};
    }
    if (topic->kind == TopicKind::set_request) {
        Json results = Json::array();
        for (const auto& item : req["values"]) results.push_back({{"id", item["id"]}, {"code", "OK"}});
        return {reply_to(request, {{"results", results}}, dev)};
    }
    if (topic->kind == TopicKind::probe_query_request)
        return {reply_to(request, {{"code", "OK"}, {"probe", {{"id", "root"}, {"devices", Json::array()}}}}, dev)};
    if (topic->kind == TopicKind::probe_set_request) return {reply_to(request, {{"code", "OK"}}, dev)};
    return {};
}

inline std::unique_ptr<Client> make_client(LoopbackBroker& broker, const std::string& ex,
                                           std::chrono::milliseconds timeout = std::chrono::milliseconds(2000)) {
    LoopbackOptions o;
    o.client_id = ex;
    ClientOptions co;
    co.ex_cid = ex;
    co.default_timeout = timeout;
    auto client = Client::create(make_loopback_transport(broker, o), co);
    REQUIRE(client.ok());
    auto c = std::move(client).value();
    REQUIRE(c->start().ok());
    REQUIRE(c->wait_connected(std::chrono::seconds(5)));
    return c;
}

}  // namespace nclink::test
