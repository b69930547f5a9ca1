// _nclink.Core: nclink::Client for Python. The Python class nclink.Client
// (python/nclink/_client.py) wraps it and shapes arguments; this file keeps
// the parts that must be C++: the GIL, the waits, the callbacks.
//
// Every request method takes `done`: None makes the call blocking (the
// caller waits with the GIL released, Ctrl-C ends the wait), a callable
// makes it asynchronous: done(value, None) or done(None, exception) runs
// once on the client's dispatch thread (nclink.Client turns this into
// awaitables). Every other callback also runs on the dispatch thread, one at
// a time, with the GIL taken for it (docs/python.md, "Threads").
#include "client_binding.hpp"

#include "errors.hpp"
#include "json_convert.hpp"
#include "py_callable.hpp"
#include "sample_batch.hpp"
#include "wait.hpp"

#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>

#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <type_traits>

namespace nclink::python {

namespace {

using std::chrono::milliseconds;

milliseconds to_ms(double seconds) {
    if (!(seconds >= 0) || !std::isfinite(seconds)) throw py::value_error("a time in seconds must be finite and >= 0");
    return milliseconds(static_cast<std::int64_t>(std::llround(seconds * 1000.0)));
}

RequestOptions request_options(const std::optional<double>& timeout_s) {
    RequestOptions options;
    if (timeout_s) options.timeout = to_ms(*timeout_s);
    return options;
}

/// "accepted", "refused", "no_answer": identifiers, as Python compares them.
std::string outcome_name(RegisterOutcome::Kind kind) {
    switch (kind) {
        case RegisterOutcome::Kind::accepted: return "accepted";
        case RegisterOutcome::Kind::refused: return "refused";
        case RegisterOutcome::Kind::no_answer: break;
    }
    return "no_answer";
}

py::object types(const char* name) { return py::module_::import("nclink._types").attr(name); }

/// The numeric code of an NG status: its `error`, else the code its reason
/// names, else 202 (a code table 19 does not define is answered 202).
int status_code(const ResponseStatus& status) {
    if (status.ok) return 0;
    if (status.error) return *status.error;
    if (status.reason) {
        if (auto code = error_code_from_reason(*status.reason)) return to_int(*code);
    }
    return to_int(ErrorCode::unavailable);
}

py::object optional_json(const std::optional<Json>& value) { return value ? to_python(*value) : py::none(); }
py::object optional_str(const std::optional<std::string>& value) { return value ? py::object(py::str(*value)) : py::none(); }

py::object msg_id(const MessageId& id) {
    if (!id) return py::none();
    if (id->is_string()) return py::str(id->get<std::string>());
    return py::str(id->dump());
}

py::object query_result(const QueryResult& r) {
    return types("QueryResult")(r.id, r.status.ok, optional_json(r.values), status_code(r.status), optional_str(r.status.reason),
                                optional_json(r.params), optional_json(r.private_info));
}

py::object set_result(const SetResult& r) {
    return types("SetResult")(r.id, r.status.ok, status_code(r.status), optional_str(r.status.reason), optional_json(r.params),
                              optional_json(r.private_info));
}

py::object method_status(const MethodStatus& s) {
    return types("MethodStatus")(msg_id(s.msg_id), s.guid, s.id, s.status,
                                 s.progress ? py::object(py::float_(*s.progress)) : py::none());
}

py::object method_result(const MethodResult& r) {
    return types("MethodResult")(msg_id(r.msg_id), r.guid, r.id, r.result, r.status.ok, status_code(r.status),
                                 optional_str(r.status.reason), optional_json(r.return_value), optional_json(r.private_info));
}

py::object event(const std::string& dev, const std::string& app, const EventData& e) {
    return types("Event")(e.id, e.guid.empty() ? dev : e.guid, app, e.time, e.event.id, to_python(e.event.value),
                          optional_json(e.event.old_value), optional_str(e.event.key),
                          e.event.index ? py::object(py::int_(*e.event.index)) : py::none(), optional_json(e.private_info));
}

py::dict stats_dict(const ClientStats& s) {
    py::dict transport;
    transport["published"] = s.transport.published;
    transport["received"] = s.transport.received;
    transport["dropped"] = s.transport.dropped;
    transport["dropped_bytes"] = s.transport.dropped_bytes;
    transport["connects"] = s.transport.connects;
    transport["connect_failures"] = s.transport.connect_failures;
    transport["buffered"] = s.transport.buffered;
    transport["buffered_bytes"] = s.transport.buffered_bytes;
    transport["in_flight"] = s.transport.in_flight;
    transport["sessions_lost"] = s.transport.sessions_lost;
    transport["last_error"] = s.transport.last_error;
    transport["refused"] = s.transport.refused;
    transport["failovers"] = s.transport.failovers;
    transport["broker"] = s.transport.broker;
    py::dict out;
    out["requests"] = s.requests;
    out["responses"] = s.responses;
    out["timeouts"] = s.timeouts;
    out["late_responses"] = s.late_responses;
    out["unmatched_responses"] = s.unmatched_responses;
    out["malformed"] = s.malformed;
    out["unreachable"] = s.unreachable;
    out["samples"] = s.samples;
    out["notifications"] = s.notifications;
    out["queued"] = s.queued;
    out["events"] = s.events;
    out["duplicates"] = s.duplicates;
    out["keepalives"] = s.keepalives;
    out["resent"] = s.resent;
    out["transport"] = std::move(transport);
    return out;
}

ChannelLayouts layouts_from(const py::dict& layouts) {
    ChannelLayouts out;
    for (auto item : layouts) {
        auto spec = item.second.cast<py::tuple>();
        if (spec.size() != 2) throw py::value_error("a channel layout is (interval_ms, [ids])");
        ChannelLayout layout;
        layout.interval_ms = spec[0].cast<double>();
        layout.ids = spec[1].cast<std::vector<std::string>>();
        out.emplace(item.first.cast<std::string>(), std::move(layout));
    }
    return out;
}

/// The less used options of ClientOptions and MqttOptions, given by name
/// (nclink.Client passes only those the caller set; the rest keep the C++
/// defaults, so they are written down once, in the headers).
void apply_advanced(const py::dict& d, MqttOptions& mqtt, ClientOptions& options) {
    for (auto item : d) {
        const auto key = item.first.cast<std::string>();
        const py::handle value = item.second;
        if (key == "max_queued_requests") {
            options.max_queued_requests = value.cast<std::size_t>();
        } else if (key == "duplicate_memory") {
            options.duplicate_memory = value.cast<std::size_t>();
        } else if (key == "stop_flush_timeout") {
            options.stop_flush_timeout = to_ms(value.cast<double>());
        } else if (key == "mqtt_version") {
            // "auto" is MqttOptions::mqtt_version 0: MQTT 5 first, 3.1.1 after
            // a broker refused 5 (a RabbitMQ 3.10 node, docs/configuration.md),
            // as the programs' "mqtt_version": "auto". Spelt as in their
            // configuration, not as the C++ 0.
            constexpr const char* expected = "mqtt_version: 4 (MQTT 3.1.1), 5 or \"auto\"";
            if (py::isinstance<py::str>(value)) {
                if (value.cast<std::string>() != "auto") throw py::value_error(expected);
                mqtt.mqtt_version = 0;
            } else {
                const int version = value.cast<int>();
                if (version != 4 && version != 5) throw py::value_error(expected);
                mqtt.mqtt_version = version;
            }
        } else if (key == "mqtt_keepalive") {
            mqtt.keep_alive = std::chrono::duration_cast<std::chrono::seconds>(to_ms(value.cast<double>()));
        } else if (key == "reconnect_min") {
            mqtt.reconnect_min = to_ms(value.cast<double>());
        } else if (key == "outbox_max_bytes") {
            mqtt.outbox.max_bytes = value.cast<std::size_t>();
        } else if (key == "outbox_max_in_flight") {
            mqtt.outbox.max_in_flight = value.cast<std::size_t>();
        } else if (key == "tcp_nodelay") {
            mqtt.tcp_nodelay = value.cast<bool>();
        } else if (key == "failover") {
            // Checked with the broker URL by the transport (Client::create): a
            // bad entry raises nclink.ValueTypeError (405) as a bad broker does.
            try {
                mqtt.failover_urls = value.cast<std::vector<std::string>>();
            } catch (const py::cast_error&) {
                throw py::value_error("failover: a list of broker URLs (strings)");
            }
        } else if (key == "last_will") {
            auto will = value.cast<py::tuple>();
            if (will.size() != 4) throw py::value_error("last_will is (topic, payload, qos, retain)");
            mqtt.last_will =
                Message{will[0].cast<std::string>(), will[1].cast<std::string>(), will[2].cast<int>(), will[3].cast<bool>()};
        } else {
            throw py::value_error("unknown client option: " + key);
        }
    }
}

}  // namespace

class PyClient {
public:
    PyClient(const std::string& broker, const std::string& client_id, const std::string& username, const std::string& password,
             const std::optional<py::dict>& tls, double timeout_s, double keepalive_s, bool clean_session,
             double connect_timeout_s, double reconnect_max_s, const std::string& log_level, const py::object& on_link_state,
             const std::optional<py::dict>& advanced)
        : broker_(broker) {
        MqttOptions mqtt;
        mqtt.broker_url = broker;
        mqtt.client_id = client_id;
        mqtt.username = username;
        mqtt.password = password;
        mqtt.clean_session = clean_session;
        mqtt.connect_timeout = to_ms(connect_timeout_s);
        mqtt.reconnect_max = to_ms(reconnect_max_s);
        if (tls) {
            MqttTlsOptions t;
            const py::dict& d = *tls;
            if (d.contains("ca_file")) t.ca_file = d["ca_file"].cast<std::string>();
            if (d.contains("cert_file")) t.cert_file = d["cert_file"].cast<std::string>();
            if (d.contains("key_file")) t.key_file = d["key_file"].cast<std::string>();
            if (d.contains("key_password")) t.key_password = d["key_password"].cast<std::string>();
            if (d.contains("verify_server")) t.verify_server = d["verify_server"].cast<bool>();
            mqtt.tls = t;
        }
        ClientOptions options;
        options.ex_cid = client_id;
        options.default_timeout = to_ms(timeout_s);
        options.keepalive_interval = to_ms(keepalive_s);
        if (advanced) apply_advanced(*advanced, mqtt, options);
        auto level = log_level_from_string(log_level);
        if (!level) throw py::value_error("log_level: trace, debug, info, warn, error or off");
        if (*level != LogLevel::off) options.logger = Logger(stderr_sink(), *level);
        PyCallable link_cb(on_link_state);
        if (!link_cb.empty()) {
            options.on_link_state = [this, link_cb](LinkState state) {
                link_cb.call(this, [&] { return py::make_tuple(std::string(to_string(state))); });
            };
        }
        auto created = Client::create(mqtt, std::move(options));
        if (!created) raise_error(created.error());
        client_ = std::move(created).value();
    }

    ~PyClient() {
        // pybind11 destroys the object with the GIL held; the dispatch
        // thread may be waiting for it to run a last callback.
        if (client_) {
            py::gil_scoped_release nogil;
            client_->stop();
        }
    }

    // ---- connection -------------------------------------------------------------
    std::string connect(double timeout_s, bool do_register, std::optional<double> register_timeout_s) {
        refuse_on_dispatch();
        start();
        const auto deadline = std::chrono::steady_clock::now() + to_ms(timeout_s);
        for (;;) {
            bool up = false;
            {
                py::gil_scoped_release nogil;
                up = client_->wait_connected(signal_poll);
            }
            if (up) break;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            ClientStats stats;
            {
                py::gil_scoped_release nogil;
                stats = client_->stats();
            }
            // Refused (credentials, a certificate): no use waiting on, as
            // nclink::Client::connect() does not.
            if (stats.transport.refused || std::chrono::steady_clock::now() >= deadline) {
                const std::string why = stats.transport.last_error.empty()
                                            ? "no connection within " + std::to_string(timeout_s) + " s"
                                            : stats.transport.last_error;
                raise_error(make_error(stats.transport.refused ? ErrorCode::permission_denied : ErrorCode::timeout,
                                       "could not connect to the broker " + broker_ + ": " + why));
            }
        }
        if (!do_register) return "not_sent";
        auto outcome = wait_for_result<RegisterOutcome>(
            [&](auto done) { client_->register_async(std::move(done), request_options(register_timeout_s)); });
        if (!outcome) {
            if (outcome.error().code == ErrorCode::timeout) return "no_answer";
            raise_error(outcome.error());
        }
        return outcome_name(outcome->kind);
    }

    void close() {
        py::gil_scoped_release nogil;
        client_->stop();
    }

    // ---- requests ---------------------------------------------------------------
    py::object register_terminal(std::optional<double> timeout, const py::object& done) {
        return request<RegisterOutcome>(
            done, [this, o = request_options(timeout)](auto cb) { client_->register_async(std::move(cb), o); },
            [](RegisterOutcome r) { return py::str(outcome_name(r.kind)); });
    }

    py::object discover(std::optional<double> timeout, const py::object& done) {
        return request<std::vector<DeviceListEntry>>(
            done, [this, o = request_options(timeout)](auto cb) { client_->discover_async(std::move(cb), o); },
            [](std::vector<DeviceListEntry> list) {
                py::list out;
                for (const auto& d : list) out.append(types("Device")(d.guid, d.status, d.last_alive_time_stamp));
                return out;
            });
    }

    py::object probe(const std::string& dev, std::optional<double> timeout, const py::object& done) {
        return request<Json>(
            done, [this, dev, o = request_options(timeout)](auto cb) { client_->probe_async(dev, std::move(cb), o); },
            [](Json model) { return to_python(model); });
    }

    py::object probe_set(const std::string& dev, const py::object& model, std::optional<double> timeout, const py::object& done) {
        Json m = from_python(model);
        return request<void>(
            done, [this, dev, m, o = request_options(timeout)](auto cb) { client_->probe_set_async(dev, m, std::move(cb), o); },
            [] { return py::none(); });
    }

    py::object query(const std::string& dev, const py::list& items, std::optional<double> timeout, const py::object& done) {
        std::vector<QueryItem> q;
        q.reserve(items.size());
        for (auto item : items) {
            auto pair = item.cast<py::tuple>();
            QueryItem qi;
            qi.id = pair[0].cast<std::string>();
            if (!pair[1].is_none()) qi.params = from_python(pair[1]);
            q.push_back(std::move(qi));
        }
        return request<std::vector<QueryResult>>(
            done,
            [this, dev, list = std::move(q), o = request_options(timeout)](auto cb) {
                client_->query_async(dev, list, std::move(cb), o);
            },
            [](std::vector<QueryResult> results) {
                py::list out;
                for (const auto& r : results) out.append(query_result(r));
                return out;
            });
    }

    py::object set(const std::string& dev, const py::list& items, std::optional<double> timeout, const py::object& done) {
        std::vector<SetItem> s;
        s.reserve(items.size());
        for (auto item : items) {
            auto pair = item.cast<py::tuple>();
            SetItem si;
            si.id = pair[0].cast<std::string>();
            if (!pair[1].is_none()) si.params = from_python(pair[1]);
            s.push_back(std::move(si));
        }
        return request<std::vector<SetResult>>(
            done,
            [this, dev, list = std::move(s), o = request_options(timeout)](auto cb) {
                client_->set_async(dev, list, std::move(cb), o);
            },
            [](std::vector<SetResult> results) {
                py::list out;
                for (const auto& r : results) out.append(set_result(r));
                return out;
            });
    }

    // ---- methods ----------------------------------------------------------------
    py::object call_method(const std::string& dev, const std::string& method, const py::object& args, const py::object& on_status,
                           std::optional<double> timeout, const py::object& done) {
        Json a = args.is_none() ? Json() : from_python(args);
        PyCallable status_cb(on_status);
        std::function<void(const MethodStatus&)> status_fn;
        if (!status_cb.empty()) {
            status_fn = [this, status_cb](const MethodStatus& s) {
                status_cb.call(this, [&] { return py::make_tuple(method_status(s)); });
            };
        }
        return request<MethodResult>(
            done,
            [this, dev, method, a, status_fn, o = request_options(timeout)](auto cb) {
                client_->call_method_async(dev, method, a, status_fn, std::move(cb), o);
            },
            [](MethodResult r) { return method_result(r); });
    }

    py::object control_method(const std::string& dev, const std::string& method, const std::string& action,
                              const std::optional<std::string>& call_id, std::optional<double> timeout, const py::object& done) {
        Client::MethodAction a;
        if (action == "stop") a = Client::MethodAction::stop;
        else if (action == "resume") a = Client::MethodAction::resume;
        else if (action == "cancel") a = Client::MethodAction::cancel;
        else raise_error(make_error(ErrorCode::method_action_type, "action must be stop, resume or cancel"));
        RequestOptions o = request_options(timeout);
        if (call_id) o.private_info = Json{{"call", *call_id}};
        return request<void>(
            done, [this, dev, method, a, o](auto cb) { client_->control_method_async(dev, method, a, std::move(cb), o); },
            [] { return py::none(); });
    }

    // ---- dynamic sampling -------------------------------------------------------
    py::object register_sampling(const std::string& dev, const std::vector<std::string>& ids, double sample_ms, double upload_ms,
                                 const py::object& on_batch, std::optional<int> qos, std::optional<double> timeout,
                                 const py::object& done) {
        if (!(sample_ms > 0) || !(upload_ms > 0)) throw py::value_error("sample_ms and upload_ms must be > 0");
        auto layout = std::make_shared<ChannelLayout>();
        layout->ids = ids;
        layout->interval_ms = sample_ms;
        SampleHandler handler = batch_handler(dev, on_batch, layout, nullptr);
        RequestOptions o = request_options(timeout);
        if (qos) o.private_info = Json{{"qos", *qos}};
        auto sample = milliseconds(static_cast<std::int64_t>(std::llround(sample_ms)));
        auto upload = milliseconds(static_cast<std::int64_t>(std::llround(upload_ms)));
        return request<Client::SamplingChannel>(
            done,
            [this, dev, ids, sample, upload, handler, o](auto cb) {
                client_->register_sampling_async(dev, ids, sample, upload, handler, std::move(cb), o);
            },
            [this](Client::SamplingChannel channel) {
                std::string id = channel.id;
                std::lock_guard<std::mutex> lock(channels_mutex_);
                channels_[{channel.dev, id}] = std::move(channel);
                return py::str(id);
            });
    }

    py::object unregister_sampling(const std::string& dev, const std::string& channel_id, std::optional<double> timeout,
                                   const py::object& done) {
        Client::SamplingChannel channel;
        {
            std::lock_guard<std::mutex> lock(channels_mutex_);
            auto it = channels_.find({dev, channel_id});
            if (it == channels_.end()) {
                raise_error(
                    make_error(ErrorCode::node_not_exists, "no dynamic channel " + channel_id + " of this client at " + dev));
            }
            channel = it->second;
            channels_.erase(it);
        }
        return request<void>(
            done,
            [this, channel, o = request_options(timeout)](auto cb) {
                client_->unregister_sampling_async(channel, std::move(cb), o);
            },
            [] { return py::none(); });
    }

    // ---- events -----------------------------------------------------------------
    py::object register_event(const std::string& dev, const std::string& id, const std::optional<std::string>& key,
                              const std::optional<std::int64_t>& index, const py::list& filters, const std::string& trigger,
                              const py::object& on_event, std::optional<double> timeout, const py::object& done) {
        Client::EventRegistration r;
        r.id = id;
        r.key = key;
        r.index = index;
        for (auto f : filters) r.filters.push_back(from_python(f));
        r.trigger = trigger;
        PyCallable cb(on_event);
        Client::EventHandler handler = [this, cb, dev](const EventData& e) {
            cb.call(this, [&] { return py::make_tuple(event(dev, "", e)); });
        };
        return request<std::string>(
            done,
            [this, dev, r, handler, o = request_options(timeout)](auto done_cb) {
                client_->register_event_async(dev, r, handler, std::move(done_cb), o);
            },
            [](std::string event_id) { return py::str(event_id); });
    }

    py::object unregister_event(const std::string& dev, const std::string& event_id, std::optional<double> timeout,
                                const py::object& done) {
        return request<void>(
            done,
            [this, dev, event_id, o = request_options(timeout)](auto cb) {
                client_->unregister_event_async(dev, event_id, std::move(cb), o);
            },
            [] { return py::none(); });
    }

    // ---- model cache (8.2.5.3, 8.2.7.3) -------------------------------------------
    /// Follows dev's model: probes it now and whenever the adapter announces
    /// another version; on_model(dev, model) gets each model fetched. Needs a
    /// started client: before connect() the first fetch could only fail.
    void follow_model(const std::string& dev, const py::object& on_model) {
        {
            std::lock_guard<std::mutex> lock(start_mutex_);
            if (!started_) raise_error(make_error(ErrorCode::unavailable, "follow_model: connect() first"));
        }
        PyCallable cb(on_model);
        Client::ModelHandler handler;
        if (!cb.empty()) {
            handler = [this, cb](const std::string& d, const Json& model) {
                cb.call(this, [&] { return py::make_tuple(d, to_python(model)); });
            };
        }
        Result<void> r;
        {
            py::gil_scoped_release nogil;
            r = client_->follow_model(dev, std::move(handler));
        }
        if (!r) raise_error(r.error());
    }

    py::object cached_model(const std::string& dev) const {
        std::optional<Json> model;
        {
            py::gil_scoped_release nogil;
            model = client_->cached_model(dev);
        }
        return optional_json(model);
    }

    std::string cached_model_version(const std::string& dev) const {
        py::gil_scoped_release nogil;
        return client_->cached_model_version(dev);
    }

    // ---- subscriptions ----------------------------------------------------------
    SubscriptionId subscribe_samples(const std::string& dev, const std::optional<std::string>& channel, const py::dict& layouts,
                                     const py::object& on_batch) {
        auto table = std::make_shared<const ChannelLayouts>(layouts_from(layouts));
        SampleHandler handler = batch_handler(dev, on_batch, nullptr, table);
        return subscribed([&] { return client_->subscribe_samples(dev, handler, channel); });
    }

    SubscriptionId subscribe_state(const std::optional<std::string>& tid, const py::object& on_state) {
        PyCallable cb(on_state);
        StateHandler handler = [this, cb](const NotifyState& s) {
            cb.call(this, [&] { return py::make_tuple(types("StateChange")(s.tid, s.state)); });
        };
        if (tid) return subscribed([&] { return client_->subscribe_state(*tid, handler); });
        return subscribed([&] { return client_->subscribe_all_states(handler); });
    }

    SubscriptionId subscribe_version(const std::string& dev, const py::object& on_version) {
        PyCallable cb(on_version);
        VersionHandler handler = [this, cb, dev](const ProbeVersionRequest& v) {
            cb.call(this, [&] { return py::make_tuple(types("VersionChange")(v.guid.empty() ? dev : v.guid, v.version)); });
        };
        return subscribed([&] { return client_->subscribe_version(dev, handler); });
    }

    SubscriptionId subscribe_method_runs(const std::string& dev, const py::object& on_run) {
        PyCallable cb(on_run);
        MethodRunHandler handler = [this, cb](const MethodRun& run) {
            cb.call(this, [&] {
                return py::make_tuple(types("MethodRun")(std::string(to_string(run.kind)), run.dev, run.ex,
                                                         run.status ? method_status(*run.status) : py::none(),
                                                         run.result ? method_result(*run.result) : py::none()));
            });
        };
        return subscribed([&] { return client_->subscribe_method_runs(dev, handler); });
    }

    SubscriptionId subscribe_events(const std::string& dev, const py::object& on_event) {
        PyCallable cb(on_event);
        WatchedEventHandler handler = [this, cb](const WatchedEvent& w) {
            cb.call(this, [&] { return py::make_tuple(event(w.dev, w.ex, w.event)); });
        };
        return subscribed([&] { return client_->subscribe_events(dev, handler); });
    }

    void unsubscribe(SubscriptionId id) {
        Result<void> r;
        {
            py::gil_scoped_release nogil;
            r = client_->unsubscribe(id);
        }
        if (!r) raise_error(r.error());
    }

    // ---- introspection ----------------------------------------------------------
    py::dict stats() const {
        ClientStats s;
        {
            py::gil_scoped_release nogil;
            s = client_->stats();
        }
        return stats_dict(s);
    }
    std::string link_state() const { return std::string(to_string(client_->link_state())); }
    std::string state() const { return std::string(to_string(client_->state())); }
    std::size_t pending_requests() const { return client_->pending_requests(); }
    std::size_t event_registrations() const { return client_->event_registrations(); }
    std::uint64_t model_reprobes() const { return client_->model_reprobes(); }
    std::uint64_t reregistrations() const { return client_->reregistrations(); }
    std::string client_id() const { return client_->ex_cid(); }
    /// True on this client's dispatch thread, in a callback (a blocking wait there would never end).
    bool in_callback() const { return dispatching_client == this; }

private:
    void start() {
        std::lock_guard<std::mutex> lock(start_mutex_);
        if (started_) return;
        Result<void> r;
        {
            py::gil_scoped_release nogil;
            r = client_->start();
        }
        if (!r) raise_error(r.error());
        started_ = true;
    }

    void refuse_on_dispatch() const {
        if (dispatching_client == this) {
            raise_error(make_error(ErrorCode::unavailable,
                                   "a blocking call from a callback of the same client would wait for its own "
                                   "thread: use the asynchronous form (await client.a...(), or done=)"));
        }
    }

    /// Blocking (done is None) or asynchronous (done(value, error) on the dispatch thread).
    template <class T, class Start, class Convert>
    py::object request(const py::object& done, Start start, Convert convert) {
        if (done.is_none()) {
            refuse_on_dispatch();
            Result<T> result = wait_for_result<T>(start);
            if (!result) raise_error(result.error());
            if constexpr (std::is_void_v<T>) {
                return convert();
            } else {
                return convert(std::move(result).value());
            }
        }
        PyCallable callback(done);
        {
            py::gil_scoped_release nogil;
            start([this, callback, convert](Result<T> result) {
                callback.call(this, [&]() -> py::tuple {
                    if (!result) return py::make_tuple(py::none(), make_exception(result.error()));
                    if constexpr (std::is_void_v<T>) {
                        return py::make_tuple(convert(), py::none());
                    } else {
                        return py::make_tuple(convert(std::move(result).value()), py::none());
                    }
                });
            });
        }
        return py::none();
    }

    template <class Subscribe>
    SubscriptionId subscribed(Subscribe&& subscribe) {
        std::optional<Result<SubscriptionId>> r;
        {
            py::gil_scoped_release nogil;
            r.emplace(subscribe());
        }
        if (!*r) raise_error(r->error());
        return r->value();
    }

    /// A Sample handler handing SampleBatch objects to on_batch: the layout of
    /// a dynamic channel, or the table of a device's model channels.
    SampleHandler batch_handler(const std::string& dev, const py::object& on_batch, std::shared_ptr<const ChannelLayout> fixed,
                                std::shared_ptr<const ChannelLayouts> table) {
        PyCallable cb(on_batch);
        return [this, cb, dev, fixed, table](const SampleDtu& dtu) {
            const ChannelLayout* layout = fixed.get();
            if (!layout && table) {
                auto it = table->find(dtu.id);
                if (it != table->end()) layout = &it->second;
            }
            auto batch = std::make_shared<SampleBatch>(dev, dtu, layout);
            cb.call(this, [&] { return py::make_tuple(py::cast(std::move(batch))); });
        };
    }

    std::string broker_;
    std::unique_ptr<Client> client_;
    std::mutex start_mutex_;
    bool started_ = false;
    std::mutex channels_mutex_;
    std::map<std::pair<std::string, std::string>, Client::SamplingChannel> channels_;
};

void bind_client(py::module_& m) {
    using py::arg;
    const auto none = py::none();
    py::class_<PyClient>(m, "Core", "nclink::Client (use nclink.Client)")
        .def(
            py::init<const std::string&, const std::string&, const std::string&, const std::string&, const std::optional<py::dict>&,
                     double, double, bool, double, double, const std::string&, const py::object&, const std::optional<py::dict>&>(),
            arg("broker"), arg("client_id"), arg("username") = "", arg("password") = "", arg("tls") = none, arg("timeout") = 2.0,
            arg("keepalive") = 60.0, arg("clean_session") = true, arg("connect_timeout") = 5.0, arg("reconnect_max") = 10.0,
            arg("log_level") = "error", arg("on_link_state") = none, arg("advanced") = none)
        .def("connect", &PyClient::connect, arg("timeout"), arg("register"), arg("register_timeout") = none)
        .def("close", &PyClient::close)
        .def("register", &PyClient::register_terminal, arg("timeout") = none, arg("done") = none)
        .def("discover", &PyClient::discover, arg("timeout") = none, arg("done") = none)
        .def("probe", &PyClient::probe, arg("dev"), arg("timeout") = none, arg("done") = none)
        .def("probe_set", &PyClient::probe_set, arg("dev"), arg("model"), arg("timeout") = none, arg("done") = none)
        .def("query", &PyClient::query, arg("dev"), arg("items"), arg("timeout") = none, arg("done") = none)
        .def("set", &PyClient::set, arg("dev"), arg("items"), arg("timeout") = none, arg("done") = none)
        .def("call_method", &PyClient::call_method, arg("dev"), arg("method"), arg("args"), arg("on_status"),
             arg("timeout") = none, arg("done") = none)
        .def("control_method", &PyClient::control_method, arg("dev"), arg("method"), arg("action"), arg("call_id") = none,
             arg("timeout") = none, arg("done") = none)
        .def("register_sampling", &PyClient::register_sampling, arg("dev"), arg("ids"), arg("sample_ms"), arg("upload_ms"),
             arg("on_batch"), arg("qos") = none, arg("timeout") = none, arg("done") = none)
        .def("unregister_sampling", &PyClient::unregister_sampling, arg("dev"), arg("channel"), arg("timeout") = none,
             arg("done") = none)
        .def("register_event", &PyClient::register_event, arg("dev"), arg("id"), arg("key"), arg("index"), arg("filters"),
             arg("trigger"), arg("on_event"), arg("timeout") = none, arg("done") = none)
        .def("unregister_event", &PyClient::unregister_event, arg("dev"), arg("event_id"), arg("timeout") = none, arg("done") = none)
        .def("subscribe_samples", &PyClient::subscribe_samples, arg("dev"), arg("channel"), arg("layouts"), arg("on_batch"))
        .def("subscribe_state", &PyClient::subscribe_state, arg("tid"), arg("on_state"))
        .def("subscribe_version", &PyClient::subscribe_version, arg("dev"), arg("on_version"))
        .def("subscribe_method_runs", &PyClient::subscribe_method_runs, arg("dev"), arg("on_run"))
        .def("subscribe_events", &PyClient::subscribe_events, arg("dev"), arg("on_event"))
        .def("unsubscribe", &PyClient::unsubscribe, arg("subscription"))
        .def("follow_model", &PyClient::follow_model, arg("dev"), arg("on_model") = none)
        .def("cached_model", &PyClient::cached_model, arg("dev"))
        .def("cached_model_version", &PyClient::cached_model_version, arg("dev"))
        .def("stats", &PyClient::stats)
        .def_property_readonly("link_state", &PyClient::link_state)
        .def_property_readonly("state", &PyClient::state)
        .def_property_readonly("pending_requests", &PyClient::pending_requests)
        .def_property_readonly("event_registrations", &PyClient::event_registrations)
        .def_property_readonly("model_reprobes", &PyClient::model_reprobes)
        .def_property_readonly("reregistrations", &PyClient::reregistrations)
        .def_property_readonly("client_id", &PyClient::client_id)
        .def_property_readonly("in_callback", &PyClient::in_callback);
}

}  // namespace nclink::python
