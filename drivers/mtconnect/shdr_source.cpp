#include "mtconnect/shdr_source.hpp"

#include "mtconnect/probe_document.hpp"
#include "mtconnect/shdr_line.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace nclink::mtconnect {

namespace {

using Clock = std::chrono::steady_clock;

/// A non-blocking connect bounded by `timeout`; -1 with `why` on failure.
int connect_to(const std::string& host, int port, std::chrono::milliseconds timeout, std::string& why) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const int rc = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found);
    if (rc != 0) {
        why = std::string("cannot resolve ") + host + ": " + ::gai_strerror(rc);
        return -1;
    }
    int fd = -1;
    for (addrinfo* a = found; a && fd < 0; a = a->ai_next) {
        fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, a->ai_protocol);
        if (fd < 0) continue;
        if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0 && errno != EINPROGRESS) {
            why = std::strerror(errno);
            ::close(fd);
            fd = -1;
            continue;
        }
        pollfd p{fd, POLLOUT, 0};
        int err = 0;
        socklen_t len = sizeof err;
        if (::poll(&p, 1, static_cast<int>(timeout.count())) != 1 || ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len) != 0 ||
            err != 0) {
            why = err ? std::strerror(err) : "connect timed out";
            ::close(fd);
            fd = -1;
        }
    }
    ::freeaddrinfo(found);
    return fd;
}

bool send_all(int fd, const std::string& text) {
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::send(fd, text.data() + done, text.size() - done, MSG_NOSIGNAL);
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
            pollfd p{fd, POLLOUT, 0};
            if (::poll(&p, 1, 1000) <= 0) return false;
            continue;
        }
        if (n <= 0) return false;
        done += static_cast<std::size_t>(n);
    }
    return true;
}

std::string level_word(std::string level) {
    for (auto& c : level) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (level == "normal") return "Normal";
    if (level == "warning") return "Warning";
    if (level == "fault") return "Fault";
    if (level == "unavailable") return "Unavailable";
    return {};
}

}  // namespace

ShdrSource::ShdrSource(ShdrOptions options, LiveValues& values, SourceStatus& status, Logger logger)
    : options_(std::move(options)), values_(values), status_(status), logger_(std::move(logger)) {}

ShdrSource::~ShdrSource() { stop(); }

Result<void> ShdrSource::start() {
    const std::size_t colon = options_.address.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == options_.address.size())
        return make_error(ErrorCode::syntax_error, "shdr address '" + options_.address + "': expected host:port");
    const std::string port = options_.address.substr(colon + 1);
    if (port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos || std::stoi(port) < 1 ||
        std::stoi(port) > 65535)
        return make_error(ErrorCode::syntax_error, "shdr address '" + options_.address + "': bad port");
    host_ = options_.address.substr(0, colon);
    port_ = std::stoi(port);

    std::ifstream in(options_.probe_file, std::ios::binary);
    if (!in) return make_error(ErrorCode::unavailable, "cannot read the probe file " + options_.probe_file);
    std::ostringstream text;
    text << in.rdbuf();
    auto probe = read_probe(text.str());
    if (!probe.ok()) return make_error(probe.error().code, options_.probe_file + ": " + probe.error().message);
    ReverseOptions ro;
    ro.device = options_.device;
    auto model = reverse_map(probe.value(), ro);
    if (!model.ok()) return make_error(model.error().code, options_.probe_file + ": " + model.error().message);
    if (const ProbeComponent* d = find_device(probe.value(), options_.device)) {
        uuid_ = d->uuid;
        name_ = d->name;
        id_ = d->id;
    }
    values_.install(std::make_shared<const ReverseModel>(std::move(model).value()));
    status_.count([](SourceCounters& c) { ++c.probes; });
    status_.disconnected("not connected to the SHDR adapter " + options_.address + " yet");
    if (::pipe2(wake_pipe_, O_CLOEXEC | O_NONBLOCK) != 0)
        return make_error(ErrorCode::unavailable, std::string("shdr source: pipe: ") + std::strerror(errno));
    stopping_ = false;
    thread_ = std::thread([this] { run(); });
    return ok_result();
}

void ShdrSource::stop() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (wake_pipe_[1] >= 0) {
        const char c = 'x';
        [[maybe_unused]] const ssize_t n = ::write(wake_pipe_[1], &c, 1);
    }
    if (thread_.joinable()) thread_.join();
    for (int& fd : wake_pipe_)
        if (fd >= 0) {
            ::close(fd);
            fd = -1;
        }
}

bool ShdrSource::for_this_device(const std::string& device) const {
    return device.empty() || device == uuid_ || device == name_ || device == id_;
}

std::size_t ShdrSource::apply_line(const std::string& line) {
    const std::vector<std::string> f = shdr_fields(line);
    std::size_t used = 0;
    // f[0] is the timestamp: NC-Link items carry current values, not times.
    for (std::size_t i = 1; i + 1 < f.size();) {
        auto [device, key] = shdr_split_key(f[i]);
        const bool ours = for_this_device(device);
        const auto model = values_.model();
        const ItemBinding* item = model && ours ? model->find_shdr(key) : nullptr;
        if (item && item->rule == ValueRule::condition) {
            // level|native_code|native_severity|qualifier|message
            auto at = [&](std::size_t k) { return i + k < f.size() ? f[i + k] : std::string(); };
            const std::string level = level_word(at(1));
            if (!level.empty() && values_.apply_condition(key, level, at(2), at(5))) ++used;
            break;  // one multi-field item per line
        }
        if (item && item->mt_type == "MESSAGE" && i + 2 < f.size()) {
            // native_code|text
            if (values_.apply_value(key, f[i + 2])) ++used;
            break;
        }
        if (item && values_.apply_value(key, f[i + 1])) ++used;
        i += 2;
    }
    return used;
}

void ShdrSource::run() {
    for (;;) {
        {
            std::lock_guard lock(mutex_);
            if (stopping_) return;
        }
        std::string why;
        const int fd = connect_to(host_, port_, options_.timeout, why);
        if (fd >= 0) {
            status_.count([](SourceCounters& c) { ++c.connects; });
            logger_.info("SHDR source: connected to {}", options_.address);
            follow(fd);
            ::close(fd);
            values_.all_unavailable();
        } else {
            status_.disconnected("SHDR adapter " + options_.address + ": " + why);
            status_.count([](SourceCounters& c) { ++c.failures; });
        }
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, options_.retry, [&] { return stopping_; });
    }
}

void ShdrSource::follow(int fd) {
    status_.connected();
    std::string buffer;
    auto last_heard = Clock::now();
    auto next_ping = Clock::now();
    long long heartbeat = -1;  // from the adapter's PONG; -1: none announced
    std::string reason = "the SHDR adapter closed the connection";
    for (;;) {
        const auto now = Clock::now();
        if (now >= next_ping) {
            if (!send_all(fd, "* PING\n")) {
                reason = std::string("cannot send to the SHDR adapter: ") + std::strerror(errno);
                break;
            }
            next_ping = now + options_.ping;
        }
        if (heartbeat > 0 && now - last_heard > std::chrono::milliseconds(2 * heartbeat)) {
            reason = "the SHDR adapter was silent for more than twice its heartbeat (" + std::to_string(heartbeat) + " ms)";
            break;
        }
        auto until = next_ping;
        if (heartbeat > 0)
            until = std::min(until, last_heard + std::chrono::milliseconds(2 * heartbeat) + std::chrono::milliseconds(1));
        const auto wait_ms =
            std::max<long long>(1, std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()).count());
        pollfd p[2] = {{fd, POLLIN, 0}, {wake_pipe_[0], POLLIN, 0}};
        const int rc = ::poll(p, 2, static_cast<int>(std::min<long long>(wait_ms, 1000)));
        if (rc < 0 && errno != EINTR) {
            reason = std::string("poll: ") + std::strerror(errno);
            break;
        }
        if (p[1].revents) {
            std::lock_guard lock(mutex_);
            if (stopping_) return;
        }
        if (rc <= 0 || !(p[0].revents & (POLLIN | POLLHUP | POLLERR))) continue;
        char chunk[4096];
        const ssize_t n = ::recv(fd, chunk, sizeof chunk, 0);
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
        if (n <= 0) {
            if (n < 0) reason = std::string("the SHDR connection failed: ") + std::strerror(errno);
            break;
        }
        last_heard = Clock::now();
        buffer.append(chunk, static_cast<std::size_t>(n));
        if (buffer.size() > (1u << 20) && buffer.find('\n') == std::string::npos) {
            reason = "the SHDR adapter sent a line longer than 1 MiB";
            break;
        }
        std::size_t start = 0;
        for (std::size_t nl; (nl = buffer.find('\n', start)) != std::string::npos; start = nl + 1) {
            const std::string line = buffer.substr(start, nl - start);
            if (!line.empty() && line[0] == '*') {
                const long long ms = shdr_pong_ms(line);
                if (ms >= 0) {
                    heartbeat = ms;
                    status_.count([](SourceCounters& c) { ++c.pongs; });
                }
                continue;
            }
            const std::size_t used = apply_line(line);
            status_.count([&](SourceCounters& c) { c.observations += used; });
        }
        buffer.erase(0, start);
        if (values_.available() == std::optional<bool>(false))
            status_.disconnected("the SHDR adapter reports the device UNAVAILABLE");
        else status_.connected();
    }
    logger_.info("SHDR source: {}; reconnecting every {} ms", reason, options_.retry.count());
    status_.disconnected(reason);
    status_.count([](SourceCounters& c) { ++c.failures; });
}

}  // namespace nclink::mtconnect
