#include "transport/mosquitto_transport.hpp"

#include "transport/ack_watchdog.hpp"
#include "transport/backoff.hpp"
#include "transport/in_flight_ids.hpp"
#include "transport/broker_list.hpp"
#include "transport/connection_lost.hpp"
#include "transport/link_record.hpp"
#include "transport/mqtt_loop.hpp"
#include "transport/outbox.hpp"
#include "transport/subscription_set.hpp"
#include "transport/tcp_nodelay.hpp"

#include <fcntl.h>
#include <mosquitto.h>
#include <mqtt_protocol.h>
#if NCLINK_WITH_TLS
#include "transport/tls_check.hpp"

#include <openssl/ssl.h>
#include <openssl/x509.h>
#endif

#include <atomic>
#include <condition_variable>
#include <future>
#include <optional>
#include <cstring>
#include <map>
#include <mutex>
#include <random>
#include <shared_mutex>
#include <utility>

namespace nclink::transport_detail {
namespace {

using std::chrono::milliseconds;
using Steady = std::chrono::steady_clock;

constexpr bool kWithTls = NCLINK_WITH_TLS != 0;

void init_library_once() {
    static std::once_flag once;
    std::call_once(once, [] { mosquitto_lib_init(); });
}

// All socket work happens on the loop thread. Other threads only queue:
// libmosquitto in "threaded" mode queues a publish and leaves the writing to
// whoever runs its loop, here MqttLoop, woken by wake(this).
//
// Each connection attempt uses a fresh libmosquitto client: the outbox owns
// every unacknowledged message and sends it again after a reconnect, so the
// library must not also replay its own copy (a duplicate, out of order).
class MosquittoTransport final : public Transport, private LoopMember {
public:
    MosquittoTransport(MqttOptions options, Logger logger, std::shared_ptr<MqttLoop> loop, core_detail::PollHost* work,
                       std::vector<BrokerAddress> brokers)
        : options_(std::move(options)),
          logger_(std::move(logger)),
          loop_(std::move(loop)),
          link_(logger_, options_.broker_url, options_.client_id),
          brokers_(std::move(brokers)),
          outbox_(
              options_.outbox,
              [this](const std::shared_ptr<const Message>& m, std::uint64_t attempt) { return send(*m, attempt); }, logger_, work,
              true),  // libmosquitto copies the payload in mosquitto_publish()
          watchdog_(ack_limit(options_)) {
        link_.brokers(brokers_.size());
    }

    ~MosquittoTransport() override {
        stop(milliseconds(0));
        destroy_client();
    }

    void set_message_handler(MessageHandler handler) override { on_message_ = std::move(handler); }
    void set_state_handler(LinkStateHandler handler) override { on_state_ = std::move(handler); }

    Result<void> start() override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (started_) return make_error(ErrorCode::unavailable, "transport already started");
            started_ = true;
        }
        retry_at_ = Steady::now();  // the first attempt at once
        loop_->add(this);
        loop_->wake(this);
        return ok_result();
    }

    void stop(milliseconds flush_timeout) override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!started_ || stopping_) return;
        }
        if (link_.state() == LinkState::connected && flush_timeout.count() > 0) outbox_.wait_drained(flush_timeout);
        outbox_.stop();
        {
            std::unique_lock<std::mutex> lock(mutex_);
            stopping_ = true;
            lock.unlock();
            loop_->wake(this);
            lock.lock();
            // The loop sends DISCONNECT (no last will for a clean stop) and closes.
            closed_cv_.wait_for(lock, milliseconds(2000), [this] { return closed_; });
        }
        loop_->remove(this);
        set_state(LinkState::disconnected, "stopped");
    }

    Result<void> publish(Message message) override { return outbox_.push(std::move(message)); }

    Result<void> subscribe(std::vector<std::string> filters, int qos) override {
        subscriptions_.add(filters, qos);
        // Sent at once when connected; every (re)connection subscribes to all.
        std::shared_lock<std::shared_mutex> client(client_mutex_);
        if (link_.state() == LinkState::connected && mosq_ != nullptr) {
            subscribe_now(filters, qos);
            loop_->wake(this);
        }
        return ok_result();
    }

    Result<void> unsubscribe(std::vector<std::string> filters) override {
        subscriptions_.remove(filters);
        std::shared_lock<std::shared_mutex> client(client_mutex_);
        if (link_.state() == LinkState::connected && mosq_ != nullptr && !filters.empty()) {
            std::vector<char*> list;
            for (auto& f : filters) list.push_back(f.data());
            mosquitto_unsubscribe_multiple(mosq_, nullptr, static_cast<int>(list.size()), list.data(), nullptr);
            loop_->wake(this);
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
    // The keep-alive libmosquitto is given (begin_connect()).
    static std::chrono::seconds effective_keep_alive(const MqttOptions& o) {
        return std::max<std::chrono::seconds>(std::chrono::seconds(5), o.keep_alive);
    }
    static milliseconds ack_limit(const MqttOptions& o) {
        return transport_detail::ack_limit(o.ack_timeout, effective_keep_alive(o));
    }

    // ---- any thread -------------------------------------------------------

    // Outbox sender or a publishing thread. The acknowledgement (or, at QoS
    // 0, the write) comes back through on_publish on the loop thread,
    // possibly before mosquitto_publish() has returned the message id.
    bool send(const Message& m, std::uint64_t attempt) {
        std::shared_lock<std::shared_mutex> client(client_mutex_);
        if (mosq_ == nullptr || link_.state() != LinkState::connected) return false;
        int mid = 0;
        const int rc = mosquitto_publish(mosq_, &mid, m.topic.c_str(), static_cast<int>(m.payload.size()), m.payload.data(),
                                         m.qos, m.retained);
        if (rc != MOSQ_ERR_SUCCESS) {
            logger_.debug("mqtt: publish to {} refused: {}", m.topic, mosquitto_strerror(rc));
            return false;
        }
        bool done = false;
        {
            std::lock_guard<std::mutex> lock(acks_mutex_);
            done = in_flight_.record(mid, attempt);
        }
        if (done) outbox_.delivered(attempt);
        loop_->wake(this);
        return true;
    }

    void subscribe_now(std::vector<std::string> filters, int qos) {
        std::vector<char*> list;
        for (auto& f : filters) list.push_back(f.data());
        const int rc = mosquitto_subscribe_multiple(mosq_, nullptr, static_cast<int>(list.size()), list.data(), qos, 0, nullptr);
        if (rc != MOSQ_ERR_SUCCESS) logger_.warn("mqtt: subscribe failed (retried on reconnect): {}", mosquitto_strerror(rc));
    }

    void set_state(LinkState next, std::string_view detail) { link_.set_state(next, detail, on_state_); }

    // mqtt_version 0 ("auto"): until a CONNACK settles it, an MQTT 5
    // attempt the broker refused for its protocol level (or closed without
    // answering) is followed by a 3.1.1 one to the same broker. Once
    // connected the level is kept for every reconnection to that broker.
    // True when it fell back (connect_failed() then stays on the broker).
    bool try_other_protocol() {
        if (options_.mqtt_version != 0 || protocol_settled_ || protocol_ != 5) return false;
        protocol_ = 4;
        fell_back_ = true;
        return true;
    }

    // Loop thread: the attempt to brokers_.current() failed. The next one
    // goes to the next broker of the failover list (the same one when the
    // list has one, or after a protocol fall-back), after the back-off.
    void connect_failed(const std::string& why, bool refused) {
        loop_->connect_done(this);
        const milliseconds retry = backoff_.wait(rng_);
        std::string next;
        if (!std::exchange(fell_back_, false)) {
            if (brokers_.advance()) {
                next = brokers_.current().url;
                moved_on();
            }
            if (options_.mqtt_version == 0 && !protocol_settled_) protocol_ = 5;
        }
        link_.attempt_failed(why, refused, retry, next);
        retry_at_ = Steady::now() + retry;
        backoff_.failed();
    }

    // Loop thread: brokers_ moved on to another broker (a failed attempt, or
    // a connection lost before it was stable): what was learnt about the
    // last one does not hold for it.
    void moved_on() {
        protocol_settled_ = false;  // another broker: "auto" asks it for 5 first
        tls_verdict_.reset();       // that verdict was about the other broker
        if (options_.mqtt_version == 0) protocol_ = 5;
    }

    // ---- loop thread ------------------------------------------------------

    void on_io(bool readable, bool writable) override {
        if (mosq_ == nullptr) return;
        // A TLS handshake moves on in loop_read whichever way the socket turned ready.
        if (readable || (writable && options_.tls && !connected_)) checked(mosquitto_loop_read(mosq_, 1));
        if (writable && !lost_ && mosquitto_socket(mosq_) >= 0) checked(mosquitto_loop_write(mosq_, 1));
        after_io();
    }

    void on_wake() override {
        bool stopping = false, closed = false;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping = stopping_;
            closed = closed_;
        }
        if (stopping) {
            if (!closed) close_for_stop();
            return;
        }
        if (mosq_ == nullptr && Steady::now() >= retry_at_) begin_connect();
        if (mosq_ != nullptr && mosquitto_want_write(mosq_)) checked(mosquitto_loop_write(mosq_, 1));
        after_io();
    }

    // A failed read or write normally ends in on_disconnected(); a failed
    // TLS handshake returns its error without it, and would otherwise be
    // noticed only by the connect timeout.
    void checked(int rc) {
        if (rc == MOSQ_ERR_SUCCESS || lost_) return;
        if (!connected_) attempt_failed(rc);
        lose(mosquitto_strerror(rc));
    }

    // Loop thread: why an attempt that got no CONNACK failed. A TLS error
    // is named by OpenSSL's verdict on the broker's certificate, as the paho
    // path names it (tls_check.hpp).
    void attempt_failed(int rc) {
#if NCLINK_WITH_TLS
        if (rc == MOSQ_ERR_TLS && mosq_ != nullptr) {
            const BrokerAddress tried = brokers_.current();  // connect_failed() may move on
            const auto* ssl = static_cast<const SSL*>(mosquitto_ssl_get(mosq_));
            const long verify = ssl != nullptr ? SSL_get_verify_result(ssl) : X509_V_OK;
            if (verify != X509_V_OK)
                return connect_failed(
                    fmt::format("the broker's certificate did not verify: {}", X509_verify_cert_error_string(verify)), true);
            // The verdict of an earlier attempt's own handshake stands until a connection succeeds.
            if (tls_verdict_) return connect_failed(*tls_verdict_, true);
            connect_failed("the TLS handshake with the broker failed", false);
            // libmosquitto freed the handshake before we could read its
            // verdict: a handshake of our own names it, off this thread (it
            // may take up to the connect timeout; the loop serves everyone).
            if (!diagnosis_.valid()) {
                diagnosed_url_ = tried.url;
                diagnosis_ = std::async(std::launch::async, [host = tried.host, port = tried.port, tls = *options_.tls,
                                                             timeout = options_.connect_timeout] {
                    return tls_handshake_problem(host, port, tls, timeout);
                });
            }
            return;
        }
#endif
        std::string why = rc == MOSQ_ERR_ERRNO ? std::string(std::strerror(errno)) : std::string(mosquitto_strerror(rc));
        if (options_.tls) why = "TLS connection failed: " + why;
        connect_failed(why, false);
    }

    void on_tick(Steady::time_point now) override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (stopping_) return;
        }
#if NCLINK_WITH_TLS
        if (diagnosis_.valid() && diagnosis_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
            // Only while the attempts still go to the broker it examined.
            if (auto problem = diagnosis_.get(); problem && !connected_ && diagnosed_url_ == brokers_.current().url) {
                tls_verdict_ = problem;
                link_.attempt_named(*problem, true);  // retrying will not help until the configuration changes
            }
        }
#endif
        if (mosq_ == nullptr) {
            if (now >= retry_at_) begin_connect();
        } else if (!connected_ && now >= attempt_deadline_) {
            connect_failed(fmt::format("no answer within {} ms", options_.connect_timeout.count()), false);
            drop_connection("connect failed");
        } else if (connected_ && watchdog_.stalled(now, outbox_.in_flight())) {
            link_.stalled(watchdog_.waited(now), outbox_.in_flight());
            drop_connection("nothing acknowledged");
        } else if (now >= next_misc_) {
            // Keep-alive: PINGREQ when due, and a broker that stopped answering is noticed.
            next_misc_ = now + std::chrono::seconds(1);
            checked(mosquitto_loop_misc(mosq_));
        }
        after_io();
    }

    // After any libmosquitto call: a socket it closed is unwatched, a lost
    // connection is dropped, queued output is written or waited for.
    void after_io() {
        if (lost_) {
            lost_ = false;
            drop_connection(lost_reason_);
            return;
        }
        if (mosq_ == nullptr) {
            loop_->watch(this, -1, false);
            return;
        }
        const int fd = mosquitto_socket(mosq_);
        if (fd >= 0 && fd != cloexec_fd_) {
            // libmosquitto opens its socket without close-on-exec: a child the
            // program starts would inherit it, and keep the broker connection
            // (and its epoll registration) alive after this side closed it.
            (void)::fcntl(fd, F_SETFD, FD_CLOEXEC);
            cloexec_fd_ = fd;
        }
        // Until the TCP connection is up the CONNECT waits in the queue:
        // writable is when it has come up (or failed).
        loop_->watch(this, fd, fd >= 0 && mosquitto_want_write(mosq_));
    }

    void begin_connect() {
        // A gateway's machines connect a few dozen at a time (connect_turns.hpp);
        // the loop wakes this one when its turn comes.
        if (!loop_->connect_turn(this)) return;
        loop_->watch(this, -1, false);  // before its socket closes (MqttLoop::watch)
        cloexec_fd_ = -1;
        destroy_client();
        init_library_once();
        const BrokerAddress& broker = brokers_.current();
        link_.trying(broker.url);
        set_state(LinkState::connecting, broker.url);
        mosquitto* m = mosquitto_new(options_.client_id.c_str(), options_.clean_session, this);
        if (m == nullptr) return connect_failed("libmosquitto could not create a client", false);
        mosquitto_threaded_set(m, true);
        mosquitto_int_option(m, MOSQ_OPT_PROTOCOL_VERSION, protocol_ >= 5 ? MQTT_PROTOCOL_V5 : MQTT_PROTOCOL_V311);
        mosquitto_int_option(m, MOSQ_OPT_TCP_NODELAY, options_.tcp_nodelay ? 1 : 0);
        mosquitto_int_option(m, MOSQ_OPT_SEND_MAXIMUM,
                             static_cast<int>(std::min<std::size_t>(options_.outbox.max_in_flight, 65535)));
        mosquitto_connect_v5_callback_set(m, &MosquittoTransport::on_connack);
        mosquitto_disconnect_callback_set(m, &MosquittoTransport::on_disconnected);
        mosquitto_publish_callback_set(m, &MosquittoTransport::on_published);
        mosquitto_message_callback_set(m, &MosquittoTransport::on_received);
        if (!options_.username.empty()) mosquitto_username_pw_set(m, options_.username.c_str(), options_.password.c_str());
        if (options_.last_will) {
            const auto& w = *options_.last_will;
            mosquitto_will_set(m, w.topic.c_str(), static_cast<int>(w.payload.size()), w.payload.data(), w.qos, w.retained);
        }
#if NCLINK_WITH_TLS
        if (options_.tls) {
            const auto& t = *options_.tls;
            if (auto problem = tls_file_problem(t)) {
                mosquitto_destroy(m);
                return connect_failed(*problem, true);
            }
            // No CA file: the system's trust store, as paho does.
            const int rc = mosquitto_tls_set(
                m, t.ca_file.empty() ? nullptr : t.ca_file.c_str(), t.ca_file.empty() ? "/etc/ssl/certs" : nullptr,
                t.cert_file.empty() ? nullptr : t.cert_file.c_str(), t.key_file.empty() ? nullptr : t.key_file.c_str(),
                t.key_password.empty() ? nullptr : &MosquittoTransport::key_password);
            if (rc != MOSQ_ERR_SUCCESS) {
                mosquitto_destroy(m);
                return connect_failed(fmt::format("TLS files not usable: {}", mosquitto_strerror(rc)), true);
            }
            mosquitto_tls_opts_set(m, t.verify_server ? 1 : 0, nullptr, nullptr);
            mosquitto_tls_insecure_set(m, !t.verify_server);
        }
#endif
        {
            std::unique_lock<std::shared_mutex> client(client_mutex_);
            mosq_ = m;
        }
        connected_ = false;
        lost_ = false;
        attempt_deadline_ = Steady::now() + options_.connect_timeout;
        next_misc_ = Steady::now() + std::chrono::seconds(1);
        const int keep_alive = static_cast<int>(effective_keep_alive(options_).count());
        const int rc = mosquitto_connect_async(m, broker.host.c_str(), broker.port, keep_alive);
        if (rc != MOSQ_ERR_SUCCESS) {
            // On loopback the TCP connection, and so the TLS handshake, can fail right here.
            attempt_failed(rc);
            drop_connection("connect failed");
        }
    }

    // Loop thread, never inside a libmosquitto callback.
    void drop_connection(const std::string& why) {
        const bool was_connected = connected_;
        connected_ = false;
        loop_->connect_done(this);
        loop_->watch(this, -1, false);  // before its socket closes (MqttLoop::watch)
        cloexec_fd_ = -1;
        destroy_client();
        {
            std::lock_guard<std::mutex> lock(acks_mutex_);
            in_flight_.clear();
        }
        // Unacknowledged messages wait again, in order, for the next connection.
        if (was_connected) outbox_.link_down();
        // The state first: until it reads disconnected, the statistics name
        // the broker of the link (the paho transport keeps the same order).
        set_state(LinkState::disconnected, why);
        if (was_connected) {
            // Lost soon after its CONNACK: a failed attempt, the back-off
            // grows and the next attempt goes to the next broker of the list
            // (connection_lost.hpp); a stable one is made again here first.
            const Steady::time_point now = Steady::now();
            const AfterLoss after = connection_lost(backoff_, brokers_, now);
            const milliseconds retry = backoff_.wait(rng_);
            if (after.moved) moved_on();
            if (!after.stable)
                link_.lost_early(after.lasted, backoff_.stable_period(), retry, after.moved ? brokers_.current().url : "");
            retry_at_ = now + retry;
        }
    }

    void destroy_client() {
        mosquitto* m = nullptr;
        {
            std::unique_lock<std::shared_mutex> client(client_mutex_);
            m = mosq_;
            mosq_ = nullptr;
        }
        if (m != nullptr) mosquitto_destroy(m);
    }

    void close_for_stop() {
        if (mosq_ != nullptr && connected_) {
            mosquitto_disconnect(mosq_);
            mosquitto_loop_write(mosq_, 1);  // best effort: a few bytes on an idle socket
        }
        connected_ = false;
        loop_->connect_done(this);
        loop_->watch(this, -1, false);
        destroy_client();
        std::lock_guard<std::mutex> lock(mutex_);
        closed_ = true;
        closed_cv_.notify_all();
    }

    // libmosquitto callbacks: loop thread, inside mosquitto_loop_*().

    static void on_connack(mosquitto*, void* self, int rc, int flags, const mosquitto_property*) {
        static_cast<MosquittoTransport*>(self)->connack(rc, flags);
    }
    void connack(int rc, int flags) {
        if (rc != 0) {
            // "Unacceptable protocol version" (3.1.1: 3.2.2.3 code 1; 5: 3.2.2.2 0x84).
            if ((rc == 1 || rc == 0x84) && try_other_protocol()) {
                connect_failed(fmt::format("the broker refused MQTT {}", protocol_ == 4 ? "5" : "3.1.1"), false);
                lose("protocol version refused");
                return;
            }
            // 3.1.1 return codes (3.2.2.3) and MQTT 5 reason codes (3.2.2.2).
            if (rc == 4 || rc == 0x86) connect_failed("the broker refused the user name or password", true);
            else if (rc == 5 || rc == 0x87)
                connect_failed("the broker refused the connection: not authorized (user name, password or certificate)", true);
            else if (rc == 2 || rc == 0x85) connect_failed("the broker refused the client id", true);
            else
                connect_failed(fmt::format("the broker refused the connection: {}",
                                           protocol_ >= 5 ? mosquitto_reason_string(rc) : mosquitto_connack_string(rc)),
                               false);
            lose("refused by the broker");
            return;
        }
        const bool session_present = (flags & 1) != 0;
        if (options_.mqtt_version == 0 && !protocol_settled_)
            logger_.info("mqtt: {} speaks MQTT {} (mqtt_version auto)", brokers_.current().url, protocol_ >= 5 ? "5" : "3.1.1");
        protocol_settled_ = true;
        if (!options_.clean_session) {
            if (session_established_ && !session_present) link_.session_lost();
            session_established_ = true;
        }
        connected_ = true;
        loop_->connect_done(this);
        watchdog_.connected(Steady::now());
        tls_verdict_.reset();
        backoff_.connected(Steady::now());  // back to reconnect_min only once it proves stable
        link_.nodelay_sockets(options_.tcp_nodelay ? 1 : 0);
        for (auto& [qos, filters] : subscriptions_.by_qos()) subscribe_now(std::move(filters), qos);
        link_.connected();
        set_state(LinkState::connected, brokers_.current().url);
        outbox_.link_up();
    }

    static void on_disconnected(mosquitto*, void* self, int rc) {
        auto* t = static_cast<MosquittoTransport*>(self);
        if (!t->connected_ && !t->lost_) {
            // Closed by the broker after the CONNECT, without a CONNACK: how
            // RabbitMQ 3.10 refuses an MQTT 5 CONNECT (docs/scaling.md).
            if (rc == MOSQ_ERR_CONN_LOST || rc == MOSQ_ERR_PROTOCOL) t->try_other_protocol();
            t->attempt_failed(rc);  // never got a CONNACK: refused TCP, TLS, ...
        }
        t->lose(rc == MOSQ_ERR_SUCCESS ? "disconnected" : mosquitto_strerror(rc));
    }
    // The client cannot be destroyed inside its own callback: after_io() drops it.
    void lose(const std::string& why) {
        if (lost_) return;
        lost_ = true;
        lost_reason_ = why;
    }

    static void on_published(mosquitto*, void* self, int mid) { static_cast<MosquittoTransport*>(self)->published(mid); }
    void published(int mid) {
        watchdog_.progress(Steady::now());
        std::uint64_t attempt = 0;
        {
            std::lock_guard<std::mutex> lock(acks_mutex_);
            const auto found = in_flight_.confirm(mid);
            if (!found) return;  // send() has not recorded it yet: it finds the confirmation
            attempt = *found;
        }
        outbox_.delivered(attempt);
    }

    static void on_received(mosquitto*, void* self, const mosquitto_message* msg) {
        static_cast<MosquittoTransport*>(self)->received(msg);
    }
    void received(const mosquitto_message* msg) {
        if (msg == nullptr || msg->topic == nullptr) return;
        link_.received();
        if (!on_message_) return;
        Message m{msg->topic, std::string(static_cast<const char*>(msg->payload), static_cast<std::size_t>(msg->payloadlen)),
                  msg->qos, msg->retain};
        on_message_(m);
    }

#if NCLINK_WITH_TLS
    // OpenSSL's user data here is the libmosquitto client, not ours.
    static int key_password(char* buf, int size, int, void* client) {
        auto* self = static_cast<MosquittoTransport*>(mosquitto_userdata(static_cast<mosquitto*>(client)));
        const std::string& pw = self->options_.tls->key_password;
        const int n = static_cast<int>(std::min<std::size_t>(pw.size(), static_cast<std::size_t>(size > 0 ? size - 1 : 0)));
        std::memcpy(buf, pw.data(), static_cast<std::size_t>(n));
        buf[n] = '\0';
        return n;
    }
#endif

    const MqttOptions options_;
    const Logger logger_;
    std::shared_ptr<MqttLoop> loop_;
    LinkRecord link_;
    BrokerRotation brokers_;  // loop thread only: which broker of the failover list
    Outbox outbox_;
    MessageHandler on_message_;
    LinkStateHandler on_state_;

    // The client is replaced on each attempt (loop thread, exclusive) while
    // other threads publish through it (shared).
    mutable std::shared_mutex client_mutex_;
    mosquitto* mosq_ = nullptr;

    std::mutex acks_mutex_;  // message id -> outbox attempt
    // Room for the outbox's window up front (at most 256 reserved: a larger
    // window grows it once).
    InFlightIds in_flight_{std::min<std::size_t>(options_.outbox.max_in_flight, 256)};

    std::mutex mutex_;  // started_, stopping_, closed_
    std::condition_variable closed_cv_;
    SubscriptionSet subscriptions_;
    bool started_ = false;
    bool stopping_ = false;
    bool closed_ = false;

    // loop thread only
    std::mt19937 rng_{std::random_device{}()};
    ReconnectBackoff backoff_{options_.reconnect_min, options_.reconnect_max};
    Steady::time_point retry_at_{};
    Steady::time_point attempt_deadline_{};
    Steady::time_point next_misc_{};
    bool lost_ = false;
    int cloexec_fd_ = -1;  // the socket last made close-on-exec (loop thread)
    std::string lost_reason_;
    AckWatchdog watchdog_;
    bool session_established_ = false;
    /// The protocol level of the next CONNECT: mqtt_version, or for 0
    /// ("auto") 5 until the broker refuses it (try_other_protocol()).
    int protocol_ = options_.mqtt_version == 0 ? 5 : options_.mqtt_version;
    bool protocol_settled_ = false;  ///< a CONNACK accepted protocol_
    bool fell_back_ = false;         ///< try_other_protocol() switched: the next attempt stays on the broker
    std::atomic<bool> connected_{false};
    std::future<std::optional<std::string>> diagnosis_;  // a TLS handshake of our own, under way
    std::optional<std::string> tls_verdict_;             // what it found
    std::string diagnosed_url_;                          // the broker it examines
};

}  // namespace

bool mosquitto_supports(const std::string& broker_url) {
    std::string host, scheme;
    int port = 0;
    if (!parse_broker_url(broker_url, host, port, scheme)) return false;
    return scheme == "tcp" || scheme == "mqtt" || scheme == "ssl" || scheme == "mqtts";
}

Result<std::unique_ptr<Transport>> make_mosquitto_transport(MqttOptions options, Logger logger, std::shared_ptr<MqttLoop> loop,
                                                            core_detail::PollHost* work) {
    if (options.client_id.empty()) return make_error(ErrorCode::parameter_missing, "MQTT client id is empty");
    if (!loop) return make_error(ErrorCode::parameter_missing, "MQTT loop missing");
    auto brokers = broker_list(options.broker_url, options.failover_urls);
    if (!brokers) return std::move(brokers).error();
    for (const BrokerAddress& broker : brokers.value())
        if (!mosquitto_supports(broker.url))
            return make_error(ErrorCode::value_type,
                              fmt::format("{}: the MQTT client of libnclink (libmosquitto) speaks tcp:// and ssl:// only; "
                                          "ws:// and wss:// need the paho transport of libnclink-plant",
                                          broker.url));
    const std::string& scheme = brokers.value().front().scheme;
    const bool tls = scheme == "ssl" || scheme == "mqtts" || options.tls;
    if (tls && !kWithTls)
        return make_error(ErrorCode::value_type,
                          fmt::format("{}: TLS to the broker is not available: this libnclink was built without it "
                                      "(NCLINK_WITH_TLS=OFF); use a tcp:// broker or a build with TLS",
                                      options.broker_url));
    if (tls && !options.tls) options.tls = MqttTlsOptions{};
    if (options.outbox.max_in_flight == 0) options.outbox.max_in_flight = 1;
    return std::unique_ptr<Transport>(std::make_unique<MosquittoTransport>(std::move(options), std::move(logger), std::move(loop),
                                                                           work, std::move(brokers).value()));
}

}  // namespace nclink::transport_detail

namespace nclink {

// A transport with its own loop: the loop lives as long as its one member
// (the transport holds the only reference), and its thread is the
// transport's callback thread.
Result<std::unique_ptr<Transport>> make_mqtt_transport(MqttOptions options, Logger logger) {
    return transport_detail::make_own_loop_transport(std::move(options), std::move(logger), nullptr);
}

}  // namespace nclink

namespace nclink::transport_detail {

Result<std::unique_ptr<Transport>> make_own_loop_transport(MqttOptions options, Logger logger, core_detail::PollHost* work) {
    if (options.client_id.empty()) return make_error(ErrorCode::parameter_missing, "MQTT client id is empty");
    if (auto usable = check_broker_url(options.broker_url); !usable) return std::move(usable).error();
    std::shared_ptr<MqttLoop> loop;
    try {
        loop = std::make_shared<MqttLoop>(logger);
    } catch (const std::exception& e) {  // no descriptor or thread left for it
        return make_error(ErrorCode::unavailable, fmt::format("MQTT client: {}", e.what()));
    }
    return make_mosquitto_transport(std::move(options), std::move(logger), std::move(loop), work);
}

}  // namespace nclink::transport_detail
