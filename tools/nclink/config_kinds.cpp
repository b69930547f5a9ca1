// The table of configuration kinds (config_kinds.hpp). One entry per kind.
#include "config_kinds.hpp"

#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/gateway.hpp>

#include "bridge/bridge.hpp"

namespace nclink::cli {
namespace {

Result<void> check_adapter(const Json& document) {
    auto config = adapter_config_from_json(document);
    if (!config) return std::move(config).error();
    return ok_result();
}

Result<void> check_agent(const Json& document) {
    auto config = agent_config_from_json(document);
    if (!config) return std::move(config).error();
    return ok_result();
}

Result<void> check_bridge(const Json& document) {
    auto config = bridge::bridge_config_from_json(document);
    if (!config) return std::move(config).error();
    return ok_result();
}

Result<void> check_gateway(const Json& document) {
    auto config = gateway_config_from_json(document);
    if (!config) return std::move(config).error();
    return ok_result();
}

}  // namespace

const std::vector<ConfigKind>& config_kinds() {
    static const std::vector<ConfigKind> kinds = {
        {"adapter", "an adapter (nclink-sim --config, AdapterConfig)", &check_adapter},
        {"agent", "the agent (nclink-agent --config, /etc/nclink/agent.json)", &check_agent},
        {"bridge", "the bridge (nclink-bridge --config, /etc/nclink/bridge.json)", &check_bridge},
        {"gateway", "a gateway's machines (nclink-sim --gateway, GatewayConfig)", &check_gateway},
    };
    return kinds;
}

const ConfigKind* find_config_kind(std::string_view name) {
    for (const auto& kind : config_kinds())
        if (name == kind.name) return &kind;
    return nullptr;
}

std::optional<Json> config_schema(std::string_view kind) {
    for (const auto& schema : embedded_schemas()) {
        if (kind != schema.name) continue;
        Json parsed = Json::parse(schema.text, nullptr, false);
        if (parsed.is_discarded()) return std::nullopt;
        return parsed;
    }
    return std::nullopt;
}

}  // namespace nclink::cli
