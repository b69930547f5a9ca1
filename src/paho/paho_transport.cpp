// The paho transport (paho_transport.hpp): the plant library's MQTT client.
#include <fmt/format.h>
#include <nclink/paho_transport.hpp>

#include "transport/outbox.hpp"
#include "core/thread_name.hpp"
#include "transport/ack_watchdog.hpp"
#include "transport/backoff.hpp"
#include "transport/broker_list.hpp"
#include "transport/connection_lost.hpp"
#include "transport/link_record.hpp"
#include "transport/subscription_set.hpp"
#include "transport/tcp_nodelay.hpp"
#if NCLINK_WITH_TLS
#include "transport/tls_check.hpp"  // names the cause of a failed handshake
#endif

#include <mqtt/async_client.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

namespace nclink {
namespace {

using std::chrono::milliseconds;

class MqttTransport final : public Transport, private mqtt::iaction_listener {
public:
    MqttTransport(MqttOptions options, Logger logger, std::vector<transport_detail::BrokerAddress> brokers)
        : options_(std::move(options)),
          logger_(std::move(logger)),
          brokers_(std::move(brokers)),
          link_(logger_, options_.broker_url, options_.client_id),
          // A client made for MQTT 5 connects at 3.1.1 too (not the other
          // way round): "auto" needs both. The URI is the first broker's;
          // every attempt names its broker in the connect options.
          client_(std::make_unique<mqtt::async_client>(
              options_.broker_url, options_.client_id,
              mqtt::create_options(options_.mqtt_version == 0 ? MQTTVERSION_5 : options_.mqtt_version,
                                   static_cast<int>(options_.outbox.max_in_flight) + 16),
              nullptr)),
          outbox_(
              options_.outbox,
              [this](const std::shared_ptr<const Message>& m, std::uint64_t attempt) { return send(m, attempt); }, logger_),
          watchdog_(transport_detail::ack_limit(options_.ack_timeout, options_.keep_alive)) {
        link_.brokers(brokers_.size());
    }

    ~MqttTransport() override {
        stop(milliseconds(0));
        // Destroyed here, while every member is alive: paho fails each
        // publish still unacknowledged from inside its destroy (on_failure on
        // this thread), and the outbox is declared after the client, so
        // member order alone would run that callback on a freed outbox
        // (heap corruption, seen with QoS 1 DTUs in flight at shutdown).
        client_.reset();
    }

    void set_message_handler(MessageHandler handler) override { on_message_ = std::move(handler); }
    void set_state_handler(LinkStateHandler handler) override { on_state_ = std::move(handler); }

    Result<void> start() override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (started_) return make_error(ErrorCode::unavailable, "transport already started");
            started_ = true;
        }
        // paho is never called with mutex_ held (see subscribe()).
        client_->set_message_callback([this](mqtt::const_message_ptr msg) { deliver(msg); });
        client_->set_connected_handler([this](const std::string&) { on_connected(); });
        client_->set_connection_lost_handler([this](const std::string& cause) { on_lost(cause); });
        // An MQTT 5 broker that ends the connection with a DISCONNECT of its
        // own (MQTT 5.0 3.14: a shared subscription it does not serve, a
        // session taken over, a shutdown) reaches this handler and not the
        // one above: without it the transport stayed "connected" and deaf
        // on an ejabberd cluster (docs/scaling.md).
        client_->set_disconnected_handler([this](const mqtt::properties&, mqtt::ReasonCode reason) {
            if (link_.state() != LinkState::connected) return;  // already known lost
            on_lost(fmt::format("the broker sent DISCONNECT (reason 0x{:02x})", static_cast<int>(reason)));
        });
        supervisor_ = std::thread([this] {
            core_detail::name_this_thread("nclink-mqtt");
            supervise();
        });
        return ok_result();
    }

    void stop(milliseconds flush_timeout) override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!started_ || stopping_) return;
        }
        if (link_.state() == LinkState::connected && flush_timeout.count() > 0) outbox_.wait_drained(flush_timeout);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        wake_.notify_all();
        if (supervisor_.joinable()) supervisor_.join();
        outbox_.stop();
        try {
            if (client_->is_connected()) client_->disconnect(milliseconds(500).count())->wait_for(milliseconds(2000));
        } catch (const mqtt::exception& e) {
            logger_.debug("mqtt: disconnect: {}", e.what());
        }
        try {
            // paho throws here too (-1) when the client is mid-reconnect;
            // an exception escaping stop() aborted Adapter::stop().
            client_->disable_callbacks();
        } catch (const mqtt::exception& e) {
            logger_.debug("mqtt: disable callbacks: {}", e.what());
        }
        link_.set_state(LinkState::disconnected, "stopped", on_state_);
    }

    Result<void> publish(Message message) override { return outbox_.push(std::move(message)); }

    // paho is never called with mutex_ held: its callback thread may be
    // waiting for mutex_ in on_connected() while holding paho's own lock.
    Result<void> subscribe(std::vector<std::string> filters, int qos) override {
        subscriptions_.add(filters, qos);
        // If the link comes up meanwhile, on_connected() subscribes too: harmless.
        if (link_.state() == LinkState::connected) subscribe_now(filters, qos);
        return ok_result();
    }

    Result<void> unsubscribe(std::vector<std::string> filters) override {
        subscriptions_.remove(filters);
        if (link_.state() == LinkState::connected) {
            try {
                client_->unsubscribe(mqtt::string_collection::create(filters));
            } catch (const mqtt::exception& e) {
                logger_.debug("mqtt: unsubscribe: {}", e.what());
            }
        }
        return ok_result();
    }

    LinkState state() const override { return link_.state(); }

    TransportStats stats() const override {
        TransportStats s;
        outbox_.fill_stats(s);
        link_.fill(s);
        return s;
    }

    bool flush(milliseconds timeout) override { return outbox_.wait_drained(timeout); }

private:
    // Thread: outbox sender. paho's publish only queues; the outcome comes
    // back through on_success/on_failure on paho's thread.
    bool send(const std::shared_ptr<const Message>& shared, std::uint64_t attempt) {
        const Message& m = *shared;
        try {
            // paho's message refers to the outbox's payload (an aliasing
            // pointer keeps the message alive) rather than copying it: one
            // copy less of every DTU, 7 % of the adapter's CPU with 400 kB
            // Sample DTUs (bench_sampling_throughput 1 x 500).
            auto msg = mqtt::make_message(m.topic, mqtt::binary_ref(std::shared_ptr<const std::string>(shared, &m.payload)),
                                          m.qos, m.retained);
            client_->publish(msg, reinterpret_cast<void*>(static_cast<std::uintptr_t>(attempt)), *this);
            return true;
        } catch (const mqtt::exception& e) {
            logger_.debug("mqtt: publish to {} refused: {}", m.topic, e.what());
            return false;
        }
    }

    void on_success(const mqtt::token& tok) override {
        {
            std::lock_guard<std::mutex> lock(watchdog_mutex_);
            watchdog_.progress(transport_detail::AckWatchdog::Clock::now());
        }
        outbox_.delivered(reinterpret_cast<std::uintptr_t>(tok.get_user_context()));
    }
    void on_failure(const mqtt::token& tok) override { outbox_.failed(reinterpret_cast<std::uintptr_t>(tok.get_user_context())); }

    // Thread: paho callback thread.
    void deliver(const mqtt::const_message_ptr& msg) {
        if (!msg) return;
        link_.received();
        if (!on_message_) return;
        Message m{msg->get_topic(), msg->to_string(), msg->get_qos(), msg->is_retained()};
        on_message_(m);
    }

    // Thread: paho callback thread.
    void on_connected() {
        if (options_.tcp_nodelay) {
            const transport_detail::BrokerAddress broker = current_broker();
            const int nodelay = transport_detail::apply_tcp_nodelay_to_peer(broker.host, broker.port);
            link_.nodelay_sockets(nodelay);
            if (nodelay == 0) logger_.warn("mqtt: could not find the broker socket to set TCP_NODELAY");
        }
        for (const auto& [qos, filters] : subscriptions_.by_qos()) subscribe_now(filters, qos);
        {
            std::lock_guard<std::mutex> lock(watchdog_mutex_);
            watchdog_.connected(transport_detail::AckWatchdog::Clock::now());
        }
        link_.connected();
        link_.set_state(LinkState::connected, link_.broker(), on_state_);
        // MQTT 5: the supervisor opens the outbox once it has read the
        // broker's Receive Maximum from the CONNACK (see supervise()).
        if (protocol_ < 5) outbox_.link_up();
    }

    // Thread: paho callback thread.
    void on_lost(const std::string& cause) {
        outbox_.link_down();
        link_.set_state(LinkState::disconnected, cause.empty() ? "connection lost" : cause, on_state_);
        { std::lock_guard<std::mutex> lock(mutex_); }  // the supervisor checks the state under mutex_: no lost wake-up
        wake_.notify_all();
    }

    void subscribe_now(const std::vector<std::string>& filters, int qos) {
        try {
            client_->subscribe(mqtt::string_collection::create(filters), std::vector<int>(filters.size(), qos));
        } catch (const mqtt::exception& e) {
            logger_.warn("mqtt: subscribe failed (retried on reconnect): {}", e.what());
        }
    }

    // The CONNACK's Receive Maximum (MQTT 5, 3.2.2.3.3); absent = 65535.
    static std::optional<std::size_t> broker_receive_maximum(mqtt::token& token) {
        try {
            const auto props = token.get_connect_response().get_properties();
            if (!props.contains(mqtt::property::RECEIVE_MAXIMUM)) return std::nullopt;
            return static_cast<std::size_t>(mqtt::get<uint16_t>(props, mqtt::property::RECEIVE_MAXIMUM));
        } catch (const std::exception&) {
            return std::nullopt;
        }
    }

    // Thread: supervisor. A persistent session that the broker no longer has
    // after a reconnection means messages queued for us are gone: the one
    // outage docs/delivery.md cannot cover, so it is never silent.
    void check_session(const mqtt::token& token) {
        bool present = true;
        try {
            present = token.get_connect_response().is_session_present();
        } catch (const std::exception&) {
            return;  // no CONNACK details: nothing to judge
        }
        if (session_established_ && !present) link_.session_lost();
        session_established_ = true;
    }

    // One attempt's options: to `url` only (paho would try every broker of
    // a list in one attempt, without our back-off and always from the
    // first), at the protocol level `protocol`.
    mqtt::connect_options connect_options(const std::string& url, int protocol) const {
        mqtt::connect_options_builder builder;
        builder.servers(mqtt::string_collection::create(std::vector<std::string>{url}));
        builder.mqtt_version(protocol >= 5 ? MQTTVERSION_5 : MQTTVERSION_3_1_1);
        builder.keep_alive_interval(options_.keep_alive)
            .connect_timeout(options_.connect_timeout)
            .automatic_reconnect(false)  // we reconnect ourselves, with our backoff
            // paho holds QoS>0 messages back beyond its own window while QoS 0
            // ones pass: keep its window at least ours so order is preserved.
            .max_inflight(static_cast<int>(options_.outbox.max_in_flight));
        if (protocol >= 5) builder.clean_start(options_.clean_session);
        else builder.clean_session(options_.clean_session);
        if (!options_.username.empty()) builder.user_name(options_.username).password(options_.password);
        if (options_.last_will) {
            const auto& w = *options_.last_will;
            builder.will(mqtt::message(w.topic, w.payload, w.qos, w.retained));
        }
        if (options_.tls) {
            const auto& t = *options_.tls;
            mqtt::ssl_options_builder ssl;
            if (!t.ca_file.empty()) ssl.trust_store(t.ca_file);
            if (!t.cert_file.empty()) ssl.key_store(t.cert_file);
            if (!t.key_file.empty()) ssl.private_key(t.key_file);
            if (!t.key_password.empty()) ssl.private_keypassword(t.key_password);
            ssl.enable_server_cert_auth(t.verify_server).verify(t.verify_server);
            builder.ssl(ssl.finalize());
        }
        return builder.finalize();
    }

    // paho C 1.3 reports a connection that failed after the CONNECT was
    // written and before a CONNACK came, and only that, as this failure; a
    // broker that is down or unreachable is "TCP/TLS connect failure" (the
    // stand-in of tests/support/mqtt5_refusing_broker.hpp and a closed port
    // show both), so "auto" does not fall back for a broker that is merely
    // down (tested: "a broker that is down is not taken for one that refuses 5").
    static bool closed_without_connack(const mqtt::exception& e) {
        return e.get_return_code() == MQTTASYNC_FAILURE && e.get_message() == "TCP connect completion failure";
    }

    // Thread: supervisor. Whether a failed MQTT 5 attempt was the broker
    // refusing the level: an "unsupported protocol version" CONNACK (MQTT 5
    // 3.2.2.2 0x84; 3.1.1 3.2.2.3 code 1 from a broker that answers in 3.1.1),
    // or the connection closed after the CONNECT without a CONNACK (how
    // RabbitMQ 3.10 refuses 5, docs/scaling.md).
    static bool protocol_refused(const mqtt::exception& e) {
        const int rc = e.get_return_code();
        if (rc == 1 || rc == 0x84 || e.get_reason_code() == 0x84) return true;
        return closed_without_connack(e);
    }

    // Thread: supervisor. Names the cause of a failed attempt: the broker's
    // CONNACK code (3.1.1) or reason code (5) when it answered, else for TLS
    // what a handshake of our own says (tls_check.hpp). With mqtt_version
    // "auto", a refused MQTT 5 is followed by 3.1.1 to the same broker.
    void connect_failed(const mqtt::exception& e, milliseconds delay) {
        if (options_.mqtt_version == 0 && !protocol_settled_ && protocol_ == 5 && protocol_refused(e)) {
            protocol_ = 4;
            fell_back_ = true;
            return connect_failed(fmt::format("the broker refused MQTT 5 ({}); trying MQTT 3.1.1", e.what()), false, delay);
        }
        const int rc = e.get_return_code();
        // Over MQTT 5 paho reports the CONNACK reason code as the return
        // code ("MQTT error [135]"), over 3.1.1 the 3.1.1 code.
        const int reason = e.get_reason_code() != 0 ? e.get_reason_code() : (rc >= 0x80 ? rc : 0);
        if (rc == 4 || reason == 0x86) return connect_failed("the broker refused the user name or password", true, delay);
        // mosquitto answers a wrong password with this one too.
        if (rc == 5 || reason == 0x87)
            return connect_failed("the broker refused the connection: not authorized (user name, password or certificate)", true,
                                  delay);
        if (rc == 2 || reason == 0x85) return connect_failed("the broker refused the client id", true, delay);
#if NCLINK_WITH_TLS
        if (options_.tls) {
            const transport_detail::BrokerAddress broker = current_broker();
            if (auto problem = transport_detail::tls_file_problem(*options_.tls)) return connect_failed(*problem, true, delay);
            if (auto problem =
                    transport_detail::tls_handshake_problem(broker.host, broker.port, *options_.tls, options_.connect_timeout))
                return connect_failed(*problem, true, delay);
        }
#endif
        connect_failed(e.what(), false, delay);
    }

    // Thread: supervisor. The attempt to the current broker failed: the
    // next one goes to the next broker of the failover list (the same one
    // when the list has one, or after a protocol fall-back).
    void connect_failed(const std::string& why, bool refused, milliseconds delay) {
        std::string next;
        if (!std::exchange(fell_back_, false)) {
            std::lock_guard<std::mutex> lock(brokers_mutex_);
            if (brokers_.advance()) {
                next = brokers_.current().url;
                moved_on();
            }
            if (options_.mqtt_version == 0 && !protocol_settled_) protocol_ = auto_protocol();
        }
        link_.attempt_failed(why, refused, delay, next);
    }

    // Thread: supervisor. brokers_ moved on to another broker (a failed
    // attempt, or a connection lost before it was stable): the level
    // learnt about the last one does not hold for it.
    void moved_on() {
        protocol_settled_ = false;  // another broker: "auto" asks it for 5 first
        if (options_.mqtt_version == 0) protocol_ = auto_protocol();
    }

    // Thread: supervisor. The level "auto" asks a broker for first. A paho
    // client that has connected at 3.1.1 refuses to connect at 5 from then
    // on ("Client created for another version of MQTT", before any byte is
    // sent): after a 3.1.1 connection, "auto" asks every broker for 3.1.1.
    int auto_protocol() const { return spoke_311_ ? 4 : 5; }

    // Thread: supervisor, under mutex_. The connection made at
    // backoff.connected() was lost (or dropped as stalled) at `now`: the
    // back-off and, for one lost before it was stable, the move to the next
    // broker of the failover list (connection_lost.hpp; the libmosquitto
    // transport follows the same rule). The wait before the next attempt.
    milliseconds after_lost_connection(transport_detail::ReconnectBackoff& backoff,
                                       transport_detail::ReconnectBackoff::Clock::time_point now) {
        transport_detail::AfterLoss after;
        std::string next;
        {
            std::lock_guard<std::mutex> lock(brokers_mutex_);
            after = transport_detail::connection_lost(backoff, brokers_, now);
            if (after.moved) next = brokers_.current().url;
        }
        if (after.moved) moved_on();
        const milliseconds wait = backoff.wait(rng_);
        if (!after.stable) link_.lost_early(after.lasted, backoff.stable_period(), wait, next);
        return wait;
    }

    transport_detail::BrokerAddress current_broker() const {
        std::lock_guard<std::mutex> lock(brokers_mutex_);
        return brokers_.current();
    }

    // Thread: supervisor. Whether the link is up but has acknowledged none of
    // the messages in flight for the watchdog's limit (transport/
    // ack_watchdog.hpp): a link keep-alive cannot see is dead, e.g. paho
    // holding a partial write under backpressure (docs/delivery.md).
    bool ack_stalled() {
        const std::size_t in_flight = outbox_.in_flight();
        std::lock_guard<std::mutex> lock(watchdog_mutex_);
        return watchdog_.stalled(transport_detail::AckWatchdog::Clock::now(), in_flight);
    }

    // Thread: supervisor, without mutex_. Drops the stalled connection; the
    // supervisor then connects again and the outbox sends every message
    // still unacknowledged again, in order (QoS 1 is at least once, 4.3.2).
    // paho's late answers for the old attempts are ignored by the outbox.
    void drop_stalled_link() {
        std::chrono::milliseconds waited{0};
        {
            std::lock_guard<std::mutex> lock(watchdog_mutex_);
            waited = watchdog_.waited(transport_detail::AckWatchdog::Clock::now());
        }
        link_.stalled(waited, outbox_.in_flight());
        outbox_.link_down();
        try {
            // A DISCONNECT that cannot be written (the fault itself) must not
            // hold the supervisor: paho closes the socket after the timeout.
            client_->disconnect(0)->wait_for(milliseconds(2000));
        } catch (const mqtt::exception& e) {
            logger_.debug("mqtt: disconnect of a stalled link: {}", e.what());
        }
        link_.set_state(LinkState::disconnected, "nothing acknowledged", on_state_);
    }

    // How often the supervisor looks at the watchdog while connected: a tenth
    // of its limit, between 100 ms and 1 s; never when it is off.
    std::optional<milliseconds> ack_check_period() const {
        if (watchdog_.limit().count() <= 0) return std::nullopt;
        return std::clamp(watchdog_.limit() / 10, milliseconds(100), milliseconds(1000));
    }

    // Thread: supervisor. Connects, and reconnects with exponential backoff
    // whenever the link is lost (or found stalled), until stop(). A link lost
    // before it was stable counts as a failed attempt (backoff.hpp).
    void supervise() {
        transport_detail::ReconnectBackoff backoff(options_.reconnect_min, options_.reconnect_max);
        const auto check_period = ack_check_period();
        bool was_up = false;  // the link was up: it was lost (or dropped as stalled)
        std::unique_lock<std::mutex> lock(mutex_);
        while (!stopping_) {
            if (link_.state() == LinkState::disconnected) {
                // A lost link waits its back-off before the first attempt
                // too, as the libmosquitto transport does: jittered, so the
                // terminals one broker restart dropped do not come back in
                // lockstep; and paho fails a connect issued while it is still
                // closing the lost socket ("socket error"), which would move
                // a failover list on from a broker that is still there.
                if (std::exchange(was_up, false)) {
                    const milliseconds wait = after_lost_connection(backoff, transport_detail::ReconnectBackoff::Clock::now());
                    if (wake_.wait_for(lock, wait, [this] { return stopping_; })) continue;
                }
                const milliseconds retry = backoff.wait(rng_);
                lock.unlock();
                const std::string url = current_broker().url;
                const int protocol = protocol_;
                link_.trying(url);
                link_.set_state(LinkState::connecting, url, on_state_);
                bool ok = false;
                std::optional<std::size_t> receive_maximum;
                try {
                    auto token = client_->connect(connect_options(url, protocol));
                    ok = token->wait_for(options_.connect_timeout + milliseconds(500));
                    if (!ok)
                        connect_failed(fmt::format("no answer within {} ms", options_.connect_timeout.count()), false, retry);
                    if (ok && protocol >= 5) receive_maximum = broker_receive_maximum(*token);
                    if (ok && !options_.clean_session) check_session(*token);
                } catch (const mqtt::exception& e) {
                    connect_failed(e, retry);
                }
                const bool answered = ok;            // a CONNACK accepted the attempt
                ok = ok && client_->is_connected();  // paho call: before taking mutex_
                // Already lost again: a connection that was never stable, so
                // a failed attempt for the rotation too (connection_lost.hpp).
                if (answered && !ok) connect_failed("the broker closed the connection right after its CONNACK", false, retry);
                if (ok && options_.mqtt_version == 0 && !protocol_settled_)
                    logger_.info("mqtt: {} speaks MQTT {} (mqtt_version auto)", url, protocol >= 5 ? "5" : "3.1.1");
                if (ok) protocol_settled_ = true;
                if (ok && protocol < 5) spoke_311_ = true;
                if (ok && protocol >= 5) {
                    // paho keeps QoS 1 messages beyond the broker's Receive
                    // Maximum in its own queue and sends them only when woken
                    // (a new publish, or once a second): more in flight than
                    // the broker allows turns a burst into a trickle and the
                    // terminal seems dead. Never hand paho more than it may send.
                    outbox_.set_window(receive_maximum.value_or(65535));
                    if (receive_maximum && *receive_maximum < options_.outbox.max_in_flight)
                        logger_.debug("mqtt: the broker allows {} unacknowledged messages", *receive_maximum);
                    outbox_.link_up();
                }
                lock.lock();
                if (!ok) {
                    if (link_.state() != LinkState::connected) {
                        lock.unlock();
                        link_.set_state(LinkState::disconnected, "connect failed", on_state_);
                        lock.lock();
                    }
                    wake_.wait_for(lock, retry, [this] { return stopping_; });
                    backoff.failed();
                    continue;
                }
                backoff.connected(transport_detail::ReconnectBackoff::Clock::now());
                was_up = true;
            }
            const auto lost = [this] { return stopping_ || link_.state() == LinkState::disconnected; };
            if (!check_period) {
                wake_.wait(lock, lost);
                continue;
            }
            if (wake_.wait_for(lock, *check_period, lost)) continue;
            lock.unlock();
            if (link_.state() == LinkState::connected && ack_stalled()) drop_stalled_link();
            lock.lock();
        }
    }

    std::mt19937 rng_{std::random_device{}()};  // supervisor thread only: reconnect jitter
    const MqttOptions options_;
    const Logger logger_;
    mutable std::mutex brokers_mutex_;  // brokers_: moved on by the supervisor, read on paho's thread too
    transport_detail::BrokerRotation brokers_;
    transport_detail::LinkRecord link_;
    std::unique_ptr<mqtt::async_client> client_;  // reset first in the destructor (see there)
    transport_detail::Outbox outbox_;
    MessageHandler on_message_;
    LinkStateHandler on_state_;

    std::mutex mutex_;  // started_, stopping_, supervisor wake-ups
    std::condition_variable wake_;
    transport_detail::SubscriptionSet subscriptions_;
    bool started_ = false;
    bool stopping_ = false;
    std::thread supervisor_;

    bool session_established_ = false;  // supervisor only: a connection has had a session
    /// The protocol level of the next CONNECT: mqtt_version, or for 0
    /// ("auto") 5 until a broker refuses it (connect_failed()). Written by
    /// the supervisor, read on paho's thread (on_connected()).
    std::atomic<int> protocol_{options_.mqtt_version == 0 ? 5 : options_.mqtt_version};
    bool protocol_settled_ = false;  ///< supervisor only: a CONNACK accepted protocol_ (from this broker)
    bool fell_back_ = false;         ///< supervisor only: the next attempt stays on the broker at 3.1.1
    bool spoke_311_ = false;         ///< supervisor only: a connection was made at 3.1.1 (see connect_failed())

    std::mutex watchdog_mutex_;  // watchdog_: progress on paho's thread, checks on the supervisor
    transport_detail::AckWatchdog watchdog_;
};

}  // namespace

Result<std::unique_ptr<Transport>> make_paho_transport(MqttOptions options, Logger logger) {
    if (options.client_id.empty()) return make_error(ErrorCode::parameter_missing, "MQTT client id is empty");
    auto brokers = transport_detail::broker_list(options.broker_url, options.failover_urls);
    if (!brokers) return std::move(brokers).error();
    const std::string& scheme = brokers.value().front().scheme;
    if ((scheme == "ssl" || scheme == "mqtts" || scheme == "wss") && !options.tls) options.tls = MqttTlsOptions{};
    if (options.outbox.max_in_flight == 0) options.outbox.max_in_flight = 1;
    try {
        return std::unique_ptr<Transport>(new MqttTransport(std::move(options), std::move(logger), std::move(brokers).value()));
    } catch (const mqtt::exception& e) {
        return make_error(ErrorCode::value_type, fmt::format("MQTT client: {}", e.what()));
    }
}

}  // namespace nclink
