// The split of the agent's requests over instances without $share
// (instance_split.hpp).
#include "agent/instance_split.hpp"

#include "agent/access.hpp"

#include <nclink/json.hpp>

#include <fmt/format.h>

namespace nclink::agent_detail {

std::uint32_t fnv1a_32(std::string_view bytes) noexcept {
    std::uint32_t hash = 2166136261u;
    for (const char c : bytes) {
        hash ^= static_cast<unsigned char>(c);
        hash *= 16777619u;  // uint32_t arithmetic wraps modulo 2^32 on every platform
    }
    return hash;
}

unsigned instance_of(std::string_view tid, unsigned instances) noexcept {
    if (instances <= 1) return 0;
    return static_cast<unsigned>(fnv1a_32(tid) % instances);
}

std::optional<std::string> registrant(std::string_view payload) {
    const Json raw = Json::parse(payload.begin(), payload.end(), nullptr, false);
    if (!raw.is_object()) return std::nullopt;
    const auto cli = raw.find("cli_uuid");
    if (cli == raw.end() || !cli->is_string()) return std::nullopt;
    return cli->get<std::string>();
}

std::optional<unsigned> answering_instance(const ParsedTopic& topic, std::string_view payload, unsigned instances) {
    switch (topic.kind) {
        case TopicKind::register_request: {
            // Registration runs before the registrant has a topic of its own:
            // its id is only in the payload.
            const auto cli = registrant(payload);
            return cli ? instance_of(*cli, instances) : 0u;
        }
        case TopicKind::discovery_request: return instance_of(topic.ex.value_or(""), instances);
        case TopicKind::probe_version: return instance_of(topic.dev, instances);
        default: break;
    }
    // Every request to an adapter carries its dev, while {ex} is optional;
    // and the adapter's instance is the one that keeps its requests' timers.
    if (required_right(topic.kind)) return instance_of(topic.dev, instances);
    return std::nullopt;
}

std::optional<SplitProblem> split_problem(const AgentConfig& config) {
    if (config.instances < 1) return SplitProblem{"instances", "must be at least 1"};
    if (config.instance >= config.instances)
        return SplitProblem{"instance",
                            fmt::format("must be below instances ({}): instances are numbered from 0", config.instances)};
    // With $share the broker already hands each request to one member:
    // splitting again would leave most requests unanswered.
    if (config.instances > 1 && !config.share_group.empty())
        return SplitProblem{"instances", fmt::format("must be 1 while share_group is set (\"{}\"): instances that split the work "
                                                     "subscribe plainly; set \"share_group\": \"\"",
                                                     config.share_group)};
    return std::nullopt;
}

}  // namespace nclink::agent_detail
