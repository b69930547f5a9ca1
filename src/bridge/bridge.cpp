#include "bridge/bridge.hpp"

#include "bridge/follower.hpp"
#include "bridge/gbt_api.hpp"
#include "bridge/json_api.hpp"
#include "bridge/mtconnect_api.hpp"
#include "bridge/mtconnect_documents.hpp"
#include "bridge/ops_api.hpp"
#include "bridge/shdr.hpp"
#include "http/http_metrics.hpp"
#include "http/http_server.hpp"
#include "transport/broker_settings.hpp"

#include <nclink/client.hpp>

namespace nclink::bridge {

struct Bridge::Impl {
    Impl(BridgeConfig c, Logger l)
        : config(std::move(c)),
          logger(std::move(l)),
          // instanceId: unique per start (part 1 5.1.1): the start time in seconds.
          store(config.buffer_size, config.sender, static_cast<std::uint64_t>(now_ms() / 1000)),
          mtconnect(store) {}

    BridgeConfig config;
    Logger logger;
    BridgeStore store;
    MtConnectApi mtconnect;
    std::unique_ptr<Client> client;
    std::unique_ptr<Follower> follower;
    std::unique_ptr<GbtApi> gbt;
    std::unique_ptr<JsonApi> json;
    http::HttpMetrics http_metrics;  // before http: the server's observer uses it
    std::unique_ptr<http::HttpServer> http;
    std::unique_ptr<OpsApi> ops;
    std::unique_ptr<ShdrServer> shdr;
};

Bridge::Bridge(BridgeConfig config, Logger logger) : impl_(std::make_unique<Impl>(std::move(config), std::move(logger))) {}

Bridge::~Bridge() { stop(); }

Result<void> Bridge::start() {
    Impl& b = *impl_;
    const BridgeConfig& c = b.config;
    MqttOptions mqtt;
    nclink::transport_detail::BrokerSettings::of(c).apply_to(mqtt);
    if (mqtt.client_id.empty()) mqtt.client_id = c.ex_cid;
    ClientOptions options;
    options.ex_cid = c.ex_cid;
    options.default_timeout = c.request_timeout;
    options.logger = b.logger;
    auto client = Client::create(std::move(mqtt), std::move(options));
    if (!client) return std::move(client).error();
    b.client = std::move(client).value();

    FollowerOptions follow;
    follow.devices = c.devices;
    follow.poll_interval = c.poll_interval;
    follow.discovery_interval = c.discovery_interval;
    follow.request_timeout = c.request_timeout;
    follow.use_events = c.use_events;
    follow.liveness = c.adapter_liveness;
    follow.logger = b.logger;
    b.follower = std::make_unique<Follower>(*b.client, b.store, follow);
    b.gbt = std::make_unique<GbtApi>(b.store, b.mtconnect, *b.follower);
    b.json = std::make_unique<JsonApi>(b.store, *b.follower, c.heartbeat);

    http::HttpOptions http_options;
    http_options.host = c.http_host;
    http_options.port = c.http_port;
    http_options.workers = c.http_workers;
    http_options.max_body_bytes = c.max_request_bytes;
    http_options.max_streams = c.http_max_streams;
    http_options.header_timeout = c.http_header_timeout;
    http_options.keep_alive_timeout = c.http_keep_alive;
    http_options.read_timeout = c.http_read_timeout;
    http_options.write_timeout = c.http_write_timeout;
    http_options.max_connections = c.http_max_connections;
    http_options.max_connections_per_peer = c.http_max_connections_per_peer;
    http_options.logger = b.logger;
    if (!c.http_username.empty() || !c.http_password.empty())
        http_options.auth = http::BasicAuth{c.http_username, c.http_password, "nclink-bridge", {}};
    b.http = std::make_unique<http::HttpServer>(http_options);
    b.http->set_observer(b.http_metrics.observer());
    b.ops = std::make_unique<OpsApi>(b.store, *b.client, *b.http, b.http_metrics);
    b.ops->install(*b.http);
    b.json->install(*b.http);
    b.gbt->install(*b.http, "/gbt18759");
    b.mtconnect.install(*b.http, "");
    b.http->set_error_page([&b](int status, const http::HttpRequest& request, const std::string& reason) {
        if (request.path.rfind("/nclink/", 0) == 0) return http::json_response(Json{{"error", reason}}, status);
        MtErrorCode code = MtErrorCode::invalid_request;
        if (status == 404) code = MtErrorCode::invalid_uri;
        else if (status == 405) code = MtErrorCode::unsupported;
        else if (status == 503) code = MtErrorCode::too_many;
        else if (status >= 500) code = MtErrorCode::internal_error;
        return b.mtconnect.error({MtError{code, reason}}, status);
    });
    if (auto started = b.http->start(); !started) return started;
    if (c.shdr_enabled) {
        b.shdr = std::make_unique<ShdrServer>(b.store, c.shdr_host, c.shdr_port, c.heartbeat, b.logger);
        if (auto started = b.shdr->start(); !started) {
            b.http->stop();
            return started;
        }
    }
    if (auto started = b.client->start(); !started) {
        stop();
        return started;
    }
    if (auto started = b.follower->start(); !started) {
        stop();
        return started;
    }
    return ok_result();
}

void Bridge::stop() {
    Impl& b = *impl_;
    b.store.wake_all();
    if (b.http) b.http->stop();
    if (b.shdr) b.shdr->stop();
    if (b.follower) b.follower->stop();
    if (b.client) b.client->stop();
}

ConfigReload Bridge::reload(const BridgeConfig& next) {
    Impl& b = *impl_;
    const BridgeConfig& c = b.config;
    ConfigReload report;
    auto restart = [&](bool same, const char* key) {
        if (!same) report.restart_needed.emplace_back(key);
    };
    using nclink::transport_detail::BrokerSettings;
    report.restart_needed = nclink::transport_detail::broker_reload_keys(BrokerSettings::of(c), BrokerSettings::of(next));
    restart(c.ex_cid == next.ex_cid, "ex_cid");
    // A device more or less changes the MTConnect probe document, which an
    // instanceId promises to keep (MTConnect part 1 5.1.1): a restart.
    restart(c.devices == next.devices, "devices");
    restart(c.http_host == next.http_host && c.http_port == next.http_port, "http");
    restart(c.http_username == next.http_username, "http_username");
    restart(c.http_password == next.http_password, "http_password");
    restart(c.http_workers == next.http_workers, "http_workers");
    restart(c.max_request_bytes == next.max_request_bytes, "max_request_bytes");
    restart(c.http_max_streams == next.http_max_streams, "http_max_streams");
    restart(c.http_header_timeout == next.http_header_timeout, "http_header_timeout_ms");
    restart(c.http_keep_alive == next.http_keep_alive, "http_keep_alive_ms");
    restart(c.http_read_timeout == next.http_read_timeout, "http_read_timeout_ms");
    restart(c.http_write_timeout == next.http_write_timeout, "http_write_timeout_ms");
    restart(c.http_max_connections == next.http_max_connections, "http_max_connections");
    restart(c.http_max_connections_per_peer == next.http_max_connections_per_peer, "http_max_connections_per_peer");
    restart(c.shdr_host == next.shdr_host && c.shdr_port == next.shdr_port, "shdr");
    restart(c.shdr_enabled == next.shdr_enabled, "shdr_enabled");
    restart(c.buffer_size == next.buffer_size, "buffer_size");
    restart(c.sender == next.sender, "sender");
    restart(c.poll_interval == next.poll_interval, "poll_interval_ms");
    restart(c.discovery_interval == next.discovery_interval, "discovery_interval_ms");
    restart(c.adapter_liveness == next.adapter_liveness, "adapter_liveness_ms");
    restart(c.request_timeout == next.request_timeout, "request_timeout_ms");
    restart(c.use_events == next.use_events, "use_events");
    restart(c.heartbeat == next.heartbeat, "heartbeat_ms");
    if (c.log_level != next.log_level) {
        // Every part logs through copies of one logger: they share the level.
        b.logger.set_min_level(next.log_level);
        b.config.log_level = next.log_level;
        report.applied.emplace_back("log_level");
    }
    return report;
}

int Bridge::http_port() const noexcept { return impl_->http ? impl_->http->port() : 0; }
int Bridge::shdr_port() const noexcept { return impl_->shdr ? impl_->shdr->port() : 0; }
const BridgeStore& Bridge::store() const noexcept { return impl_->store; }

}  // namespace nclink::bridge
