#include "modbus/modbus_bus.hpp"

#include <modbus.h>
#include <sys/select.h>

#include <cerrno>
#include <filesystem>
#include <thread>

namespace nclink::modbus {
namespace {

Outcome classify(int err) {
    if (err >= EMBXILFUN && err <= EMBXGTAR) return Outcome::exception;
    if (err == ETIMEDOUT) return Outcome::no_answer;
    if (err >= EMBBADCRC && err <= EMBBADSLAVE) return Outcome::bad_frame;
    // ECONNRESET (the device read end of file), EIO, ENXIO, EBADF: the
    // device itself failed (a USB adapter unplugged, the pty closed).
    return Outcome::line_down;
}

std::pair<std::uint32_t, std::uint32_t> sec_usec(std::chrono::milliseconds ms) {
    return {static_cast<std::uint32_t>(ms.count() / 1000), static_cast<std::uint32_t>((ms.count() % 1000) * 1000)};
}

}  // namespace

Bus::Bus(SerialLine line)
    : line_(std::move(line)), gap_(line_.frame_gap.count() > 0 ? line_.frame_gap : line_.minimum_frame_gap()) {}

Bus::~Bus() { close_device(); }

Bus::Stats Bus::stats() const {
    std::lock_guard lock(queue_mutex_);
    return stats_;
}

void Bus::take_turn() {
    std::unique_lock lock(queue_mutex_);
    const std::uint64_t ticket = next_ticket_++;
    if (ticket != serving_) ++stats_.waits;
    queue_cv_.wait(lock, [&] { return serving_ == ticket; });
}

void Bus::end_turn() {
    {
        std::lock_guard lock(queue_mutex_);
        ++serving_;
    }
    queue_cv_.notify_all();
}

Bus::Reply Bus::open() {
    take_turn();
    Reply reply;
    if (!open_device(reply.detail)) reply.outcome = Outcome::line_down;
    end_turn();
    return reply;
}

bool Bus::open_device(std::string& why) {
    if (ctx_) return true;
    modbus_t* ctx = modbus_new_rtu(line_.device.c_str(), line_.baud, line_.parity, line_.data_bits, line_.stop_bits);
    if (!ctx) {
        why = "cannot make an RTU context for " + line_.describe() + ": " + modbus_strerror(errno);
        return false;
    }
    if (modbus_connect(ctx) == -1) {
        why = "cannot open " + line_.device + ": " + modbus_strerror(errno);
        modbus_free(ctx);
        return false;
    }
    // libmodbus waits for answers with select(), which cannot watch a
    // descriptor at or above FD_SETSIZE: refuse it rather than corrupt memory.
    if (modbus_get_socket(ctx) >= FD_SETSIZE) {
        why = "cannot use " + line_.device + ": its descriptor " + std::to_string(modbus_get_socket(ctx)) + " is above " +
              std::to_string(FD_SETSIZE) + ", which libmodbus's select() cannot wait on";
        modbus_close(ctx);
        modbus_free(ctx);
        return false;
    }
    // Whatever a slave sent before we listened is not an answer of ours.
    modbus_flush(ctx);
    ctx_ = ctx;
    quiet_since_ = std::chrono::steady_clock::now();
    std::lock_guard lock(queue_mutex_);
    ++stats_.opens;
    return true;
}

void Bus::close_device() {
    if (!ctx_) return;
    modbus_close(ctx_);
    modbus_free(ctx_);
    ctx_ = nullptr;
}

Bus::Reply Bus::transact(const SlaveSettings& slave, const std::function<int(modbus_t*)>& request) {
    take_turn();
    struct TurnEnd {
        Bus* bus;
        ~TurnEnd() { bus->end_turn(); }
    } turn_end{this};

    Reply reply;
    if (!open_device(reply.detail)) {
        reply.outcome = Outcome::line_down;
        return reply;
    }
    modbus_set_slave(ctx_, slave.slave);
    const auto [rs, ru] = sec_usec(slave.response_timeout);
    modbus_set_response_timeout(ctx_, rs, ru);
    const auto [bs, bu] = sec_usec(slave.byte_timeout);
    modbus_set_byte_timeout(ctx_, bs, bu);
    // 2.5.1.1: the line stays silent 3.5 characters between frames, also
    // between one slave's answer and the request to the next slave.
    const auto quiet_until = quiet_since_ + gap_;
    if (std::chrono::steady_clock::now() < quiet_until) std::this_thread::sleep_until(quiet_until);
    // Between transactions no slave may speak (2.1: a slave answers only
    // the request addressed to it), so whatever waits in the input now is a
    // late answer to an earlier request that timed out: drop it, or it would
    // be read as this request's answer.
    modbus_flush(ctx_);
    {
        std::lock_guard lock(queue_mutex_);
        ++stats_.transactions;
    }
    const int n = request(ctx_);
    const int err = errno;
    quiet_since_ = std::chrono::steady_clock::now();
    if (n != -1) {
        reply.value = n;
        return reply;
    }
    reply.outcome = classify(err);
    reply.detail = modbus_strerror(err);
    if (reply.outcome == Outcome::line_down) {
        close_device();  // the next transaction opens it again
    } else if (reply.outcome != Outcome::exception) {
        // The rest of a damaged frame, or a late answer already under way,
        // must not be read as the next slave's answer.
        modbus_flush(ctx_);
    }
    return reply;
}

Result<std::shared_ptr<Bus>> BusRegistry::attach(const SerialLine& line) {
    std::error_code ec;
    const auto resolved = std::filesystem::weakly_canonical(line.device, ec);
    const std::string key = ec ? line.device : resolved.string();
    std::lock_guard lock(mutex_);
    for (auto it = buses_.begin(); it != buses_.end();)
        it = it->second.expired() && it->first != key ? buses_.erase(it) : std::next(it);
    auto& slot = buses_[key];
    if (auto bus = slot.lock()) {
        if (!bus->line().same_settings(line))
            return make_error(ErrorCode::value_type,
                              "modbus driver configuration: device: " + line.describe() +
                                  " differs from the line another machine opened as " + bus->line().describe() +
                                  " (every machine on one bus uses the same baud, parity, data and stop bits, frame gap)");
        return bus;
    }
    auto bus = std::make_shared<Bus>(line);
    slot = bus;
    return bus;
}

}  // namespace nclink::modbus
