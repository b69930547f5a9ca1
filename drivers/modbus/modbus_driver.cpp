#include "modbus/modbus_driver.hpp"

#include "modbus/modbus_bus.hpp"

#include <modbus.h>

#include <cerrno>
#include <cstring>

namespace nclink::modbus {

/// The way requests reach the PLC: one libmodbus TCP connection of this
/// driver's own, or this driver's slave on a shared RTU line. Not
/// thread-safe: the driver is serialized (the line serializes its users).
class Connection {
public:
    virtual ~Connection() = default;
    /// Runs one request (a libmodbus call, -1 and errno on failure).
    virtual Bus::Reply run(const std::function<int(modbus_t*)>& request) = 0;
};

namespace {

/// A Modbus exception answer (the PLC is there and refuses this request:
/// illegal address, illegal value, ...) as opposed to a lost connection.
bool is_exception(int err) { return err >= EMBXILFUN && err <= EMBXGTAR; }

std::string errno_text(int err) { return modbus_strerror(err); }

/// One libmodbus TCP context.
class TcpConnection final : public Connection {
public:
    explicit TcpConnection(const Config& c) : ctx_(modbus_new_tcp(c.host.c_str(), c.port)) {
        if (!ctx_) return;
        modbus_set_slave(ctx_, c.unit_id);
        const auto ms = c.timeout.count();
        modbus_set_response_timeout(ctx_, static_cast<std::uint32_t>(ms / 1000), static_cast<std::uint32_t>((ms % 1000) * 1000));
    }
    ~TcpConnection() override {
        if (!ctx_) return;
        modbus_close(ctx_);
        modbus_free(ctx_);
    }
    TcpConnection(const TcpConnection&) = delete;
    TcpConnection& operator=(const TcpConnection&) = delete;

    modbus_t* get() const { return ctx_; }

    Bus::Reply run(const std::function<int(modbus_t*)>& request) override {
        Bus::Reply reply;
        const int n = request(ctx_);
        if (n != -1) {
            reply.value = n;
            return reply;
        }
        const int err = errno;
        // On TCP every failure but an exception means the connection is gone
        // (a timeout too): the driver reconnects.
        reply.outcome = is_exception(err) ? Outcome::exception : Outcome::line_down;
        reply.detail = errno_text(err);
        return reply;
    }

private:
    modbus_t* ctx_;
};

/// This driver's slave on a serial line shared with other drivers.
class RtuConnection final : public Connection {
public:
    RtuConnection(std::shared_ptr<Bus> bus, const Config& c)
        : bus_(std::move(bus)), slave_{c.unit_id, c.timeout, c.byte_timeout} {}
    Bus::Reply run(const std::function<int(modbus_t*)>& request) override { return bus_->transact(slave_, request); }

private:
    std::shared_ptr<Bus> bus_;
    SlaveSettings slave_;
};

}  // namespace

ModbusDriver::ModbusDriver(std::optional<Config> config, Clock clock, std::shared_ptr<BusRegistry> buses)
    : config_(std::move(config)),
      clock_(clock ? std::move(clock) : Clock([] { return std::chrono::steady_clock::now(); })),
      buses_(buses ? std::move(buses) : std::make_shared<BusRegistry>()) {
    rtu_ = config_ && config_->serial;
}

ModbusDriver::~ModbusDriver() = default;

DriverInfo ModbusDriver::info() const { return DriverInfo{rtu_ ? "modbus-rtu" : "modbus-tcp", "1.0", false}; }

Result<void> ModbusDriver::open(const DriverContext& context) {
    logger_ = context.logger;
    if (!config_) {
        auto parsed = parse_config(context.config);
        if (!parsed.ok()) return std::move(parsed).error();
        config_ = std::move(parsed).value();
    }
    rtu_ = config_->serial.has_value();
    backoff_ = config_->backoff_min;
    if (config_->serial) {
        // Every machine of the process naming this device shares its line.
        auto bus = buses_->attach(*config_->serial);
        if (!bus.ok()) return std::move(bus).error();
        bus_ = std::move(bus).value();
        // A device that is not there yet is not fatal (a USB adapter plugged
        // in later): the items answer Unavailable until it opens.
        if (auto opened = bus_->open(); opened.outcome != Outcome::ok) {
            lost(opened.detail);
            logger_.warn("modbus {}: not reachable at start ({}); retrying in the background of reads", config_->endpoint(),
                         opened.detail);
        }
        return ok_result();
    }
    // A PLC that is not there at start is not fatal: the adapter comes up,
    // its items answer Unavailable, and the driver keeps trying (a gateway
    // starts before the machines are switched on).
    if (auto r = ensure_connected(); !r.ok())
        logger_.warn("modbus {}: not reachable at start ({}); retrying in the background of reads", config_->endpoint(),
                     r.error().message);
    return ok_result();
}

void ModbusDriver::close() {
    connection_.reset();
    bus_.reset();
    link_ = MachineLink::disconnected;
}

MachineLinkStatus ModbusDriver::link() const {
    const MachineLink state = link_.load();
    if (state != MachineLink::disconnected) return {state, {}};
    // Disconnected only while the backoff lasts: when the next attempt is
    // due the SDK must call read() again, which is where reconnecting happens.
    const auto now = (clock_ ? clock_() : std::chrono::steady_clock::now()).time_since_epoch().count();
    if (now >= next_attempt_ticks_.load(std::memory_order_acquire)) return {MachineLink::unknown, {}};
    return {MachineLink::disconnected,
            "DEV_UNREACHABLE: modbus " + (config_ ? config_->endpoint() : std::string("PLC")) + " not reachable"};
}

ModbusDriver::Stats ModbusDriver::stats() const { return Stats{requests_.load(), connects_.load(), failures_.load()}; }

Error ModbusDriver::unreachable(const std::string& what) const {
    // The reason on the wire is table 19's "Unavailable"; the detail names the
    // PLC and DEV_UNREACHABLE (8.3.4's word for a terminal that cannot be reached).
    return make_error(ErrorCode::unavailable, std::string(dev_unreachable_reason) + ": modbus " + config_->endpoint() + " " + what);
}

Error ModbusDriver::no_answer() const {
    // Table 19's Timeout: the line works, the slave did not answer in time.
    return make_error(ErrorCode::timeout, std::string(dev_unreachable_reason) + ": modbus " + config_->endpoint() +
                                              " did not answer within " + std::to_string(config_->timeout.count()) + " ms");
}

void ModbusDriver::answered() {
    // RTU: the slave answering is what makes the machine connected (opening
    // the shared line says nothing about this slave).
    if (!config_->serial) return;
    if (link_.exchange(MachineLink::connected) != MachineLink::connected) {
        ++connects_;
        logger_.info("modbus {}: answering", config_->endpoint());
    }
    backoff_ = config_->backoff_min;
}

void ModbusDriver::lost(const std::string& why) {
    ++failures_;
    connection_.reset();
    if (link_.exchange(MachineLink::disconnected) != MachineLink::disconnected) {
        if (config_->serial) logger_.warn("modbus {}: not answering ({}); asking again with backoff", config_->endpoint(), why);
        else logger_.warn("modbus {}: connection lost ({}); reconnecting with backoff", config_->endpoint(), why);
    }
    last_failure_ = why;
    next_attempt_ = clock_() + backoff_;
    next_attempt_ticks_.store(next_attempt_.time_since_epoch().count(), std::memory_order_release);
    backoff_ = std::min(backoff_ * 2, config_->backoff_max);
}

Result<void> ModbusDriver::ensure_connected() {
    if (connection_) return ok_result();
    const auto now = clock_();
    if (now < next_attempt_) {
        const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next_attempt_ - now).count();
        return unreachable("not connected (" + last_failure_ + "); next attempt in " + std::to_string(wait) + " ms");
    }
    if (config_->serial) {
        // No I/O here: the line opens (again) in the bus's turn.
        connection_ = std::make_unique<RtuConnection>(bus_, *config_);
        return ok_result();
    }
    auto c = std::make_unique<TcpConnection>(*config_);
    if (!c->get()) {
        lost("cannot create a Modbus TCP context");
        return unreachable("cannot create a Modbus TCP context");
    }
    if (modbus_connect(c->get()) == -1) {
        const std::string why = "connect: " + errno_text(errno);
        lost(why);
        return unreachable(why);
    }
    connection_ = std::move(c);
    backoff_ = config_->backoff_min;
    ++connects_;
    if (link_.exchange(MachineLink::connected) != MachineLink::connected)
        logger_.info("modbus {}: connected (unit {})", config_->endpoint(), config_->unit_id);
    return ok_result();
}

void ModbusDriver::read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) {
    std::vector<const Point*> mapped(points.size(), nullptr);
    for (std::size_t i = 0; i < points.size(); ++i) {
        mapped[i] = config_ ? config_->find(points[i].id) : nullptr;
        if (!mapped[i])
            results[i] = make_error(ErrorCode::unavailable, "modbus: " + points[i].id + " is not in the driver's map");
    }
    if (!config_) return;
    const auto spans = plan_reads(mapped, config_->max_gap);
    std::vector<std::uint16_t> words;
    std::vector<std::uint8_t> bits;
    for (std::size_t s = 0; s < spans.size(); ++s) {
        const ReadSpan& span = spans[s];
        if (auto r = ensure_connected(); !r.ok()) {
            for (std::size_t rest = s; rest < spans.size(); ++rest)
                for (std::size_t m : spans[rest].members) results[m] = r.error();
            return;
        }
        ++requests_;
        const Bus::Reply reply = connection_->run([&](modbus_t* ctx) {
            switch (span.table) {
                case Table::holding_register:
                    words.resize(span.count);
                    return modbus_read_registers(ctx, span.start, span.count, words.data());
                case Table::input_register:
                    words.resize(span.count);
                    return modbus_read_input_registers(ctx, span.start, span.count, words.data());
                case Table::coil: bits.resize(span.count); return modbus_read_bits(ctx, span.start, span.count, bits.data());
                case Table::discrete_input:
                    bits.resize(span.count);
                    return modbus_read_input_bits(ctx, span.start, span.count, bits.data());
            }
            return -1;
        });
        if (reply.outcome == Outcome::exception || reply.outcome == Outcome::bad_frame) {
            ++failures_;
            // The PLC refused the request, or its answer arrived damaged: the
            // items of this request only; the connection and the line stay.
            const std::string what = reply.outcome == Outcome::exception ? ": the PLC refused the read: " : ": damaged answer: ";
            for (std::size_t m : span.members)
                results[m] = make_error(ErrorCode::unavailable, "modbus " + points[m].id + what + reply.detail);
            if (reply.outcome == Outcome::exception) answered();
            continue;
        }
        if (reply.outcome != Outcome::ok) {
            // A transport failure (TCP: the connection is gone; RTU: the slave
            // is silent or the device failed): this span and every later one
            // answer the same (the next call retries after backoff).
            const Error failed = reply.outcome == Outcome::no_answer ? no_answer() : unreachable("read failed: " + reply.detail);
            lost("read: " + reply.detail);
            for (std::size_t rest = s; rest < spans.size(); ++rest)
                for (std::size_t m : spans[rest].members) results[m] = failed;
            return;
        }
        answered();
        for (std::size_t m : span.members) {
            const Point& p = *mapped[m];
            const std::size_t at = p.address - span.start;
            if (span.table == Table::coil || span.table == Table::discrete_input) results[m] = decode_bit(p, bits[at] != 0);
            else results[m] = decode(p, words.data() + at);
        }
    }
}

Result<void> ModbusDriver::write(const WriteRequest& request) {
    const Point* p = config_ ? config_->find(request.id) : nullptr;
    if (!p) return make_error(ErrorCode::permission_denied, "modbus: " + request.id + " is not in the driver's map");
    if (!p->writable())
        return make_error(ErrorCode::permission_denied,
                          "modbus " + request.id + ": an input register or discrete input cannot be written");
    // The map's points are whole values; the SDK computed the item's value
    // after the Set's operation.
    const Json& value = request.new_value.is_null() && request.params.is_object() && request.params.contains("value")
                            ? request.params["value"]
                            : request.new_value;
    auto encoded = encode(*p, value);
    if (!encoded.ok()) return std::move(encoded).error();
    if (auto r = ensure_connected(); !r.ok()) return r;
    ++requests_;
    const auto& e = encoded.value();
    const Bus::Reply reply = connection_->run([&](modbus_t* ctx) {
        if (p->table == Table::coil) return modbus_write_bit(ctx, p->address, e.bit ? 1 : 0);
        if (e.words.size() == 1) return modbus_write_register(ctx, p->address, e.words[0]);
        return modbus_write_registers(ctx, p->address, static_cast<int>(e.words.size()), e.words.data());
    });
    switch (reply.outcome) {
        case Outcome::ok: answered(); return ok_result();
        case Outcome::exception:
            ++failures_;
            answered();
            return make_error(ErrorCode::permission_denied,
                              "modbus " + request.id + ": the PLC refused the write: " + reply.detail);
        case Outcome::bad_frame:
            ++failures_;
            return make_error(ErrorCode::unavailable, "modbus " + request.id + ": damaged answer to the write (" + reply.detail +
                                                          "); it may have been applied");
        case Outcome::no_answer: lost("write: " + reply.detail); return no_answer();
        case Outcome::line_down: break;
    }
    lost("write: " + reply.detail);
    return unreachable("write of " + request.id + " failed: " + last_failure_);
}

}  // namespace nclink::modbus
