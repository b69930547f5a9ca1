// Every data object (dataItems and configs) of a model document, by id,
// through all components: what tests compare between two models.
#pragma once

#include <nclink/json.hpp>

#include <map>
#include <string>

namespace nclink::test {

inline void collect_model_items(const Json& o, std::map<std::string, Json>& out) {
    for (const char* k : {"dataItems", "configs"})
        if (o.contains(k))
            for (const auto& i : o[k]) out[i["id"].get<std::string>()] = i;
    if (o.contains("components"))
        for (const auto& c : o["components"]) collect_model_items(c, out);
}

inline std::map<std::string, Json> model_items(const Json& model) {
    std::map<std::string, Json> out;
    for (const auto& d : model["devices"]) collect_model_items(d, out);
    return out;
}

}  // namespace nclink::test
