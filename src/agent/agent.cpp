// Agent: wires the transport to registration, discovery, presence, the
// version cache and the request watch (timeouts, DEV_UNREACHABLE, 301).
//
// Every DTU is handled on the transport's callback thread under one mutex
// (bookkeeping only, no I/O); what it decides to publish is collected and
// published after the lock is released. The housekeeping thread runs the
// timeouts and liveness on the injected clock and writes the state files.
#include <nclink/agent.hpp>
#include <nclink/dtu.hpp>
#include <nclink/topics.hpp>

#include "agent/access.hpp"
#include "agent/model_cache.hpp"
#include "agent/pending_forwards.hpp"
#include "agent/presence.hpp"
#include "agent/registrar.hpp"
#include "agent/state_store.hpp"
#include "agent/terminal_id.hpp"

#include <fmt/format.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <random>
#include <set>
#include <thread>

namespace nclink {

using namespace agent_detail;

namespace {

bool publishable_level(std::string_view level) {
    if (level.empty()) return false;
    for (char c : level)
        if (c == '+' || c == '#' || c == '\0') return false;
    return true;
}

std::string random_suffix() {
    std::random_device device;
    return fmt::format("{:08x}", static_cast<std::uint32_t>(device()));
}

bool is_response(TopicKind kind) {
    switch (kind) {
        case TopicKind::probe_query_response:
        case TopicKind::probe_set_response:
        case TopicKind::query_response:
        case TopicKind::set_response:
        case TopicKind::sample_register_response:
        case TopicKind::sample_unregister_response:
        case TopicKind::method_status:
        case TopicKind::method_result:
        case TopicKind::method_control_response:
        case TopicKind::event_register_response:
        case TopicKind::event_unregister_response: return true;
        default: return false;
    }
}

bool same_tls(const std::optional<MqttTlsOptions>& a, const std::optional<MqttTlsOptions>& b) {
    if (a.has_value() != b.has_value()) return false;
    if (!a) return true;
    return a->ca_file == b->ca_file && a->cert_file == b->cert_file && a->key_file == b->key_file &&
           a->key_password == b->key_password && a->verify_server == b->verify_server;
}

bool same_registration(const RegistrationPolicy& a, const RegistrationPolicy& b) {
    if (a.open != b.open || a.max_id_length != b.max_id_length || a.id_pattern != b.id_pattern ||
        a.terminals.size() != b.terminals.size())
        return false;
    for (const auto& [tid, entry] : a.terminals) {
        const auto other = b.terminals.find(tid);
        if (other == b.terminals.end() || other->second.kind != entry.kind || other->second.password != entry.password)
            return false;
    }
    return true;
}

bool same_access(const AccessPolicy& a, const AccessPolicy& b) {
    return a.default_rights == b.default_rights && a.applications == b.applications;
}

}  // namespace

struct Agent::Impl {
    struct Counters {
        std::atomic<std::uint64_t> registrations{0}, refused{0}, discoveries{0}, versions{0}, fetched{0}, cached{0},
            unreachable{0}, timeouts{0}, denied{0}, notifications{0}, malformed{0}, retained{0};
    };
    using Out = std::vector<Message>;

    AgentConfig config;
    Logger log;
    std::shared_ptr<const Clock> clock = std::make_shared<SystemClock>();
    std::unique_ptr<Transport> transport;
    StateStore store;
    Counters counters;

    mutable std::mutex mutex;  // everything below up to the housekeeping part
    Presence presence;
    std::unique_ptr<Registrar> registrar;
    ModelCache models;
    PendingForwards pending;
    std::map<std::string, int> expected_echo;  // "tid\nstate" -> our own Notify/State still to come back
    bool loaded = false;  // the state files were read: only then may they be written
    bool registry_dirty = false;
    std::set<std::string> models_dirty;
    std::uint64_t msg_counter = 0;

    std::mutex lifecycle;
    bool started = false;
    bool stopped = false;
    std::mutex hk_mutex;
    std::condition_variable hk_wake;
    bool hk_stopping = false;
    std::thread housekeeping;

    Impl(AgentConfig c, Logger l)
        : config(std::move(c)),
          log(std::move(l)),
          store(config.state_dir),
          presence(config.adapter_liveness, config.application_liveness) {}

    std::int64_t wall_s() const { return clock->wall_ms() / 1000; }

    // ------------------------------------------------------------ lifecycle

    Result<void> start() {
        {
            std::lock_guard<std::mutex> lock(lifecycle);
            if (started) return make_error(ErrorCode::unavailable, "agent already started");
            started = true;
        }
        auto rule = TerminalIdRule::make(config.registration);
        if (!rule) return std::move(rule).error();
        {
            std::lock_guard<std::mutex> lock(mutex);
            registrar = std::make_unique<Registrar>(std::move(rule).value(), config.registration);
            if (auto read = store.load(*registrar, presence, models, log); !read) return read;
            loaded = true;
            for (const auto& [tid, entry] : config.registration.terminals)
                presence.set_kind(tid, kind_from_string(entry.kind));
            log.info("agent {}: {} registered terminal(s), {} cached model(s) from {}", config.agent_id,
                     registrar->all().size(), models.all().size(),
                     store.enabled() ? config.state_dir : std::string("(not persisted)"));
        }
        if (!transport) {
            auto made = make_mqtt_transport(mqtt_options(), log);
            if (!made) return std::move(made).error();
            transport = std::move(made).value();
        }
        transport->set_message_handler([this](const Message& m) { on_message(m); });
        transport->set_state_handler([this](LinkState s, std::string_view detail) {
            log.info("agent {}: broker link {} ({})", config.agent_id, to_string(s), detail);
        });
        if (auto r = transport->subscribe(answer_filters(), 1); !r) return r;
        if (auto r = transport->subscribe(observe_filters(), 1); !r) return r;
        housekeeping = std::thread([this] { housekeep(); });
        return transport->start();
    }

    void stop(std::chrono::milliseconds flush_timeout) {
        {
            std::lock_guard<std::mutex> lock(lifecycle);
            if (!started || stopped) return;
            stopped = true;
        }
        {
            std::lock_guard<std::mutex> lock(hk_mutex);
            hk_stopping = true;
        }
        hk_wake.notify_all();
        if (housekeeping.joinable()) housekeeping.join();
        if (transport) transport->stop(flush_timeout);  // no handler calls after this
        persist(true);
        log.info("agent {} stopped", config.agent_id);
    }

    // Thread: the owner's (nclink-agent: its signal loop). Applies under the
    // lock every DTU handler takes, so a DTU sees the old or the new rules.
    Result<ConfigReload> reload(const AgentConfig& next) {
        ConfigReload report;
        auto rule = TerminalIdRule::make(next.registration);
        if (!rule) return std::move(rule).error();
        std::lock_guard<std::mutex> life(lifecycle);
        std::lock_guard<std::mutex> lock(mutex);
        const bool running = started && !stopped && registrar;
        auto restart_only = [&](bool same, const char* key) {
            if (!same) (running ? report.restart_needed : report.applied).push_back(key);
        };
        auto reloadable = [&](bool same, const char* key) {
            if (!same) report.applied.push_back(key);
        };
        restart_only(config.broker_url == next.broker_url, "broker.url");
        restart_only(config.client_id == next.client_id, "broker.client_id");
        restart_only(config.username == next.username, "broker.username");
        restart_only(config.password == next.password, "broker.password");
        restart_only(config.mqtt_version == next.mqtt_version, "broker.mqtt_version");
        restart_only(config.keep_alive == next.keep_alive, "broker.keep_alive_s");
        restart_only(same_tls(config.tls, next.tls), "broker.tls");
        restart_only(config.agent_id == next.agent_id, "agent_id");
        restart_only(config.share_group == next.share_group, "share_group");
        restart_only(config.state_dir == next.state_dir, "state_dir");
        restart_only(config.observe_samples == next.observe_samples, "observe_samples");
        restart_only(config.tick == next.tick, "tick_ms");
        const bool registration_changed = !same_registration(config.registration, next.registration);
        reloadable(!registration_changed, "registration");
        reloadable(same_access(config.access, next.access), "access");
        reloadable(config.request_timeout == next.request_timeout, "request_timeout_ms");
        reloadable(config.adapter_liveness == next.adapter_liveness, "adapter_liveness_ms");
        reloadable(config.application_liveness == next.application_liveness, "application_liveness_ms");
        reloadable(config.acl_agent_user == next.acl_agent_user, "acl.agent_user");
        reloadable(config.log_level == next.log_level, "log_level");
        if (config.log_level != next.log_level) log.set_min_level(next.log_level);

        if (!running) {  // nothing runs yet: the whole new configuration counts
            config = next;
            return report;
        }
        if (registration_changed) {
            registrar->set_policy(std::move(rule).value(), next.registration);
            for (const auto& [tid, entry] : next.registration.terminals)
                presence.set_kind(tid, kind_from_string(entry.kind));
        }
        config.registration = next.registration;
        config.access = next.access;
        config.request_timeout = next.request_timeout;
        config.adapter_liveness = next.adapter_liveness;
        config.application_liveness = next.application_liveness;
        presence.set_liveness(next.adapter_liveness, next.application_liveness);
        config.acl_agent_user = next.acl_agent_user;
        config.log_level = next.log_level;
        return report;
    }

    MqttOptions mqtt_options() const {
        MqttOptions o;
        o.broker_url = config.broker_url;
        o.client_id = config.client_id.empty() ? config.agent_id + "-" + random_suffix() : config.client_id;
        o.username = config.username;
        o.password = config.password;
        o.tls = config.tls;
        o.mqtt_version = config.mqtt_version;
        o.keep_alive = config.keep_alive;
        return o;
    }

    // Requests the agent answers: with several agents, exactly one of them
    // gets each (MQTT shared subscription).
    std::vector<std::string> answer_filters() const {
        std::vector<std::string> filters = {topics::register_request(), topics::discovery_request("+"),
                                            topics::probe_version("+")};
        for (TopicKind kind : adapter_request_kinds())
            for (Spelling s : {Spelling::standard, Spelling::typo}) {
                if (s == Spelling::typo && !has_typo_spelling(kind)) continue;
                filters.push_back(build_topic(ParsedTopic{kind, "+", std::nullopt, std::nullopt, s}));
                filters.push_back(build_topic(ParsedTopic{kind, "+", "+", std::nullopt, s}));
            }
        if (!config.share_group.empty())
            for (auto& f : filters) f = "$share/" + config.share_group + "/" + f;
        return filters;
    }

    // What every agent instance must see to keep its own picture complete.
    std::vector<std::string> observe_filters() const {
        std::vector<std::string> filters = {topics::register_response("+"), topics::notify_state("+"),
                                            topics::probe_version_response("+"),
                                            topics::probe_version_response("+", "+"), topics::event("+"),
                                            topics::event("+", "+")};
        for (TopicKind kind : adapter_request_kinds()) {
            std::vector<TopicKind> answers = {*response_kind(kind)};
            if (kind == TopicKind::method_call) answers.push_back(TopicKind::method_status);
            for (TopicKind answer : answers)
                for (Spelling s : {Spelling::standard, Spelling::typo}) {
                    if (s == Spelling::typo && !has_typo_spelling(answer)) continue;
                    filters.push_back(build_topic(ParsedTopic{answer, "+", std::nullopt, std::nullopt, s}));
                    filters.push_back(build_topic(ParsedTopic{answer, "+", "+", std::nullopt, s}));
                }
        }
        if (config.observe_samples) filters.push_back("Sample/#");
        return filters;
    }

    // ------------------------------------------------------------ messages

    // Thread: transport callback.
    void on_message(const Message& m) {
        const auto parsed = parse_topic(m.topic);
        if (!parsed) return;  // not NC-Link
        Out out;
        {
            std::lock_guard<std::mutex> lock(mutex);
            try {
                dispatch(*parsed, m, out);
            } catch (const std::exception& e) {  // a bug must not kill the callback thread
                log.error("agent: handling {} failed: {}", m.topic, e.what());
            }
        }
        publish(out);
    }

    void publish(Out& out) {
        for (auto& message : out)
            if (auto r = transport->publish(std::move(message)); !r)
                log.warn("agent: publish failed: {}", r.error().describe());
    }

    void dispatch(const ParsedTopic& topic, const Message& m, Out& out) {
        switch (topic.kind) {
            case TopicKind::register_request: return on_register(m, out);
            case TopicKind::register_response: return on_register_response(topic, m);
            case TopicKind::discovery_request: return on_discovery(topic, m, out);
            case TopicKind::probe_version: return on_version(topic, m, out);
            case TopicKind::probe_version_response: return on_version_response(topic, m, out);
            case TopicKind::notify_state: return on_notify(topic, m, out);
            case TopicKind::sample:
            case TopicKind::dynamic_sample:
            case TopicKind::event: return alive(topic.dev, Kind::adapter, out);
            default: break;
        }
        if (required_right(topic.kind)) return on_request(topic, m, out);
        if (is_response(topic.kind)) return on_response(topic, m, out);
    }

    void reply(Out& out, std::string topic, const Json& payload) {
        out.push_back(Message{std::move(topic), payload.dump(-1, ' ', false, Json::error_handler_t::replace), 1, false});
    }

    // Answers the agent gives in an adapter's place carry privateInfo.agent,
    // so every agent instance can tell them from the adapter's own.
    Json marked(Json answer) const {
        if (!answer.contains("privateInfo") || !answer["privateInfo"].is_object()) answer["privateInfo"] = Json::object();
        answer["privateInfo"]["agent"] = config.agent_id;
        return answer;
    }

    void reply_all(Out& out, const ParsedTopic& request, const Json& payload) {
        for (auto& t : response_topics(request, true)) reply(out, std::move(t), payload);
    }

    void announce_state(const std::string& tid, Status status, Out& out) {
        NotifyState notify;
        notify.tid = tid;
        notify.state = to_wire(status);
        ++expected_echo[tid + "\n" + notify.state];
        ++counters.notifications;
        out.push_back(Message{topics::notify_state(tid), encode(notify), 1, true});
    }

    // A DTU from `tid`: a sign of life (3.22/3.23).
    void alive(const std::string& tid, Kind kind, Out& out) {
        if (tid.empty() || tid == config.agent_id) return;
        presence.set_kind(tid, kind);
        if (presence.saw_dtu(tid, clock->now(), wall_s())) {
            log.info("agent: {} {} is online (it sent a DTU)", to_string(presence.kind(tid)), tid);
            announce_state(tid, Status::online, out);
            registry_dirty = true;
        }
    }

    // ---- 8.2.1 / 8.2.2 ----
    void on_register(const Message& m, Out& out) {
        if (m.retained) {
            ++counters.retained;
            return;
        }
        auto request = decode<RegisterRequest>(m.payload);
        if (!request) {
            ++counters.malformed;
            ++counters.refused;
            // Answerable only when a usable cli_uuid can be picked out.
            const Json raw = Json::parse(m.payload, nullptr, false);
            if (raw.is_object() && raw.contains("cli_uuid") && raw["cli_uuid"].is_string()) {
                const std::string cli = raw["cli_uuid"].get<std::string>();
                if (publishable_level(cli))
                    if (auto answer = make_error_reply(TopicKind::register_request, peek_message_id(m.payload), cli,
                                                       request.error()))
                        reply(out, topics::register_response(cli), *answer);
            }
            log.warn("agent: malformed Register/Request: {}", request.error().describe());
            return;
        }
        const std::string& cli = request->cli_uuid;
        if (registrar->valid_id(cli)) {
            presence.set_kind(cli, registrar->listed_kind(cli));
            alive(cli, Kind::unknown, out);  // before deciding: the registration belongs to this online period
        }
        const auto decision = registrar->decide(*request, presence, wall_s());
        RegisterResponse response;
        response.msg_id = request->msg_id;
        response.cli_uuid = cli;
        response.status = decision.status;
        if (decision.status.ok) {
            ++counters.registrations;
            registry_dirty = true;
            log.info("agent: registered {} {}", to_string(presence.kind(cli)), cli);
        } else {
            ++counters.refused;
            log.warn("agent: registration of '{}' refused ({} {}): {}", cli, response.status.error.value_or(0),
                     response.status.reason.value_or(""), decision.why);
        }
        if (!publishable_level(cli)) return;  // no topic to answer on (the id has a wildcard or is empty)
        reply(out, topics::register_response(cli), to_json(response));
    }

    void on_register_response(const ParsedTopic& topic, const Message& m) {
        auto response = decode<RegisterResponse>(m.payload);
        if (!response || !response->status.ok || response->cli_uuid != topic.dev) return;
        if (!registrar->registered(topic.dev)) registry_dirty = true;
        registrar->record(topic.dev, presence.kind(topic.dev), wall_s(), presence.online_periods(topic.dev));
    }

    // ---- 8.2.3 / 8.2.4 ----
    void on_discovery(const ParsedTopic& topic, const Message& m, Out& out) {
        if (m.retained) {
            ++counters.retained;
            return;
        }
        const std::string ex = topic.ex.value_or("");
        alive(ex, Kind::application, out);
        auto request = decode<DiscoveryRequest>(m.payload);
        if (!request) {
            ++counters.malformed;
            if (auto answer = make_error_reply(TopicKind::discovery_request, peek_message_id(m.payload), ex,
                                               request.error()))
                reply(out, topics::discovery_response(ex), *answer);
            return;
        }
        DiscoveryResponse response;
        response.msg_id = request->msg_id;
        response.guid = ex;
        std::vector<DeviceListEntry> list;
        for (const auto& [tid, registration] : registrar->all()) {
            const Kind kind = presence.kind(tid) != Kind::unknown ? presence.kind(tid) : registration.kind;
            if (kind != Kind::adapter || rights_of(config.access, ex, tid) == access_none) continue;
            DeviceListEntry entry;
            entry.guid = tid;
            entry.status = to_wire(presence.status(tid));
            entry.last_alive_time_stamp = std::to_string(presence.last_alive_s(tid));
            list.push_back(std::move(entry));
        }
        if (!list.empty()) response.device_list = std::move(list);  // null: no accessible adapter (table 24)
        ++counters.discoveries;
        reply(out, topics::discovery_response(ex), to_json(response));
    }

    // ---- 8.2.5 / 8.2.6 and the model fetch of 8.2.7 ----
    void on_version(const ParsedTopic& topic, const Message& m, Out& out) {
        const std::string& dev = topic.dev;
        alive(dev, Kind::adapter, out);
        if (m.retained) return;  // a stale announcement replayed by the broker
        auto request = decode<ProbeVersionRequest>(m.payload);
        ProbeVersionResponse response;
        response.guid = dev;
        if (!request) {
            ++counters.malformed;
            response.msg_id = peek_message_id(m.payload);
            response.status = ResponseStatus(request.error());
            reply(out, topics::probe_version_response(dev), to_json(response));
            return;
        }
        response.msg_id = request->msg_id;
        response.status = ResponseStatus::success();
        response.version = request->version;
        ++counters.versions;
        reply(out, topics::probe_version_response(dev), to_json(response));
        if (models.announce(dev, request->version, clock->now())) fetch_model(dev, out);
    }

    void fetch_model(const std::string& dev, Out& out) {
        ProbeQueryRequest query;
        const std::string id = config.agent_id + "-fetch-" + std::to_string(++msg_counter);
        query.msg_id = Json(id);
        query.guid = dev;
        models.fetching(dev, id, clock->now() + config.request_timeout);
        log.info("agent: fetching the model of {} (version {})", dev, models.find(dev)->version);
        out.push_back(Message{topics::probe_query_request(dev, config.agent_id), encode(query), 1, false});
    }

    void on_version_response(const ParsedTopic& topic, const Message& m, Out&) {
        // Another agent (or an application) acknowledged a version: keep the
        // number; the model comes with that agent's fetch, which every agent sees.
        auto response = decode<ProbeVersionResponse>(m.payload);
        if (!response || !response->version || (response->status && !response->status->ok)) return;
        presence.set_kind(topic.dev, Kind::adapter);
        (void)models.announce(topic.dev, *response->version, clock->now());
    }

    // ---- 8.2.16 ----
    void on_notify(const ParsedTopic& topic, const Message& m, Out& out) {
        if (m.payload.empty()) return;  // a cleared retained state
        auto notify = decode<NotifyState>(m.payload);
        if (!notify || (notify->state != "online" && notify->state != "offline")) {
            ++counters.malformed;
            return;
        }
        const std::string& tid = topic.dev;
        if (tid == config.agent_id) return;
        if (auto echo = expected_echo.find(tid + "\n" + notify->state); echo != expected_echo.end()) {
            if (--echo->second == 0) expected_echo.erase(echo);
            return;  // our own announcement coming back
        }
        const Status status = notify->state == "online" ? Status::online : Status::offline;
        if (presence.set_state(tid, status, clock->now(), wall_s())) {
            registry_dirty = true;
            log.info("agent: {} is {}{}", tid, notify->state, m.retained ? " (retained state)" : "");
        }
        if (status == Status::offline) unreachable_for(tid, out);
    }

    // 8.3.5: the adapter went away while requests to it were waiting.
    void unreachable_for(const std::string& dev, Out& out) {
        for (auto& request : pending.take_for(dev)) answer_unreachable(request.kind, request.topic, dev, request.ex,
                                                                        request.msg_id, out);
    }

    void answer_unreachable(TopicKind kind, const std::string& request_topic, const std::string& dev,
                            const std::optional<std::string>& ex, const MessageId& msg_id, Out& out) {
        DevUnreachable dtu;
        dtu.msg_id = msg_id;
        dtu.dev_uuid = dev;
        dtu.cli_uuid = ex.value_or("");
        ++counters.unreachable;
        log.debug("agent: {} to {} answered DEV_UNREACHABLE", to_string(kind), dev);
        const Json answer = marked(to_json(dtu));
        for (auto& t : response_topics(request_topic, true)) reply(out, std::move(t), answer);
    }

    // ---- requests to adapters: 301, DEV_UNREACHABLE, cached probe, 203 ----
    void on_request(const ParsedTopic& topic, const Message& m, Out& out) {
        if (m.retained) {
            ++counters.retained;
            return;  // WIRE.md: never act on a replayed request
        }
        if (topic.ex && *topic.ex == config.agent_id) return;  // our own model fetch
        if (topic.ex) alive(*topic.ex, Kind::application, out);
        const std::string& dev = topic.dev;
        const std::string ex = topic.ex.value_or("");
        const MessageId msg_id = peek_message_id(m.payload);
        if (!allowed(config.access, ex, dev, *required_right(topic.kind))) {
            ++counters.denied;
            log.info("agent: {} from '{}' to {} denied (301)", to_string(topic.kind), ex, dev);
            if (auto answer = make_error_reply(topic.kind, msg_id, dev,
                                               make_error(ErrorCode::permission_denied, "access control")))
                reply_all(out, topic, marked(*answer));
            return;
        }
        if (presence.status(dev) == Status::offline) {
            const CachedModel* cached = models.find(dev);
            if (topic.kind == TopicKind::probe_query_request && cached && cached->model) {
                ProbeQueryResponse response;
                response.msg_id = msg_id;
                response.guid = dev;
                response.probe = *cached->model;
                response.private_info = Json{{"cached", true},
                                             {"version", cached->model_version},
                                             {"fetchedAt", std::to_string(cached->fetched_at_s)}};
                ++counters.cached;
                reply_all(out, topic, marked(to_json(response)));
                return;
            }
            answer_unreachable(topic.kind, m.topic, dev, topic.ex, msg_id, out);
            return;
        }
        Forwarded request;
        request.kind = topic.kind;
        request.dev = dev;
        request.ex = topic.ex;
        request.msg_id = msg_id;
        request.topic = m.topic;
        request.deadline = clock->now() + config.request_timeout;
        pending.add(std::move(request));
    }

    void on_response(const ParsedTopic& topic, const Message& m, Out& out) {
        if (m.retained || from_agent(m.payload)) return;  // an agent's answer says nothing about the adapter
        const std::string id = id_text(peek_message_id(m.payload));
        if (topic.kind == TopicKind::probe_query_response) {
            // Our fetch's answer, or any application's: either refreshes the cache.
            auto response = decode<ProbeQueryResponse>(m.payload);
            if (response && response->status.ok && response->probe && response->probe->is_object()) {
                if (models.store(topic.dev, std::move(*response->probe), wall_s())) {
                    ++counters.fetched;
                    models_dirty.insert(topic.dev);
                    log.info("agent: cached the model of {} (version {})", topic.dev, models.find(topic.dev)->version);
                }
            } else if (topic.ex && *topic.ex == config.agent_id && models.is_fetch(topic.dev, id)) {
                log.warn("agent: fetching the model of {} failed", topic.dev);
                models.fetching(topic.dev, "", clock->now());
            }
        }
        alive(topic.dev, Kind::adapter, out);
        if (!id.empty()) (void)pending.answered(topic.kind, topic.dev, topic.ex, id);
    }

    static bool from_agent(const std::string& payload) {
        if (payload.find("\"agent\"") == std::string::npos) return false;  // cheap filter: this runs per response
        const Json dtu = Json::parse(payload, nullptr, false);
        if (!dtu.is_object()) return false;
        const auto info = dtu.find("privateInfo");
        return info != dtu.end() && info->is_object() && info->contains("agent");
    }

    // ------------------------------------------------------------ housekeeping

    // Thread: housekeeping. Polls the injected clock every tick.
    void housekeep() {
        auto last_save = clock->now();
        std::unique_lock<std::mutex> lock(hk_mutex);
        while (!hk_stopping) {
            lock.unlock();
            Out out;
            {
                std::lock_guard<std::mutex> state(mutex);
                tick(out);
            }
            publish(out);
            if (clock->now() - last_save >= std::chrono::seconds(1)) {
                persist(false);
                last_save = clock->now();
            }
            lock.lock();
            hk_wake.wait_for(lock, config.tick, [this] { return hk_stopping; });
        }
    }

    void tick(Out& out) {
        const auto now = clock->now();
        for (auto& request : pending.take_expired(now)) {
            ++counters.timeouts;
            log.info("agent: {} to {} not answered within {} ms: 203", to_string(request.kind), request.dev,
                     config.request_timeout.count());
            if (auto answer = make_error_reply(request.kind, request.msg_id, request.dev,
                                               make_error(ErrorCode::timeout, "no answer from the adapter")))
                for (auto& t : response_topics(request.topic, true)) reply(out, std::move(t), marked(*answer));
        }
        for (const auto& tid : presence.expire(now)) {
            log.info("agent: {} {} is offline (no DTU for its liveness time)", to_string(presence.kind(tid)), tid);
            announce_state(tid, Status::offline, out);
            registry_dirty = true;
            unreachable_for(tid, out);
        }
        models.expire_fetches(now);
    }

    // Writes what changed; the text is built under the lock, written outside it.
    void persist(bool all) {
        if (!store.enabled()) return;
        std::optional<std::pair<Registrar, Presence>> registry;
        std::vector<std::pair<std::string, CachedModel>> dirty_models;
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (!loaded) return;  // never overwrite a file that could not be read
            if (registry_dirty || all) registry.emplace(*registrar, presence);
            registry_dirty = false;
            for (const auto& dev : models_dirty)
                if (const auto* entry = models.find(dev)) dirty_models.emplace_back(dev, *entry);
            models_dirty.clear();
        }
        if (registry)
            if (auto r = store.save_registry(registry->first, registry->second); !r)
                log.error("agent: cannot save the registry: {}", r.error().describe());
        for (const auto& [dev, entry] : dirty_models)
            if (auto r = store.save_model(dev, entry); !r)
                log.error("agent: cannot save the model of {}: {}", dev, r.error().describe());
    }
};

Agent::Agent(AgentConfig config, Logger logger) : impl_(std::make_unique<Impl>(std::move(config), std::move(logger))) {}

Agent::~Agent() { impl_->stop(std::chrono::milliseconds(0)); }

void Agent::use_transport(std::unique_ptr<Transport> transport) { impl_->transport = std::move(transport); }

void Agent::use_clock(std::shared_ptr<const Clock> clock) {
    if (clock) impl_->clock = std::move(clock);
}

Result<void> Agent::start() { return impl_->start(); }

Result<ConfigReload> Agent::reload(const AgentConfig& next) { return impl_->reload(next); }

void Agent::stop(std::chrono::milliseconds flush_timeout) { impl_->stop(flush_timeout); }

AgentStats Agent::stats() const {
    const auto& c = impl_->counters;
    AgentStats s;
    s.registrations = c.registrations;
    s.registrations_refused = c.refused;
    s.discoveries = c.discoveries;
    s.versions = c.versions;
    s.models_fetched = c.fetched;
    s.cached_probes = c.cached;
    s.unreachable = c.unreachable;
    s.timeouts = c.timeouts;
    s.denied = c.denied;
    s.state_notifications = c.notifications;
    s.malformed = c.malformed;
    s.ignored_retained = c.retained;
    {
        std::lock_guard<std::mutex> lock(impl_->mutex);
        s.pending = impl_->pending.size();
    }
    if (impl_->transport) s.transport = impl_->transport->stats();
    return s;
}

std::vector<TerminalInfo> Agent::terminals() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    std::set<std::string> ids;
    for (const auto& tid : impl_->presence.known()) ids.insert(tid);
    if (impl_->registrar)
        for (const auto& [tid, r] : impl_->registrar->all()) ids.insert(tid);
    std::vector<TerminalInfo> out;
    for (const auto& tid : ids) {
        TerminalInfo info;
        info.id = tid;
        info.kind = to_string(impl_->presence.kind(tid));
        info.registered = impl_->registrar && impl_->registrar->registered(tid);
        info.status = to_wire(impl_->presence.status(tid));
        info.last_alive_s = impl_->presence.last_alive_s(tid);
        if (const auto* cached = impl_->models.find(tid)) info.version = cached->version;
        out.push_back(std::move(info));
    }
    return out;
}

std::optional<Json> Agent::cached_model(const std::string& dev) const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    const auto* cached = impl_->models.find(dev);
    if (!cached || !cached->model) return std::nullopt;
    return cached->model;
}

}  // namespace nclink
