// The agent's facade and lifecycle: connect, subscribe, load the state
// files, run the housekeeping thread; the DTU handling lives beside this file
// (agent_impl.hpp lists them).
#include "agent/agent_impl.hpp"

#include "agent/agent_mqtt_options.hpp"
#include "agent/shared_subscription_check.hpp"
#include "transport/broker_settings.hpp"

#include <nclink/paho_transport.hpp>

#include <random>

namespace nclink {

using namespace agent_detail;

namespace {
std::string random_suffix() {
    std::random_device device;
    return fmt::format("{:08x}", static_cast<std::uint32_t>(device()));
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

Result<void> Agent::Impl::start() {
    {
        std::lock_guard<std::mutex> lock(lifecycle);
        if (started) return make_error(ErrorCode::unavailable, "agent already started");
        started = true;
    }
    // A configuration built in code skips the file reader's checks.
    if (const auto problem = split_problem(config))
        return make_error(ErrorCode::out_of_range, std::string("configuration: ") + problem->key + " " + problem->text);
    auto rule = TerminalIdRule::make(config.registration);
    if (!rule) return std::move(rule).error();
    auto loaded = picture.with([&](State& p) -> Result<void> {
        p.registrar = std::make_unique<agent_detail::Registrar>(std::move(rule).value(), config.registration);
        p.presence.set_answer_window(config.request_timeout);
        if (auto read = store.load(*p.registrar, p.presence, p.models, log); !read) return read;
        p.saves.loaded();
        for (const auto& [tid, entry] : config.registration.terminals) p.presence.set_kind(tid, kind_from_string(entry.kind));
        log.info("agent {}: {} registered terminal(s), {} cached model(s) from {}", config.agent_id, p.registrar->all().size(),
                 p.models.all().size(), store.enabled() ? config.state_dir : std::string("(not persisted)"));
        // Seed 004 item 31: the registrations were checked (read) above; the
        // pairs leave `initial` and follow who is online from now on.
        const auto row = agent_transition(AgentState::initial, AgentEvent::initialized);
        p.started_serving = row.next != AgentState::initial;
        log.info("agent {}: state {} -> {} (initialized)", config.agent_id, to_string(AgentState::initial), to_string(row.next));
        return ok_result();
    });
    if (!loaded) return loaded;
    share_group = config.share_group;
    if (!transport) {
        share_group = usable_share_group();
        const MqttOptions options = mqtt_options();
        auto made = make_paho_transport(options, log);  // MQTT 5 $share, ws:// (paho_transport.hpp)
        if (!made) return std::move(made).error();
        transport = std::move(made).value();
        if (config.discovery_link) {
            MqttOptions o = options;
            o.client_id += "-discovery";
            auto link = make_paho_transport(o, log);
            if (!link) return std::move(link).error();
            discovery_transport = std::move(link).value();
        }
    }
    attach(transport, "broker link");
    if (auto r = transport->subscribe(answer_filters(), 1); !r) return r;
    if (auto r = transport->subscribe(observe_filters(), 1); !r) return r;
    // Sample DTUs only tell the agent that their terminal lives (3.22): at
    // QoS 0, so they do not take the broker's window of unacknowledged
    // messages to the agent. At 10,000 machines, at QoS 1, they shared it
    // with every machine's registration and model, and an application's
    // Discovery waited seconds behind them (docs/performance.md).
    if (config.observe_samples)
        if (auto r = transport->subscribe({"Sample/#"}, 0); !r) return r;
    last_save = clock->now();
    housekeeping.start(
        config.tick, [this] { housekeep(); }, "nclink-agent-hk");
    if (auto r = transport->start(); !r) return r;
    return start_discovery_link();
}

// Every terminal's registration, version, model and state come to the agent
// over its main link when a plant powers up: at 10,000 machines about four
// QoS 1 messages each, answered by as many, which mosquitto 2.0 reads from
// that one connection a packet per pass of its event loop (about 1,000 a
// second under that load, docs/performance.md). An application's Discovery
// queued behind them for 30-50 s, both ways. On a connection of its own it
// waits for nothing: the answer is the picture as far as the agent has read
// it. Only Discovery moves: its answer depends on nothing in flight, while
// a request the agent answers in an adapter's place must be seen in order
// with that adapter's answer, on the one link.
Result<void> Agent::Impl::start_discovery_link() {
    if (!discovery_transport) return ok_result();
    attach(discovery_transport, "Discovery link");
    if (auto r = discovery_transport->subscribe({shared(topics::discovery_request("+"))}, 1); !r) return r;
    return discovery_transport->start();
}

// Both links: DTUs counted by kind (docs/metrics.md), every message to
// on_message(), their state in the log.
void Agent::Impl::attach(std::unique_ptr<Transport>& link, const char* name) {
    link = transport_detail::count_dtus(std::move(link), dtus);
    link->set_message_handler([this](const Message& m) { on_message(m); });
    link->set_state_handler([this, name](LinkState s, std::string_view detail) {
        log.info("agent {}: {} {} ({})", config.agent_id, name, to_string(s), detail);
    });
}

void Agent::Impl::stop(std::chrono::milliseconds flush_timeout) {
    {
        std::lock_guard<std::mutex> lock(lifecycle);
        if (!started || stopped) return;
        stopped = true;
    }
    housekeeping.stop();
    // The Discovery link first: its handler may still announce an
    // application online on the main one (no handler calls after stop()).
    if (discovery_transport) discovery_transport->stop(flush_timeout);
    if (transport) transport->stop(flush_timeout);
    persist(true);
    log.info("agent {} stopped", config.agent_id);
}

Result<ConfigReload> Agent::Impl::reload(const AgentConfig& next) {
    ConfigReload report;
    auto rule = TerminalIdRule::make(next.registration);
    if (!rule) return std::move(rule).error();
    std::lock_guard<std::mutex> life(lifecycle);
    // Under the picture's lock: every DTU handler reads the configuration
    // there, so a DTU sees the old or the new rules, never a mix.
    return picture.with([&](State& p) -> Result<ConfigReload> {
        const bool running = started && !stopped && p.registrar;
        auto restart_only = [&](bool same, const char* key) {
            if (!same) (running ? report.restart_needed : report.applied).push_back(key);
        };
        auto reloadable = [&](bool same, const char* key) {
            if (!same) report.applied.push_back(key);
        };
        for (const std::string& key : transport_detail::broker_reload_keys(transport_detail::BrokerSettings::of(config),
                                                                           transport_detail::BrokerSettings::of(next)))
            restart_only(false, key.c_str());
        restart_only(config.agent_id == next.agent_id, "agent_id");
        restart_only(config.share_group == next.share_group, "share_group");
        // Every instance must change its share with all the others at once.
        restart_only(config.instances == next.instances, "instances");
        restart_only(config.instance == next.instance, "instance");
        restart_only(config.state_dir == next.state_dir, "state_dir");
        restart_only(config.observe_samples == next.observe_samples, "observe_samples");
        restart_only(config.max_in_flight == next.max_in_flight, "max_in_flight");
        restart_only(config.discovery_link == next.discovery_link, "discovery_link");
        restart_only(config.tick == next.tick, "tick_ms");
        restart_only(config.metrics == next.metrics, "metrics");  // the program's /metrics server, bound once
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
            p.registrar->set_policy(std::move(rule).value(), next.registration);
            for (const auto& [tid, entry] : next.registration.terminals) p.presence.set_kind(tid, kind_from_string(entry.kind));
        }
        config.registration = next.registration;
        config.access = next.access;
        config.request_timeout = next.request_timeout;
        config.adapter_liveness = next.adapter_liveness;
        config.application_liveness = next.application_liveness;
        p.presence.set_liveness(next.adapter_liveness, next.application_liveness);
        p.presence.set_answer_window(next.request_timeout);
        config.acl_agent_user = next.acl_agent_user;
        config.log_level = next.log_level;
        return report;
    });
}

MqttOptions Agent::Impl::mqtt_options() const { return agent_mqtt_options(config, random_suffix()); }

// A broker without shared subscriptions hears nothing of an agent that
// answers through them (RabbitMQ 3.10) or drops it at the SUBSCRIBE
// (ejabberd 23.01), and says so nowhere (shared_subscription_check.hpp).
// One agent then answers as well through plain subscriptions; several
// would each answer every request, which is why the log says what to set.
// A broker that cannot be reached now keeps the configured group.
std::string Agent::Impl::usable_share_group() {
    if (config.share_group.empty()) return "";
    MqttOptions o = mqtt_options();
    o.client_id += "-share-check";
    o.clean_session = true;
    auto probe = make_paho_transport(o, Logger{});
    if (!probe) return config.share_group;
    const std::string topic = "nclink/share-check/" + o.client_id;
    const auto check =
        check_shared_subscriptions(**probe, config.share_group, topic, o.connect_timeout, std::chrono::milliseconds(3000));
    switch (check.result) {
        case SharedSubscriptions::available:
            log.debug("agent {}: the broker delivers through $share ({})", config.agent_id, check.detail);
            return config.share_group;
        case SharedSubscriptions::unknown:
            log.warn("agent {}: could not check the broker for shared subscriptions ({}); answering through share group '{}'",
                     config.agent_id, check.detail, config.share_group);
            return config.share_group;
        case SharedSubscriptions::unavailable: break;
    }
    log.warn(
        "agent {}: the broker has no shared subscriptions ({}): answering through plain subscriptions. Run one "
        "agent, or several with \"share_group\": \"\" and \"instances\" (docs/agent.md)",
        config.agent_id, check.detail);
    return "";
}

// Requests the agent answers: with several agents, exactly one of them
// gets each (MQTT shared subscription), or all get each and one answers
// (instances, without $share: agent_split.cpp).
std::vector<std::string> Agent::Impl::answer_filters() const {
    std::vector<std::string> filters = {topics::register_request(), topics::probe_version("+")};
    if (!discovery_transport) filters.push_back(topics::discovery_request("+"));
    for (TopicKind kind : adapter_request_kinds())
        for (Spelling s : {Spelling::standard, Spelling::typo}) {
            if (s == Spelling::typo && !has_typo_spelling(kind)) continue;
            filters.push_back(build_topic(ParsedTopic{kind, "+", std::nullopt, std::nullopt, s}));
            filters.push_back(build_topic(ParsedTopic{kind, "+", "+", std::nullopt, s}));
        }
    for (auto& f : filters) f = shared(f);
    return filters;
}

std::string Agent::Impl::shared(const std::string& filter) const {
    return share_group.empty() ? filter : "$share/" + share_group + "/" + filter;
}

// What every agent instance must see to keep its own picture complete.
std::vector<std::string> Agent::Impl::observe_filters() const {
    std::vector<std::string> filters = {
        topics::register_response("+"),           topics::notify_state("+"), topics::probe_version_response("+"),
        topics::probe_version_response("+", "+"), topics::event("+"),        topics::event("+", "+")};
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
    return filters;
}

Agent::Agent(AgentConfig config, Logger logger) : impl_(std::make_unique<Impl>(std::move(config), std::move(logger))) {}

Agent::~Agent() { impl_->stop(std::chrono::milliseconds(0)); }

void Agent::use_transport(std::unique_ptr<Transport> transport) { impl_->transport = std::move(transport); }

void Agent::use_discovery_transport(std::unique_ptr<Transport> transport) { impl_->discovery_transport = std::move(transport); }

void Agent::use_clock(std::shared_ptr<const Clock> clock) {
    if (clock) impl_->clock = std::move(clock);
}

Result<void> Agent::start() { return impl_->start(); }

Result<ConfigReload> Agent::reload(const AgentConfig& next) { return impl_->reload(next); }

void Agent::stop(std::chrono::milliseconds flush_timeout) { impl_->stop(flush_timeout); }

std::string Agent::share_group_in_use() const { return impl_->share_group; }

AgentStats Agent::stats() const {
    const auto& c = impl_->counters;
    AgentStats s;
    s.registrations = c.registrations;
    s.registrations_refused = c.refused;
    s.registrations_repeated = c.repeated;
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
    impl_->picture.with([&](const Impl::State& p) {
        s.pending = p.pending.size();
        s.state = std::string(to_string(p.started_serving ? AgentState::normal : AgentState::initial));
    });
    s.held_responses = c.held;
    if (impl_->transport) s.transport = impl_->transport->stats();
    return s;
}

std::vector<TerminalInfo> Agent::terminals() const {
    return impl_->picture.with([](const Impl::State& p) { return p.terminals(); });
}

std::optional<Json> Agent::cached_model(const std::string& dev) const {
    return impl_->picture.with([&](const Impl::State& p) -> std::optional<Json> {
        const auto* cached = p.models.find(dev);
        if (!cached || !cached->model) return std::nullopt;
        return cached->model;
    });
}

}  // namespace nclink
