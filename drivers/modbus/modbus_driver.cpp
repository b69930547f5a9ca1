#include "modbus/modbus_driver.hpp"

#include <modbus.h>

#include <cerrno>
#include <cstring>

namespace nclink::modbus {

/// One libmodbus TCP context. Not thread-safe: the driver is serialized.
class Connection {
public:
    explicit Connection(const Config& c) : ctx_(modbus_new_tcp(c.host.c_str(), c.port)) {
        if (!ctx_) return;
        modbus_set_slave(ctx_, c.unit_id);
        const auto ms = c.timeout.count();
        modbus_set_response_timeout(ctx_, static_cast<std::uint32_t>(ms / 1000), static_cast<std::uint32_t>((ms % 1000) * 1000));
    }
    ~Connection() {
        if (!ctx_) return;
        modbus_close(ctx_);
        modbus_free(ctx_);
    }
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;

    modbus_t* get() const { return ctx_; }

private:
    modbus_t* ctx_;
};

namespace {

/// A Modbus exception answer (the PLC is there and refuses this request:
/// illegal address, illegal value, ...) as opposed to a lost connection.
bool is_exception(int err) {
    return err >= EMBXILFUN && err <= EMBXGTAR;
}

std::string errno_text(int err) {
    return modbus_strerror(err);
}

}  // namespace

ModbusDriver::ModbusDriver(std::optional<Config> config, Clock clock)
    : config_(std::move(config)), clock_(clock ? std::move(clock) : Clock([] { return std::chrono::steady_clock::now(); })) {}

ModbusDriver::~ModbusDriver() = default;

DriverInfo ModbusDriver::info() const {
    return DriverInfo{"modbus-tcp", "1.0", false};
}

Result<void> ModbusDriver::open(const DriverContext& context) {
    logger_ = context.logger;
    if (!config_) {
        auto parsed = parse_config(context.config);
        if (!parsed.ok()) return std::move(parsed).error();
        config_ = std::move(parsed).value();
    }
    backoff_ = config_->backoff_min;
    // A PLC that is not there at start is not fatal: the adapter comes up,
    // its items answer Unavailable, and the driver keeps trying (a gateway
    // starts before the machines are switched on).
    if (auto r = ensure_connected(); !r.ok())
        logger_.warn("modbus {}: not reachable at start ({}); retrying in the background of reads", config_->endpoint(), r.error().message);
    return ok_result();
}

void ModbusDriver::close() {
    connection_.reset();
    link_ = MachineLink::disconnected;
}

MachineLinkStatus ModbusDriver::link() const {
    const MachineLink state = link_.load();
    if (state != MachineLink::disconnected) return {state, {}};
    // Disconnected only while the backoff lasts: when the next attempt is
    // due the SDK must call read() again, which is where reconnecting happens.
    const auto now = (clock_ ? clock_() : std::chrono::steady_clock::now()).time_since_epoch().count();
    if (now >= next_attempt_ticks_.load(std::memory_order_acquire)) return {MachineLink::unknown, {}};
    return {MachineLink::disconnected, "DEV_UNREACHABLE: modbus " + (config_ ? config_->endpoint() : std::string("PLC")) + " not reachable"};
}

ModbusDriver::Stats ModbusDriver::stats() const {
    return Stats{requests_.load(), connects_.load(), failures_.load()};
}

Error ModbusDriver::unreachable(const std::string& what) const {
    // The reason on the wire is table 19's "Unavailable"; the detail names the
    // PLC and DEV_UNREACHABLE (8.3.4's word for a terminal that cannot be reached).
    return make_error(ErrorCode::unavailable, std::string(dev_unreachable_reason) + ": modbus " + config_->endpoint() + " " + what);
}

void ModbusDriver::lost(const std::string& why) {
    ++failures_;
    connection_.reset();
    if (link_.exchange(MachineLink::disconnected) != MachineLink::disconnected)
        logger_.warn("modbus {}: connection lost ({}); reconnecting with backoff", config_->endpoint(), why);
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
    auto c = std::make_unique<Connection>(*config_);
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
        if (!mapped[i]) results[i] = make_error(ErrorCode::unavailable, "modbus: " + points[i].id + " is not in the driver's map");
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
        int n = -1;
        modbus_t* ctx = connection_->get();
        switch (span.table) {
            case Table::holding_register:
                words.resize(span.count);
                n = modbus_read_registers(ctx, span.start, span.count, words.data());
                break;
            case Table::input_register:
                words.resize(span.count);
                n = modbus_read_input_registers(ctx, span.start, span.count, words.data());
                break;
            case Table::coil:
                bits.resize(span.count);
                n = modbus_read_bits(ctx, span.start, span.count, bits.data());
                break;
            case Table::discrete_input:
                bits.resize(span.count);
                n = modbus_read_input_bits(ctx, span.start, span.count, bits.data());
                break;
        }
        if (n == -1) {
            const int err = errno;
            if (is_exception(err)) {
                ++failures_;
                for (std::size_t m : span.members)
                    results[m] = make_error(ErrorCode::unavailable, "modbus " + points[m].id + ": the PLC refused the read: " + errno_text(err));
                continue;
            }
            // A transport failure: the connection is gone; this span and every
            // later one answer DEV_UNREACHABLE (the next call retries after backoff).
            lost("read: " + errno_text(err));
            for (std::size_t m : span.members) results[m] = unreachable("read failed: " + last_failure_);
            continue;
        }
        for (std::size_t m : span.members) {
            const Point& p = *mapped[m];
            const std::size_t at = p.address - span.start;
            if (span.table == Table::coil || span.table == Table::discrete_input)
                results[m] = decode_bit(p, bits[at] != 0);
            else
                results[m] = decode(p, words.data() + at);
        }
    }
}

Result<void> ModbusDriver::write(const WriteRequest& request) {
    const Point* p = config_ ? config_->find(request.id) : nullptr;
    if (!p) return make_error(ErrorCode::permission_denied, "modbus: " + request.id + " is not in the driver's map");
    if (!p->writable())
        return make_error(ErrorCode::permission_denied, "modbus " + request.id + ": an input register or discrete input cannot be written");
    // The map's points are whole values; the SDK computed the item's value
    // after the Set's operation.
    const Json& value = request.new_value.is_null() && request.params.is_object() && request.params.contains("value")
                            ? request.params["value"]
                            : request.new_value;
    auto encoded = encode(*p, value);
    if (!encoded.ok()) return std::move(encoded).error();
    if (auto r = ensure_connected(); !r.ok()) return r;
    ++requests_;
    modbus_t* ctx = connection_->get();
    const auto& e = encoded.value();
    int n;
    if (p->table == Table::coil)
        n = modbus_write_bit(ctx, p->address, e.bit ? 1 : 0);
    else if (e.words.size() == 1)
        n = modbus_write_register(ctx, p->address, e.words[0]);
    else
        n = modbus_write_registers(ctx, p->address, static_cast<int>(e.words.size()), e.words.data());
    if (n == -1) {
        const int err = errno;
        if (is_exception(err)) {
            ++failures_;
            return make_error(ErrorCode::permission_denied, "modbus " + request.id + ": the PLC refused the write: " + errno_text(err));
        }
        lost("write: " + errno_text(err));
        return unreachable("write of " + request.id + " failed: " + last_failure_);
    }
    return ok_result();
}

}  // namespace nclink::modbus
