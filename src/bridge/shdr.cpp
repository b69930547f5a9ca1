#include "bridge/shdr.hpp"

#include "bridge/mtconnect_documents.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <iterator>

namespace nclink::bridge {

std::string shdr_escape(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        if (c == '|') out += '/';
        else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) out += ' ';
        else out += c;
    }
    return out;
}

std::string shdr_value(std::string_view text) {
    std::string plain;
    plain.reserve(text.size());
    for (char c : text) plain += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? ' ' : c;
    const auto first = plain.find_first_not_of(' ');
    const bool quote = plain.find('|') != std::string::npos || (first != std::string::npos && (first > 0 || plain[first] == '"'));
    if (!quote) return plain;
    // The adapter protocol's quoted form: '"' ... '"' with '\' before each
    // '|', '"' and '\' inside; the agent drops the backslashes and keeps
    // the character after each.
    std::string out = "\"";
    out.reserve(plain.size() + 8);
    for (char c : plain) {
        if (c == '|' || c == '"' || c == '\\') out += '\\';
        out += c;
    }
    out += '"';
    return out;
}

std::string shdr_device_key(const MtDevice& device) {
    // An agent finds the device of "<device>:<item>" by uuid first, then by
    // name, and splits the key at its first ':'. Names need not be unique
    // (two machines of one model), uuids are: the uuid unless it holds a
    // character that would split or end the key.
    const bool usable = !device.uuid.empty() && device.uuid.find_first_of(":| \t\r\n") == std::string::npos;
    return shdr_escape(usable ? device.uuid : device.name);
}

namespace {

/// Native units an MTConnect agent converts to the DataItem's `units` by
/// itself, with the factor the mapping uses (checked with cppagent 1.8.0.3,
/// docs/bridge.md "Agents tried"). Part 2 `nativeUnits`: the unit the
/// equipment reports in; an adapter sends a SAMPLE in it and the agent
/// converts (its default; `ConversionRequired = false` turns that off).
/// Other native units (the x: extensions, MICRO_RADIAN, KILOWATT_HOUR,
/// JOULE, CENTIPOISE) the agent leaves as they are, so the bridge sends
/// those values already converted.
bool agent_converts(std::string_view native_units) {
    static constexpr std::string_view kConverted[] = {"MILLIMETER/MINUTE", "DEGREE/MINUTE", "RADIAN",
                                                      "RADIAN/SECOND",     "RADIAN/MINUTE", "RADIAN/SECOND^2",
                                                      "REVOLUTION/SECOND", "KILOWATT",      "FAHRENHEIT"};
    return std::find(std::begin(kConverted), std::end(kConverted), native_units) != std::end(kConverted);
}

}  // namespace

std::optional<MtDataItem> shdr_native_item(const MtDataItem& item) {
    if (item.category != MtCategory::sample || !agent_converts(item.native_units)) return std::nullopt;
    MtDataItem unconverted = item;
    unconverted.scale = 1;
    unconverted.offset = 0;
    return unconverted;
}

std::string shdr_lines(const DeviceEntry& device, const ItemEntry& item, const Observation& o) {
    const std::string prefix = iso_time(o.time_ms) + "|" + shdr_device_key(device.mt) + ":" + shdr_escape(item.mt.id) + "|";
    std::string out;
    if (item.availability) {
        out = prefix + (o.value.is_null() ? "UNAVAILABLE" : "AVAILABLE") + "\n";
        return out;
    }
    // A SAMPLE the agent converts goes in its nativeUnits (the NC-Link
    // value): sent converted, it was converted twice (x_speed: 20 mm/s in
    // the bridge, 0.33 in the agent). Decided once per item, by the store.
    const auto observations = mtconnect_observations(item.shdr_mt ? *item.shdr_mt : item.mt, o.value);
    if (item.mt.category == MtCategory::condition) {
        // level|nativeCode|nativeSeverity|qualifier|message
        for (const auto& ob : observations) {
            std::string level = ob.element == "Fault"     ? "fault"
                                : ob.element == "Warning" ? "warning"
                                : ob.element == "Normal"  ? "normal"
                                                          : "unavailable";
            out += prefix + level + "|" + shdr_value(ob.native_code) + "|||" + shdr_value(ob.value) + "\n";
        }
        return out;
    }
    // A MESSAGE is read as nativeCode|text (part 2 MESSAGE: its nativeCode
    // attribute): with the value alone the agent takes it for the code,
    // finds no text and records UNAVAILABLE, which is how the list and dict
    // items (EVENT MESSAGE x:<type>, docs/mapping.md) were lost. The code is
    // left empty, so the agent sets none.
    const bool message = item.mt.type == "MESSAGE";
    for (const auto& ob : observations) out += prefix + (message ? "|" : "") + shdr_value(ob.value) + "\n";
    return out;
}

std::string shdr_answer(std::string_view line, std::chrono::milliseconds heartbeat) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
    if (line.substr(0, 6) == "* PING") return "* PONG " + std::to_string(heartbeat.count()) + "\n";
    return {};
}

ShdrServer::ShdrServer(const BridgeStore& store, std::string host, int port, std::chrono::milliseconds heartbeat, Logger logger,
                       std::size_t max_connections)
    : store_(store),
      host_(std::move(host)),
      port_(port),
      heartbeat_(heartbeat),
      logger_(std::move(logger)),
      max_connections_(max_connections) {}

ShdrServer::~ShdrServer() { stop(); }

Result<void> ShdrServer::start() {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
    addrinfo* found = nullptr;
    const std::string service = std::to_string(port_);
    if (getaddrinfo(host_.c_str(), service.c_str(), &hints, &found) != 0 || !found)
        return make_error(ErrorCode::unavailable, "shdr: cannot resolve " + host_);
    int fd = ::socket(found->ai_family, found->ai_socktype | SOCK_CLOEXEC, found->ai_protocol);
    int one = 1;
    if (fd >= 0) ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (fd < 0 || ::bind(fd, found->ai_addr, found->ai_addrlen) != 0 || ::listen(fd, 16) != 0) {
        const std::string why = std::strerror(errno);
        if (fd >= 0) ::close(fd);
        freeaddrinfo(found);
        return make_error(ErrorCode::unavailable, "shdr: cannot bind " + host_ + ":" + service + ": " + why);
    }
    freeaddrinfo(found);
    sockaddr_storage bound{};
    socklen_t length = sizeof bound;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &length);
    port_ = bound.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port)
                                        : ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
    listen_fd_ = fd;
    running_ = true;
    acceptor_ = std::thread([this] { accept_loop(); });
    logger_.info("shdr: serving on {}:{}", host_, port_);
    return ok_result();
}

void ShdrServer::stop() {
    if (!running_.exchange(false)) return;
    store_.wake_all();
    if (acceptor_.joinable()) acceptor_.join();
    if (listen_fd_ >= 0) ::close(listen_fd_);
    listen_fd_ = -1;
    std::list<std::thread> threads;
    {
        std::lock_guard<std::mutex> lock(threads_mutex_);
        threads.swap(threads_);
    }
    for (auto& t : threads)
        if (t.joinable()) t.join();
}

void ShdrServer::accept_loop() {
    while (running_) {
        pollfd p{listen_fd_, POLLIN, 0};
        if (::poll(&p, 1, 100) <= 0) continue;
        int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
        if (fd < 0) continue;
        if (connections_ >= max_connections_) {
            ::close(fd);
            continue;
        }
        int one = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        ++connections_;
        std::lock_guard<std::mutex> lock(threads_mutex_);
        threads_.emplace_back([this, fd] {
            serve(fd);
            ::close(fd);
            --connections_;
        });
    }
}

namespace {
bool send_all(int fd, const std::string& data) {
    std::size_t sent = 0;
    while (sent < data.size()) {
        const ssize_t n = ::send(fd, data.data() + sent, data.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) return false;
        sent += static_cast<std::size_t>(n);
    }
    return true;
}
}  // namespace

void ShdrServer::serve(int fd) {
    std::uint64_t cursor = 0;
    bool snapshot = true;
    std::string input;
    while (running_) {
        std::string out;
        store_.read([&](const BridgeState& st) {
            if (!snapshot && cursor < st.buffer.first_sequence()) snapshot = true;  // fell behind: start over
            if (snapshot) {
                for (const auto& d : st.devices)
                    for (ItemIndex i : d.items)
                        if (i < st.buffer.latest().size() && st.buffer.latest()[i])
                            out += shdr_lines(d, st.items[i], *st.buffer.latest()[i]);
                cursor = st.buffer.next_sequence();
                snapshot = false;
                return 0;
            }
            auto range = st.buffer.range(cursor, 8192, nullptr);
            cursor = range.next_sequence;
            for (const auto& o : range.observations) {
                const ItemEntry& item = st.items[o.item];
                out += shdr_lines(st.devices[item.device], item, o);
            }
            return 0;
        });
        if (!out.empty() && !send_all(fd, out)) return;
        // Read what the agent sent (PING), waiting briefly for either side.
        pollfd p{fd, POLLIN, 0};
        const int ready = ::poll(&p, 1, 0);
        if (ready > 0) {
            char buffer[1024];
            const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
            if (n <= 0) return;  // the agent closed the connection
            input.append(buffer, static_cast<std::size_t>(n));
            if (input.size() > 65536) return;  // no line is this long
            std::size_t eol;
            while ((eol = input.find('\n')) != std::string::npos) {
                const std::string answer = shdr_answer(std::string_view(input).substr(0, eol), heartbeat_);
                input.erase(0, eol + 1);
                if (!answer.empty() && !send_all(fd, answer)) return;
            }
            continue;
        }
        store_.wait_for_change(cursor - 1, std::numeric_limits<std::uint64_t>::max(), std::chrono::milliseconds(20));
    }
}

}  // namespace nclink::bridge
