#include "core/poll_host.hpp"
#include "core/thread_name.hpp"

namespace nclink::core_detail {

struct PollHost::Entry {
    Poll poll;
    // All under the host's mutex:
    std::uint64_t generation = 0;  // bumped on every (re)schedule: older heap items are stale
    bool running = false;
    bool woken = false;  // wake() while running: poll again at once
    bool removed = false;
    std::thread::id runner;  // the thread running the poll, while `running`
};

PollHost::PollHost(std::size_t threads, std::string name, std::chrono::milliseconds backstop)
    : name_(std::move(name)), backstop_(backstop) {
    if (threads == 0) threads = 1;
    watching_.assign(threads, Time::max());
    for (std::size_t i = 0; i < threads; ++i) threads_.emplace_back([this, i] { work(i); });
}

PollHost::~PollHost() { stop(); }

void PollHost::schedule_locked(const Handle& entry, Time at) {
    ++entry->generation;
    const bool earlier = due_.empty() || at < due_.top().at;
    due_.push(Due{at, entry->generation, entry});
    if (earlier && !watched_locked(at)) wake_.notify_one();
}

bool PollHost::watched_locked(Time at) const {
    for (const Time watch : watching_)
        if (watch <= at) return true;
    return false;
}

PollHost::Handle PollHost::add(Poll poll) {
    auto entry = std::make_shared<Entry>();
    entry->poll = std::move(poll);
    std::lock_guard<std::mutex> lock(mutex_);
    ++entries_;
    schedule_locked(entry, std::chrono::steady_clock::now());
    return entry;
}

void PollHost::wake(const Handle& entry) {
    if (!entry) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (entry->removed) return;
    if (entry->running) {
        entry->woken = true;
        return;
    }
    schedule_locked(entry, std::chrono::steady_clock::now());
}

void PollHost::remove(const Handle& entry) {
    if (!entry) return;
    std::unique_lock<std::mutex> lock(mutex_);
    if (!entry->removed) {
        entry->removed = true;
        ++entry->generation;  // its heap items are stale now
        --entries_;
    }
    if (entry->running && entry->runner == std::this_thread::get_id()) return;  // from inside its own poll
    finished_.wait(lock, [&] { return !entry->running; });
}

void PollHost::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    for (auto& t : threads_)
        if (t.joinable() && t.get_id() != std::this_thread::get_id()) t.join();
    threads_.clear();
    std::lock_guard<std::mutex> lock(mutex_);
    due_ = {};
}

std::size_t PollHost::size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return entries_;
}

std::uint64_t PollHost::polls() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return polls_;
}

std::uint64_t PollHost::wakeups() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return wakeups_;
}

void PollHost::work(std::size_t index) {
    name_this_thread(name_ + "-" + std::to_string(index));
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        if (due_.empty()) {
            wake_.wait(lock);
            ++wakeups_;
            continue;
        }
        const Due top = due_.top();
        if (top.generation != top.entry->generation || top.entry->removed || top.entry->running) {
            // Stale (rescheduled, removed) or another thread runs it: that
            // thread schedules it again when done.
            due_.pop();
            continue;
        }
        const auto now = std::chrono::steady_clock::now();
        if (top.at > now) {
            // One thread watches the next deadline; the others only back it
            // up (backstop_ later), in case its watcher is then stuck in a
            // long poll. All of them waiting for the same deadline woke
            // together and all but one went back to sleep: at 1,000
            // machines tens of thousands of futile wake-ups a second, each
            // a futex call and a fight for this mutex.
            if (watched_locked(top.at)) {
                wake_.wait_until(lock, top.at + backstop_);
            } else {
                watching_[index] = top.at;
                wake_.wait_until(lock, top.at);  // an earlier item, or stop, notifies
                watching_[index] = Time::max();
            }
            ++wakeups_;
            continue;
        }
        due_.pop();
        const Handle entry = top.entry;
        entry->running = true;
        entry->woken = false;
        entry->runner = std::this_thread::get_id();
        ++polls_;
        // Items due already are this thread's after the poll, like those due
        // later; another thread takes them only once they have waited
        // kBackstop. Waking a second thread for every due item made a
        // gateway's bursts (every machine's 100 ms channels come due at the
        // same instant) a fight for this mutex: at 1,000 machines a fifth of
        // the timer threads' CPU went to futex wake-ups, and one thread
        // served the same bursts with a quarter less CPU and no worse Query
        // tail (docs/gateway.md, "Threads").
        lock.unlock();
        Time next;
        try {
            next = entry->poll(now);
        } catch (...) {
            next = std::chrono::steady_clock::now() + std::chrono::seconds(1);
        }
        lock.lock();
        entry->running = false;
        entry->runner = {};
        if (entry->removed) {
            finished_.notify_all();
            continue;
        }
        if (entry->woken) next = std::chrono::steady_clock::now();
        if (next != Time::max()) schedule_locked(entry, next);
    }
}

}  // namespace nclink::core_detail
