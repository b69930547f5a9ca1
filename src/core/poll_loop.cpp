#include "core/poll_loop.hpp"

namespace nclink::detail {

PollLoop::PollLoop() { thread_ = std::thread([this] { run(); }); }

PollLoop::~PollLoop() { stop(); }

void PollLoop::schedule_locked(std::uint64_t id, Entry& entry, Time at) {
    entry.deadline = at;
    entry.generation++;
    if (at == Time::max()) return;
    heap_.push(Due{at, id, entry.generation});
    if (at < sleeping_until_) wake_.notify_one();
}

std::uint64_t PollLoop::add(Poller poller) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return 0;
    const std::uint64_t id = next_id_++;
    Entry& entry = entries_[id];
    entry.poller = std::make_shared<Poller>(std::move(poller));
    schedule_locked(id, entry, std::chrono::steady_clock::now());
    return id;
}

void PollLoop::poke(std::uint64_t id) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = entries_.find(id);
    if (it == entries_.end()) return;
    Entry& entry = it->second;
    if (entry.running) {
        entry.poked = true;  // rescheduled at once when it returns
        return;
    }
    const Time now = std::chrono::steady_clock::now();
    if (entry.deadline <= now) return;  // already due
    schedule_locked(id, entry, now);
}

void PollLoop::remove(std::uint64_t id) {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto it = entries_.find(id);
    if (it == entries_.end()) return;
    if (it->second.running && std::this_thread::get_id() != thread_.get_id()) {
        idle_.wait(lock, [&] {
            const auto found = entries_.find(id);
            return found == entries_.end() || !found->second.running;
        });
    }
    entries_.erase(id);  // its heap items are stale from now on
}

void PollLoop::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopping_ && !thread_.joinable()) return;
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable() && std::this_thread::get_id() != thread_.get_id()) thread_.join();
    std::lock_guard<std::mutex> lock(mutex_);
    entries_.clear();
    idle_.notify_all();
}

std::size_t PollLoop::size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return entries_.size();
}

std::uint64_t PollLoop::calls() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return calls_;
}

void PollLoop::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        // Stale heap items (removed pollers, superseded deadlines) go first.
        while (!heap_.empty()) {
            const Due& top = heap_.top();
            const auto it = entries_.find(top.id);
            if (it != entries_.end() && it->second.generation == top.generation) break;
            heap_.pop();
        }
        if (heap_.empty()) {
            sleeping_until_ = Time::max();
            wake_.wait(lock);
            continue;
        }
        const Due due = heap_.top();
        const Time now = std::chrono::steady_clock::now();
        if (due.at > now) {
            sleeping_until_ = due.at;
            wake_.wait_until(lock, due.at);
            continue;
        }
        sleeping_until_ = now;
        heap_.pop();
        Entry& entry = entries_[due.id];
        entry.running = true;
        entry.poked = false;
        entry.deadline = Time::max();
        const std::shared_ptr<Poller> poller = entry.poller;
        ++calls_;
        lock.unlock();
        Time next = Time::max();
        try {
            next = (*poller)();
        } catch (...) {
            // A poller reports its errors itself; this only keeps the loop alive.
            next = std::chrono::steady_clock::now() + std::chrono::seconds(1);
        }
        lock.lock();
        const auto it = entries_.find(due.id);
        if (it != entries_.end()) {
            it->second.running = false;
            if (it->second.poked) next = std::chrono::steady_clock::now();
            schedule_locked(due.id, it->second, next);
        }
        idle_.notify_all();
    }
}

PollPool::PollPool(std::size_t threads) {
    if (threads == 0) threads = 1;
    for (std::size_t i = 0; i < threads; ++i) loops_.push_back(std::make_unique<PollLoop>());
}

PollLoop& PollPool::next() {
    std::lock_guard<std::mutex> lock(mutex_);
    PollLoop& loop = *loops_[turn_ % loops_.size()];
    ++turn_;
    return loop;
}

void PollPool::stop() {
    for (auto& loop : loops_) loop->stop();
}

}  // namespace nclink::detail
