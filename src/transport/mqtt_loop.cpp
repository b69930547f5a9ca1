#include "transport/mqtt_loop.hpp"

#include "core/shared_threads_impl.hpp"
#include "core/thread_name.hpp"

#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace nclink::transport_detail {

MqttLoop::MqttLoop(Logger logger, std::chrono::milliseconds tick, std::size_t connect_max)
    : logger_(std::move(logger)), tick_(tick), turns_(connect_max) {
    epoll_fd_ = ::epoll_create1(EPOLL_CLOEXEC);
    event_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (epoll_fd_ < 0 || event_fd_ < 0) {
        if (epoll_fd_ >= 0) ::close(epoll_fd_);
        if (event_fd_ >= 0) ::close(event_fd_);
        throw std::runtime_error(std::string("MQTT loop: ") + std::strerror(errno));
    }
    epoll_event e{};
    e.events = EPOLLIN;
    e.data.u64 = 0;  // the wake-up descriptor (members' tokens start at 1)
    ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, event_fd_, &e);
    thread_ = std::thread([this] {
        core_detail::name_this_thread("nclink-mqtt-io");
        thread_id_ = std::this_thread::get_id();
        run();
    });
}

MqttLoop::~MqttLoop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    signal();
    if (thread_.joinable()) thread_.join();
    ::close(event_fd_);
    ::close(epoll_fd_);
}

void MqttLoop::signal() {
    const std::uint64_t one = 1;
    // A full counter (never in practice) still leaves the descriptor readable.
    [[maybe_unused]] const auto n = ::write(event_fd_, &one, sizeof one);
}

void MqttLoop::add(LoopMember* member) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        adds_.push_back(member);
    }
    signal();
}

void MqttLoop::remove(LoopMember* member) {
    std::unique_lock<std::mutex> lock(mutex_);
    removes_.push_back(member);
    const std::uint64_t ticket = ++removals_asked_;
    wakes_.erase(std::remove(wakes_.begin(), wakes_.end(), member), wakes_.end());
    lock.unlock();
    signal();
    lock.lock();
    removed_.wait(lock, [&] { return removals_done_ >= ticket || stopping_; });
}

void MqttLoop::wake(LoopMember* member) {
    bool first = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        first = wakes_.empty();
        wakes_.push_back(member);  // a repeat is folded on the loop thread
    }
    // One signal per batch: the loop takes every pending wake at once.
    if (first) signal();
}

void MqttLoop::arm(Watch& w) {
    // One-shot: an event disarms the registration until the member watches
    // again (every call into it ends with watch()), so a registration left
    // behind by a socket a child process still holds reports at most once
    // instead of waking the loop without end.
    epoll_event e{};
    e.events = EPOLLIN | EPOLLONESHOT | (w.want_write ? EPOLLOUT : 0u);
    e.data.u64 = w.token;
    // MOD first: the usual case is re-arming the same socket; ENOENT means
    // a new socket under a number the member had before.
    if (::epoll_ctl(epoll_fd_, EPOLL_CTL_MOD, w.fd, &e) != 0 && ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, w.fd, &e) != 0) {
        logger_.warn("mqtt loop: cannot watch socket {}: {}", w.fd, std::strerror(errno));
        w.armed = false;
        return;
    }
    w.armed = true;
}

void MqttLoop::watch(LoopMember* member, int fd, bool want_write) {
    auto found = watches_.find(member);
    if (found == watches_.end()) return;  // not (or no longer) a member
    Watch& w = found->second;
    if (w.fd == fd && w.want_write == want_write && (w.armed || fd < 0)) return;
    if (w.fd != fd && w.fd >= 0) {
        // Before the member closes it (watch(): -1 first). Already closed by
        // the MQTT library on an error, the kernel dropped it by itself.
        ::epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, w.fd, nullptr);
        w.armed = false;
    }
    w.fd = fd;
    w.want_write = want_write;
    if (fd >= 0) arm(w);
    else w.armed = false;
}

void MqttLoop::connect_done(LoopMember* member) {
    if (LoopMember* next = turns_.release(member)) wake(next);
}

void MqttLoop::take_requests() {
    std::vector<LoopMember*> adds, removes;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        adds.swap(adds_);
        removes.swap(removes_);
        // The two lists trade buffers: once grown, a wake allocates nothing
        // (a set's node per wake was one allocation per published DTU).
        woken_.clear();
        woken_.swap(wakes_);
    }
    std::sort(woken_.begin(), woken_.end());
    woken_.erase(std::unique(woken_.begin(), woken_.end()), woken_.end());
    for (LoopMember* m : adds) {
        members_.push_back(m);
        Watch w;
        w.token = next_token_++;
        by_token_.emplace(w.token, m);
        watches_.emplace(m, w);
    }
    if (!removes.empty()) {
        for (LoopMember* m : removes) {
            watch(m, -1, false);
            connect_done(m);  // a turn it held or waited for passes on
            if (const auto gone = watches_.find(m); gone != watches_.end()) by_token_.erase(gone->second.token);
            watches_.erase(m);
            members_.erase(std::remove(members_.begin(), members_.end(), m), members_.end());
            woken_.erase(std::remove(woken_.begin(), woken_.end(), m), woken_.end());
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            removals_done_ += removes.size();
        }
        removed_.notify_all();
    }
    // A wake() may come after its member left (a late publish on a stopped
    // transport): only members are called.
    woken_.erase(std::remove_if(woken_.begin(), woken_.end(), [this](LoopMember* m) { return watches_.count(m) == 0; }),
                 woken_.end());
}

void MqttLoop::run() {
    constexpr int kBatch = 256;
    epoll_event events[kBatch];
    auto next_tick = std::chrono::steady_clock::now() + tick_;
    for (;;) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (stopping_) break;
        }
        take_requests();
        for (LoopMember* m : woken_) m->on_wake();
        woken_.clear();

        auto now = std::chrono::steady_clock::now();
        if (now >= next_tick) {
            for (LoopMember* m : members_) m->on_tick(now);
            next_tick = now + tick_;
        }
        const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next_tick - now).count() + 1;
        const int n = ::epoll_wait(epoll_fd_, events, kBatch, static_cast<int>(wait));
        ++iterations_;
        for (int i = 0; i < n; ++i) {
            const std::uint64_t token = events[i].data.u64;
            if (token == 0) {
                std::uint64_t count = 0;
                [[maybe_unused]] const auto r = ::read(event_fd_, &count, sizeof count);
                continue;
            }
            // Members only leave in take_requests(), between batches. A
            // token of no member is a registration its member left behind
            // (watch()): one-shot, it is not heard of again.
            const auto found = by_token_.find(token);
            if (found == by_token_.end()) continue;
            LoopMember* member = found->second;
            Watch& w = watches_.at(member);
            w.armed = false;
            const bool error = (events[i].events & (EPOLLERR | EPOLLHUP)) != 0;
            member->on_io(error || (events[i].events & EPOLLIN) != 0, error || (events[i].events & EPOLLOUT) != 0);
            // A member that did not watch again keeps its socket watched.
            Watch& after = watches_.at(member);
            if (!after.armed && after.fd >= 0) arm(after);
        }
    }
    // Whoever still waits in remove() is released (the loop is going away).
    removed_.notify_all();
}

std::shared_ptr<MqttLoop> shared_mqtt_loop(SharedThreads::Impl& threads, const Logger& logger) {
    std::lock_guard<std::mutex> lock(threads.mqtt_loop_mutex);
    if (!threads.mqtt_loop)
        threads.mqtt_loop = std::make_shared<MqttLoop>(logger, std::chrono::milliseconds(100), threads.mqtt_connect_max);
    return threads.mqtt_loop;
}

}  // namespace nclink::transport_detail
