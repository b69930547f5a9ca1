// A Modbus RTU serial line for the RTU driver's tests, with no hardware:
// - PtyLine: socat (Debian package socat, tools/install-deps.sh) joins two
//   pseudo-terminals, like the two ends of a cable: the driver opens
//   driver_end(), the simulated slaves slave_end().
// - RtuSlaves: the slaves of a multi-drop bus on slave_end(), each with its
//   own registers (libmodbus' modbus_mapping_t, answered by modbus_reply()).
//   A slave can be made silent (it ignores its requests, as a switched-off
//   slave does) or made to send its next answer with a wrong CRC (line noise).
// No Catch assertion in here.
#pragma once

#include "support/child_process.hpp"

#include <fcntl.h>
#include <modbus.h>
#include <sys/ioctl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace nclink::test {

/// The path of `program` on PATH, empty when it is not installed.
inline std::string find_program(const std::string& program) {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    for (std::size_t at = 0; at <= dirs.size();) {
        const auto end = std::min(dirs.find(':', at), dirs.size());
        const std::string candidate = dirs.substr(at, end - at) + "/" + program;
        if (::access(candidate.c_str(), X_OK) == 0) return candidate;
        at = end + 1;
    }
    return {};
}

/// The Modbus RTU CRC (Modbus over Serial Line 6.2.2): low byte first on the wire.
inline std::uint16_t modbus_crc(const std::uint8_t* data, std::size_t n) {
    std::uint16_t crc = 0xFFFF;
    for (std::size_t i = 0; i < n; ++i) {
        crc ^= data[i];
        for (int bit = 0; bit < 8; ++bit)
            crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : static_cast<std::uint16_t>(crc >> 1);
    }
    return crc;
}

class PtyLine {
public:
    /// Throws when socat is missing or does not make the pair.
    PtyLine() {
        const std::string socat = find_program("socat");
        if (socat.empty()) throw std::runtime_error("socat is not installed (Debian package socat; run tools/install-deps.sh)");
        std::string tmpl = (std::filesystem::temp_directory_path() / "nclink-rtu-XXXXXX").string();
        if (!::mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
        dir_ = tmpl;
        socat_ = std::make_unique<ChildProcess>(std::vector<std::string>{socat, "-d", "-d", "pty,raw,echo=0,link=" + driver_end(),
                                                                         "pty,raw,echo=0,link=" + slave_end()},
                                                dir_ + "/socat.log");
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (!std::filesystem::exists(driver_end()) || !std::filesystem::exists(slave_end())) {
            if (std::chrono::steady_clock::now() > deadline || !socat_->running())
                throw std::runtime_error("socat made no pty pair: " + socat_->log());
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        // socat ends when the last holder of a pty closes it; holding the
        // driver's end open keeps the line up while a driver closes and
        // opens it again. This descriptor is never read.
        keep_open_ = ::open(driver_end().c_str(), O_RDWR | O_NOCTTY);
    }
    ~PtyLine() {
        if (keep_open_ >= 0) ::close(keep_open_);
        socat_.reset();
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    PtyLine(const PtyLine&) = delete;
    PtyLine& operator=(const PtyLine&) = delete;

    /// Bytes that arrived at the driver's end and wait to be read (a tty's
    /// input queue is one for every descriptor open on it).
    int waiting_at_driver_end() const {
        int n = 0;
        return keep_open_ >= 0 && ::ioctl(keep_open_, FIONREAD, &n) == 0 ? n : -1;
    }

    std::string driver_end() const { return dir_ + "/master"; }
    std::string slave_end() const { return dir_ + "/slaves"; }
    std::string dir() const { return dir_; }

private:
    std::string dir_;
    std::unique_ptr<ChildProcess> socat_;
    int keep_open_ = -1;
};

class RtuSlaves {
public:
    /// Answers on `device` as the slaves `ids`, each with 256 registers and bits of each table.
    RtuSlaves(const std::string& device, const std::set<int>& ids) {
        fd_ = ::open(device.c_str(), O_RDWR | O_NOCTTY);
        if (fd_ < 0) throw std::runtime_error("cannot open " + device);
        termios tio{};
        ::tcgetattr(fd_, &tio);
        ::cfmakeraw(&tio);
        ::tcsetattr(fd_, TCSANOW, &tio);
        for (int id : ids) {
            modbus_mapping_t* map = modbus_mapping_new(256, 256, 256, 256);
            if (!map) throw std::runtime_error("modbus_mapping_new failed");
            slaves_[id].map = map;
        }
        // modbus_reply() builds and sends an answer on a context's
        // descriptor: here a pipe, so the test can damage the answer before
        // it goes on the line.
        if (::pipe(pipe_) != 0) throw std::runtime_error("pipe failed");
        ctx_ = modbus_new_rtu(device.c_str(), 19200, 'E', 8, 1);
        modbus_set_socket(ctx_, pipe_[1]);
        running_ = true;
        thread_ = std::thread([this] { serve(); });
    }
    ~RtuSlaves() {
        running_ = false;
        thread_.join();
        modbus_free(ctx_);  // not modbus_close(): the pipe is ours
        ::close(pipe_[0]);
        ::close(pipe_[1]);
        ::close(fd_);
        for (auto& [id, s] : slaves_) modbus_mapping_free(s.map);
    }
    RtuSlaves(const RtuSlaves&) = delete;
    RtuSlaves& operator=(const RtuSlaves&) = delete;

    void set_holding(int slave, int address, std::uint16_t value) {
        std::lock_guard lock(mutex_);
        slaves_.at(slave).map->tab_registers[address] = value;
    }
    std::uint16_t holding(int slave, int address) {
        std::lock_guard lock(mutex_);
        return slaves_.at(slave).map->tab_registers[address];
    }
    void set_input(int slave, int address, std::uint16_t value) {
        std::lock_guard lock(mutex_);
        slaves_.at(slave).map->tab_input_registers[address] = value;
    }
    void set_coil(int slave, int address, bool value) {
        std::lock_guard lock(mutex_);
        slaves_.at(slave).map->tab_bits[address] = value ? 1 : 0;
    }
    bool coil(int slave, int address) {
        std::lock_guard lock(mutex_);
        return slaves_.at(slave).map->tab_bits[address] != 0;
    }
    void set_discrete(int slave, int address, bool value) {
        std::lock_guard lock(mutex_);
        slaves_.at(slave).map->tab_input_bits[address] = value ? 1 : 0;
    }
    /// A silent slave ignores its requests (switched off, cable cut).
    void set_silent(int slave, bool silent) {
        std::lock_guard lock(mutex_);
        slaves_.at(slave).silent = silent;
    }
    /// The slave answers only after `delay` (a slow slave: past the
    /// driver's timeout, its answer arrives late). answers() counts them.
    void set_delay(int slave, std::chrono::milliseconds delay) {
        std::lock_guard lock(mutex_);
        slaves_.at(slave).delay = delay;
    }
    /// Answers the slave sent.
    int answers(int slave) {
        std::lock_guard lock(mutex_);
        return slaves_.at(slave).answers;
    }
    /// The slave's next answer pauses for `pause` after its first half (a
    /// slave or converter that stalls mid-frame).
    void pause_next_answer(int slave, std::chrono::milliseconds pause) {
        std::lock_guard lock(mutex_);
        slaves_.at(slave).pause_next = pause;
    }
    /// The slave's next answer goes out with its CRC damaged.
    void damage_next_answer(int slave) {
        std::lock_guard lock(mutex_);
        slaves_.at(slave).damage_next = true;
    }
    /// Requests for the slave seen on the line (answered or not).
    int requests(int slave) {
        std::lock_guard lock(mutex_);
        return slaves_.at(slave).requests;
    }
    /// Frames with a bad CRC or of an unknown function, dropped.
    int bad_frames() {
        std::lock_guard lock(mutex_);
        return bad_frames_;
    }

private:
    struct Slave {
        modbus_mapping_t* map = nullptr;
        bool silent = false;
        bool damage_next = false;
        std::chrono::milliseconds delay{0};
        std::chrono::milliseconds pause_next{0};
        int requests = 0;
        int answers = 0;
    };

    /// The length of the request at the start of `buf` (0: not known yet,
    /// -1: not a request of a function the driver uses).
    static int request_length(const std::vector<std::uint8_t>& buf) {
        if (buf.size() < 2) return 0;
        const int function = buf[1];
        if (function >= 1 && function <= 6) return 8;  // slave, function, address, count/value, CRC
        if (function == 15 || function == 16) return buf.size() < 7 ? 0 : 9 + buf[6];
        return -1;
    }

    void serve() {
        std::vector<std::uint8_t> buf;
        auto last_byte = std::chrono::steady_clock::now();
        while (running_) {
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, 10) > 0) {
                std::uint8_t chunk[512];
                const ssize_t n = ::read(fd_, chunk, sizeof chunk);
                if (n > 0) {
                    buf.insert(buf.end(), chunk, chunk + n);
                    last_byte = std::chrono::steady_clock::now();
                }
            } else if (!buf.empty() && std::chrono::steady_clock::now() - last_byte > std::chrono::milliseconds(100)) {
                buf.clear();  // a frame cut off: start over at the next one
            }
            for (;;) {
                const int length = request_length(buf);
                if (length < 0) {
                    std::lock_guard lock(mutex_);
                    ++bad_frames_;
                    buf.clear();
                    break;
                }
                if (length == 0 || buf.size() < static_cast<std::size_t>(length)) break;
                std::vector<std::uint8_t> frame(buf.begin(), buf.begin() + length);
                buf.erase(buf.begin(), buf.begin() + length);
                answer(frame);
            }
        }
    }

    void answer(const std::vector<std::uint8_t>& frame) {
        const std::uint16_t crc = modbus_crc(frame.data(), frame.size() - 2);
        std::chrono::milliseconds delay{0};
        {
            std::lock_guard lock(mutex_);
            auto it = slaves_.find(frame[0]);
            if (it != slaves_.end()) delay = it->second.delay;
        }
        if (delay.count() > 0) std::this_thread::sleep_for(delay);
        std::lock_guard lock(mutex_);
        if (frame[frame.size() - 2] != (crc & 0xFF) || frame[frame.size() - 1] != (crc >> 8)) {
            ++bad_frames_;  // a real slave ignores a damaged request
            return;
        }
        auto it = slaves_.find(frame[0]);
        if (it == slaves_.end()) return;  // no such slave on this line
        Slave& slave = it->second;
        ++slave.requests;
        if (slave.silent) return;
        if (modbus_reply(ctx_, frame.data(), static_cast<int>(frame.size()), slave.map) <= 0) return;
        std::uint8_t out[MODBUS_RTU_MAX_ADU_LENGTH];
        const ssize_t n = ::read(pipe_[0], out, sizeof out);
        if (n <= 0) return;
        if (slave.damage_next) {
            out[n - 1] ^= 0xA5;
            slave.damage_next = false;
        }
        const std::chrono::milliseconds pause = slave.pause_next;
        slave.pause_next = std::chrono::milliseconds(0);
        const ssize_t half = pause.count() > 0 ? n / 2 : n;
        ssize_t sent = 0;
        while (sent < n) {
            if (sent == half) std::this_thread::sleep_for(pause);
            const ssize_t w = ::write(fd_, out + sent, static_cast<std::size_t>((sent < half ? half : n) - sent));
            if (w <= 0) break;
            sent += w;
        }
        ++slave.answers;
    }

    int fd_ = -1;
    int pipe_[2] = {-1, -1};
    modbus_t* ctx_ = nullptr;
    std::map<int, Slave> slaves_;
    int bad_frames_ = 0;
    std::mutex mutex_;
    std::atomic<bool> running_{false};
    std::thread thread_;
};

}  // namespace nclink::test
