// The gateway's one file: defaults every machine starts from and the list of
// machines, each an adapter configuration of its own (docs/gateway.md).
#include <nclink/gateway.hpp>

#include "core/config_common.hpp"

#include <filesystem>
#include <set>

namespace nclink {

namespace {

using core_detail::ConfigReader;

void resolve(const std::string& base_dir, std::string& path) {
    if (base_dir.empty() || path.empty()) return;
    const std::filesystem::path p(path);
    if (p.is_relative()) path = (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

std::string default_id(const MachineConfig& m) {
    if (!m.adapter.dev_uuid.empty()) return m.adapter.dev_uuid;
    return std::filesystem::path(m.adapter.model_path).stem().string();
}

}  // namespace

Result<MachineConfig> machine_config_from_json(const Json& entry, const Json& defaults, const std::string& base_dir) {
    if (!entry.is_object()) return make_error(ErrorCode::value_type, "configuration: a machine must be an object");
    MachineConfig machine;
    Json merged = defaults.is_object() ? defaults : Json::object();
    Json own = entry;
    if (auto id = own.find("id"); id != own.end()) {
        if (!id->is_string()) return make_error(ErrorCode::value_type, "configuration: machines[].id must be a string");
        machine.id = id->get<std::string>();
        own.erase("id");
    }
    merged.merge_patch(own);
    auto adapter = adapter_config_from_json(merged);
    if (!adapter) return std::move(adapter).error();
    machine.adapter = std::move(adapter).value();
    // Paths the machine's entry or the defaults give are relative to the file.
    resolve(base_dir, machine.adapter.model_path);
    resolve(base_dir, machine.adapter.persistence_dir);
    resolve(base_dir, machine.adapter.driver_plugin);
    if (machine.adapter.tls) {
        resolve(base_dir, machine.adapter.tls->ca_file);
        resolve(base_dir, machine.adapter.tls->cert_file);
        resolve(base_dir, machine.adapter.tls->key_file);
    }
    if (machine.id.empty()) machine.id = default_id(machine);
    if (machine.id.empty())
        return make_error(ErrorCode::parameter_missing, "configuration: a machine needs an id, a dev_uuid or a model");
    return machine;
}

Result<GatewayConfig> gateway_config_from_json(const Json& json, const std::string& base_dir) {
    if (!json.is_object()) return make_error(ErrorCode::syntax_error, "configuration: the file must hold a JSON object");
    GatewayConfig c;
    ConfigReader top(json, "");
    if (const Json* defaults = top.object("defaults")) {
        if (!defaults->is_object()) return make_error(ErrorCode::value_type, "configuration: defaults must be an object");
        // Checked once here, so a typo in the defaults is named as such.
        if (auto checked = adapter_config_from_json(*defaults); !checked) {
            Error e = make_error(checked.error().code, "defaults: " + checked.error().message);
            e.pointer = "/defaults" + checked.error().pointer;  // located by `nclink config check`
            return e;
        }
        c.defaults = *defaults;
    }
    NCLINK_TRY(top.count("start_threads", c.start_threads));
    NCLINK_TRY(top.count("timer_threads", c.timer_threads));
    NCLINK_TRY(top.count("request_threads", c.request_threads));
    NCLINK_TRY(top.count("driver_threads", c.driver_threads));
    NCLINK_TRY(top.count("work_threads", c.work_threads));
    NCLINK_TRY(top.str("mqtt_client", c.mqtt_client));
    NCLINK_TRY(top.count("mqtt_connect_max", c.mqtt_connect_max));
    if (c.mqtt_client != "mosquitto" && c.mqtt_client != "paho")
        return make_error(ErrorCode::out_of_range,
                          fmt::format("configuration: mqtt_client must be \"mosquitto\" or \"paho\", not \"{}\"", c.mqtt_client));
    NCLINK_TRY(core_detail::read_log_level(top, c.log_level));
    const Json* machines = top.object("machines");
    NCLINK_TRY(top.no_unknown_keys());
    if (!machines) return make_error(ErrorCode::parameter_missing, "configuration: machines is missing");
    if (!machines->is_array()) return make_error(ErrorCode::value_type, "configuration: machines must be an array");
    std::set<std::string> ids, guids;
    for (std::size_t i = 0; i < machines->size(); ++i) {
        auto machine = machine_config_from_json((*machines)[i], c.defaults, base_dir);
        if (!machine) {
            // The entry's own keys are where a problem is: the defaults were checked alone above.
            Error e = make_error(machine.error().code, fmt::format("machines[{}]: {}", i, machine.error().message));
            e.pointer = fmt::format("/machines/{}{}", i, machine.error().pointer);
            return e;
        }
        if (!ids.insert(machine->id).second)
            return make_error(ErrorCode::keys_of_arguments, fmt::format("machines[{}]: id '{}' is listed twice", i, machine->id));
        const std::string& guid = machine->adapter.dev_uuid;
        if (!guid.empty() && !guids.insert(guid).second)
            return make_error(ErrorCode::keys_of_arguments, fmt::format("machines[{}]: GUID '{}' is listed twice", i, guid));
        c.machines.push_back(std::move(machine).value());
    }
    return c;
}

Result<GatewayConfig> load_gateway_config(const std::string& path) {
    auto json = core_detail::read_config_file(path);
    if (!json) return std::move(json).error();
    const std::string dir = std::filesystem::absolute(std::filesystem::path(path)).parent_path().string();
    auto config = gateway_config_from_json(*json, dir);
    if (!config) return make_error(config.error().code, fmt::format("{}: {}", path, config.error().message));
    return config;
}

}  // namespace nclink
