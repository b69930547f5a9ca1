// A burst of hostile and broken requests for one adapter (docs/security.md,
// "Floods"): half valid Query, the rest malformed JSON, huge Queries, JSON
// nested 300 deep and Set requests with wrong types, sent at QoS 0 as fast as
// the link takes them. Shared by the flood test and bench_request_flood.
#pragma once

#include <nclink/json.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/topics.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace nclink::test {

enum class FloodKind { valid_query, malformed, huge, deep, bad_set };

inline FloodKind flood_kind(std::size_t i) {
    if (i % 2 == 0) return FloodKind::valid_query;
    switch ((i / 2) % 4) {
        case 0: return FloodKind::malformed;
        case 1: return FloodKind::huge;
        case 2: return FloodKind::deep;
        default: return FloodKind::bad_set;
    }
}

/// The i-th message of a flood from application `ex` to adapter `dev`
/// reading `item` (a valid item of the adapter's model).
inline Message flood_message(std::size_t i, const std::string& dev, const std::string& ex, const std::string& item) {
    const std::string id = "flood-" + std::to_string(i);
    switch (flood_kind(i)) {
        case FloodKind::valid_query:
            return Message{topics::query_request(dev, ex), Json{{"@id", id}, {"ids", {{{"id", item}}}}}.dump(), 0, false};
        case FloodKind::malformed:
            return Message{topics::query_request(dev, ex), "{\"@id\": \"" + id + "\", \"ids\": [{\"id\": ", 0, false};
        case FloodKind::huge: {
            Json ids = Json::array();
            for (int k = 0; k < 1000; ++k) ids.push_back(Json{{"id", item}});
            return Message{topics::query_request(dev, ex), Json{{"@id", id}, {"ids", ids}}.dump(), 0, false};
        }
        case FloodKind::deep:
            return Message{topics::query_request(dev, ex),
                           "{\"@id\": \"" + id + "\", \"ids\": " + std::string(300, '[') + std::string(300, ']') + "}", 0, false};
        case FloodKind::bad_set:
        default:
            return Message{topics::set_request(dev, ex),
                           Json{{"@id", id}, {"values", {{{"id", 42}, {"params", "not an object"}}}}}.dump(), 0, false};
    }
}

/// A transport able to hold a whole burst (its offline buffer is sized for it).
inline std::unique_ptr<Transport> flood_transport(const std::string& url, const std::string& client_id) {
    MqttOptions m;
    m.broker_url = url;
    m.client_id = client_id;
    m.outbox.max_bytes = 512u << 20;
    m.outbox.max_in_flight = 1024;
    return make_mqtt_transport(m).value();
}

}  // namespace nclink::test
