// Several agent instances without MQTT shared subscriptions (a broker with no
// `$share`, such as a RabbitMQ 3.10 cluster): every instance subscribes
// plainly and sees every DTU, and each answers only the requests of its
// share (docs/agent.md "Several agents"). The share of a request is fixed by
// one terminal id of it, so that every instance computes the same owner
// without talking to the others, and every request gets exactly one answer
// while all instances run.
//
// The hash is FNV-1a of 32 bits over the id's bytes, taken modulo the number
// of instances. Written down (not std::hash, whose values differ between
// standard libraries and architectures): instances built on different
// machines, or from different releases, must agree on every id. Changing it
// is a change of the wire contract between instances; the unit tests pin it.
#pragma once

#include <nclink/agent.hpp>
#include <nclink/topics.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace nclink::agent_detail {

/// FNV-1a, 32 bits (offset basis 2166136261, prime 16777619), of the bytes.
std::uint32_t fnv1a_32(std::string_view bytes) noexcept;

/// The instance (0 .. instances-1) whose share terminal `tid` is in:
/// fnv1a_32(tid) mod instances. 0 when instances is 0 or 1.
unsigned instance_of(std::string_view tid, unsigned instances) noexcept;

/// The cli_uuid of a Register/Request, when it can be read (a JSON object
/// with a string cli_uuid): the registrant is the terminal it belongs to.
std::optional<std::string> registrant(std::string_view payload);

/// The instance that answers this DTU when `instances` agents split the
/// work; std::nullopt for the DTUs every instance handles alike (responses,
/// states, samples, events: all but the requests the agent answers). Per
/// request kind, the terminal that decides:
///   Register/Request        its cli_uuid (instance 0 when none can be read:
///                           it cannot be answered, only counted, once)
///   Discovery/Request/{ex}  ex, the asking application
///   Probe/Version/{dev}     dev, the announcing adapter
///   requests to adapters    dev, the adapter asked (the instance that
///                           watches the adapter's answer, answers 203 or
///                           DEV_UNREACHABLE for it, and fetches its model)
std::optional<unsigned> answering_instance(const ParsedTopic& topic, std::string_view payload, unsigned instances);

/// What is wrong with the instances/instance/share_group combination of
/// `config`, as a key and a sentence for ConfigReader::fail; std::nullopt
/// when it is usable.
struct SplitProblem {
    const char* key;
    std::string text;
};
std::optional<SplitProblem> split_problem(const AgentConfig& config);

}  // namespace nclink::agent_detail
