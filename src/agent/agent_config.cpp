// Reads the agent's configuration file (docs/agent.md has the reference).
#include <nclink/agent.hpp>

#include "agent/access.hpp"
#include "agent/instance_split.hpp"
#include "agent/terminal_id.hpp"
#include "core/config_common.hpp"
#include "transport/broker_config.hpp"

namespace nclink {
using core_detail::ConfigReader;

namespace {

Result<void> read_broker(const Json& broker, AgentConfig& c) {
    ConfigReader b(broker, "broker.");
    if (!broker.is_object()) return b.fail(ErrorCode::value_type, "", "must be an object");
    NCLINK_TRY(transport_detail::read_broker_common(b, c));
    return b.no_unknown_keys();
}

Result<void> read_registration(const Json& section, RegistrationPolicy& p) {
    ConfigReader r(section, "registration.");
    if (!section.is_object()) return r.fail(ErrorCode::value_type, "", "must be an object");
    NCLINK_TRY(r.boolean("open", p.open));
    NCLINK_TRY(r.count("max_id_length", p.max_id_length));
    NCLINK_TRY(r.str("id_pattern", p.id_pattern));
    if (const Json* terminals = r.object("terminals")) {
        if (!terminals->is_object()) return r.fail(ErrorCode::value_type, "terminals", "must be an object");
        for (auto it = terminals->begin(); it != terminals->end(); ++it) {
            // Terminal ids may hold dots: the pointer is built from the keys.
            ConfigReader t(*it, "registration.terminals." + it.key() + ".",
                           core_detail::pointer_append("/registration/terminals", it.key()));
            if (!it->is_object()) return t.fail(ErrorCode::value_type, "", "must be an object");
            TerminalEntry entry;
            NCLINK_TRY(t.str("kind", entry.kind));
            NCLINK_TRY(t.str("password", entry.password));
            NCLINK_TRY(t.no_unknown_keys());
            if (!entry.kind.empty() && entry.kind != "adapter" && entry.kind != "application")
                return t.fail(ErrorCode::value_type, "kind", "must be \"adapter\" or \"application\"");
            p.terminals[it.key()] = entry;
        }
    }
    NCLINK_TRY(r.no_unknown_keys());
    if (auto rule = agent_detail::TerminalIdRule::make(p); !rule) {
        Error e = std::move(rule).error();
        e.pointer = "/registration/id_pattern";
        return e;
    }
    return ok_result();
}

Result<void> read_access(const Json& section, AccessPolicy& p) {
    ConfigReader a(section, "access.");
    if (!section.is_object()) return a.fail(ErrorCode::value_type, "", "must be an object");
    if (const Json* rights = a.object("default")) {
        auto bits = agent_detail::parse_rights(*rights, "access.default", "/access/default");
        if (!bits) return std::move(bits).error();
        p.default_rights = *bits;
    }
    if (const Json* apps = a.object("applications")) {
        if (!apps->is_object()) return a.fail(ErrorCode::value_type, "applications", "must be an object");
        for (auto app = apps->begin(); app != apps->end(); ++app) {
            const std::string app_pointer = core_detail::pointer_append("/access/applications", app.key());
            if (!app->is_object()) {
                Error e =
                    make_error(ErrorCode::value_type, "configuration: access.applications." + app.key() + " must be an object");
                e.pointer = app_pointer;
                return e;
            }
            auto& entry = p.applications[app.key()];
            for (auto dev = app->begin(); dev != app->end(); ++dev) {
                auto bits = agent_detail::parse_rights(*dev, "access.applications." + app.key() + "." + dev.key(),
                                                       core_detail::pointer_append(app_pointer, dev.key()));
                if (!bits) return std::move(bits).error();
                entry[dev.key()] = *bits;
            }
        }
    }
    return a.no_unknown_keys();
}

}  // namespace

Result<AgentConfig> agent_config_from_json(const Json& json, AgentConfig c) {
    if (!json.is_object()) return make_error(ErrorCode::syntax_error, "configuration: the file must hold a JSON object");
    ConfigReader top(json, "");
    if (const Json* broker = top.object("broker")) NCLINK_TRY(read_broker(*broker, c));
    NCLINK_TRY(top.str("agent_id", c.agent_id));
    NCLINK_TRY(top.str("share_group", c.share_group));
    NCLINK_TRY(top.count("instances", c.instances));
    NCLINK_TRY(top.count("instance", c.instance));
    NCLINK_TRY(top.str("state_dir", c.state_dir));
    NCLINK_TRY(top.duration("request_timeout_ms", c.request_timeout));
    NCLINK_TRY(top.duration("adapter_liveness_ms", c.adapter_liveness));
    NCLINK_TRY(top.duration("application_liveness_ms", c.application_liveness));
    NCLINK_TRY(top.boolean("observe_samples", c.observe_samples));
    NCLINK_TRY(top.count("max_in_flight", c.max_in_flight));
    NCLINK_TRY(top.boolean("discovery_link", c.discovery_link));
    NCLINK_TRY(top.duration("tick_ms", c.tick));
    if (const Json* section = top.object("registration")) NCLINK_TRY(read_registration(*section, c.registration));
    if (const Json* section = top.object("access")) NCLINK_TRY(read_access(*section, c.access));
    if (const Json* acl = top.object("acl")) {
        ConfigReader a(*acl, "acl.");
        if (!acl->is_object()) return a.fail(ErrorCode::value_type, "", "must be an object");
        NCLINK_TRY(a.str("agent_user", c.acl_agent_user));
        NCLINK_TRY(a.no_unknown_keys());
    }
    NCLINK_TRY(core_detail::read_log_level(top, c.log_level));
    NCLINK_TRY(core_detail::read_http_limits(top, "metrics", c.metrics));
    NCLINK_TRY(top.no_unknown_keys());
    if (c.request_timeout.count() <= 0) return top.fail(ErrorCode::out_of_range, "request_timeout_ms", "must be positive");
    if (c.tick.count() <= 0) c.tick = std::chrono::milliseconds(1);
    if (c.max_in_flight == 0) c.max_in_flight = 1;
    if (c.agent_id.empty() || c.agent_id.find_first_of("/+#") != std::string::npos)
        return top.fail(ErrorCode::value_type, "agent_id", "must be one topic level");
    if (c.share_group.find_first_of("/+#") != std::string::npos)
        return top.fail(ErrorCode::value_type, "share_group", "must not contain '/', '+' or '#'");
    if (const auto problem = agent_detail::split_problem(c))
        return top.fail(ErrorCode::out_of_range, problem->key, problem->text);
    return c;
}

Result<AgentConfig> load_agent_config(const std::string& path, AgentConfig base) {
    auto doc = core_detail::read_config_document(path);
    if (!doc) return std::move(doc).error();
    auto config = agent_config_from_json(doc->json, std::move(base));
    if (!config) return core_detail::located(*doc, std::move(config).error());
    const Json* json = &doc->json;
    AgentConfig& c = config.value();
    if (json->contains("state_dir")) core_detail::resolve_against(path, c.state_dir);
    if (json->contains("broker")) transport_detail::resolve_tls_paths(path, c.tls);
    return config;
}

}  // namespace nclink
