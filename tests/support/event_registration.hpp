// A Client::EventRegistration (8.2.19 Register/Event) in one expression, for
// the tests of the client's events (unit and integration).
#pragma once

#include <nclink/client.hpp>

#include <string>
#include <utility>
#include <vector>

namespace nclink::test {

inline Client::EventRegistration event_registration(const std::string& id, std::vector<Json> filters = {},
                                                    std::string trigger = "always") {
    Client::EventRegistration r;
    r.id = id;
    r.filters = std::move(filters);
    r.trigger = std::move(trigger);
    return r;
}

}  // namespace nclink::test
