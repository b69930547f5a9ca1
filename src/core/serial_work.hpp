// One owner's serial background work (an outbox's sender, an events
// engine, a method status ticker, a sample spool) run as a pollable of a
// PollHost: in a gateway the host is the shared work pool of every machine
// (SharedThreads, docs/gateway.md "Threads"), so N machines do not cost N
// threads each; without one (a single adapter, a unit test) the work gets a
// host of its own with one thread, the same code path.
//
// The owner's poll does what is ready without blocking and returns when it
// wants to run again (time_point::max(): only when woken). PollHost runs
// one pollable on one thread at a time, so the work stays serial (in order)
// as it was on a thread of its own; wake() after queueing work replaces the
// condition variable the thread slept on.
//
// Threading: start() once, before anything calls wake() or stop(); wake()
// from any thread, also from inside the poll (it runs again right after);
// stop() from any thread but the poll's own, idempotent: it returns once the
// poll is not running and never will again. The owner must stop() before
// anything the poll touches is destroyed.
#pragma once

#include "core/poll_host.hpp"

#include <memory>
#include <string>

namespace nclink::core_detail {

class SerialWork {
public:
    SerialWork() = default;
    ~SerialWork() { stop(); }
    SerialWork(const SerialWork&) = delete;
    SerialWork& operator=(const SerialWork&) = delete;

    /// `host`: the shared pool, or null for a host of one thread named `name`.
    void start(PollHost* host, const std::string& name, PollHost::Poll poll) {
        if (host == nullptr) {
            own_ = std::make_unique<PollHost>(1, name);
            host = own_.get();
        }
        host_ = host;
        handle_ = host_->add(std::move(poll));
    }

    void wake() {
        if (host_) host_->wake(handle_);
    }

    void stop() {
        if (!host_) return;
        host_->remove(handle_);
        // The own host is stopped, not destroyed: a late wake() from another
        // thread still finds it (and the removed handle does nothing).
        if (own_) own_->stop();
    }

    bool shared() const { return host_ != nullptr && !own_; }

private:
    std::unique_ptr<PollHost> own_;
    PollHost* host_ = nullptr;
    PollHost::Handle handle_;
};

}  // namespace nclink::core_detail
