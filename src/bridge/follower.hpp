// The NC-Link side of the bridge: an application (include/nclink/client.hpp)
// that follows adapters and feeds the store.
//
// Which adapters: the configured devices, or — with none configured — every
// adapter that announces itself: each terminal whose retained Notify/State
// (8.2.16) says online and that answers Probe/Query is followed, and the
// agent's Discovery (8.2.3), when an agent runs, adds the adapters it lists.
//
// Per adapter:
//  - Probe/Query (8.2.7) gives the model; the store maps it;
//  - Query (8.2.11) of every data object gives initial values, again after
//    every online;
//  - Sample DTUs of the model channels (Sample/{dev}/+, 8.2.15) give the
//    sampled items, one observation per row and item at beginTime + row x
//    sampleInterval;
//  - items in no channel: a change event (Register/Event, default change
//    filter, trigger always; 8.2.27) per single-valued item, their Event DTUs
//    give the values; items the adapter refuses an event for (e.g. 416 when
//    its event slots run out) and list/dict items are queried every
//    poll_interval, which is never shorter than the model's shortest
//    channel sampleInterval (docs/bridge.md "Where values come from");
//  - Notify/State offline turns its items UNAVAILABLE; online brings a new
//    Probe/Query, Query and event registration (the adapter lost its events
//    when it restarted);
//  - an adapter heard nothing from for `liveness` (no Sample, event or
//    answer) is asked a Query of one item; no answer within the request
//    timeout turns its items UNAVAILABLE as an offline state would, until it
//    answers a later check, publishes a DTU or says online. Its last will
//    does not cover this: a broker node that dies takes the will with it
//    (docs/scaling.md), and a link that hangs keeps it for 1.5 keep-alives;
//  - Probe/Version (8.2.5) with a new version brings a new Probe/Query;
//  - Method/Status and Method/Result (8.2.23, 8.2.24) of every caller and
//    the Event DTUs (8.2.31) of every other application's registrations go
//    to the store's per-device activity log (the broker passes them only
//    with the agent's "watch" right; docs/security.md). The bridge's own
//    change events are values, not log entries.
//
// Threading: the client's callbacks run on its dispatch thread; one
// housekeeping thread polls and discovers; set() is called from HTTP
// workers. The follower's own state is guarded by a mutex.
#pragma once

#include "bridge/bridge_store.hpp"

#include <nclink/client.hpp>
#include <nclink/log.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace nclink::bridge {

struct FollowerOptions {
    std::vector<std::string> devices;  ///< empty: follow every adapter found
    std::chrono::milliseconds poll_interval{1000};
    std::chrono::milliseconds discovery_interval{30000};
    std::chrono::milliseconds request_timeout{3000};
    bool use_events = true;  ///< false: every item in no channel is polled
    /// Silence after which an adapter is asked whether it is there; 0 = never
    /// (its Notify/State alone tells).
    std::chrono::milliseconds liveness{10000};
    Logger logger;
};

class Follower {
public:
    Follower(Client& client, BridgeStore& store, FollowerOptions options);
    ~Follower();  ///< stop()s
    Follower(const Follower&) = delete;
    Follower& operator=(const Follower&) = delete;

    /// Subscribes and starts the housekeeping thread. The client must be started.
    Result<void> start();
    void stop();

    /// NC-Link Set of `items` at `dev` (blocking; not from a client callback).
    Result<std::vector<SetResult>> set(const std::string& dev, std::vector<SetItem> items);
    /// NC-Link Method/Call of `method` at `dev` (8.2.22), answered with its
    /// Method/Result (8.2.24; a refused call is a result `error` with its
    /// table-19 code). Blocks until the result or `timeout` (then timeout 203;
    /// the run itself goes on at the machine). Not from a client callback.
    Result<MethodResult> call(const std::string& dev, const std::string& method, Json args, std::chrono::milliseconds timeout);

private:
    struct Followed {
        std::shared_ptr<const Model> model;
        std::vector<std::string> event_ids;
        std::vector<std::string> polled;  ///< items queried every poll interval
        std::chrono::milliseconds poll_interval{1000};
        std::chrono::steady_clock::time_point next_poll{};
        bool refreshing = false;
        bool refresh_again = false;
        std::uint64_t epoch = 0;                             ///< grows with every refresh; late answers of older ones are dropped
        std::chrono::steady_clock::time_point last_heard{};  ///< its last DTU or answer
        std::string check_item;                              ///< what a liveness check queries ("": Probe/Query)
        bool checking = false;                               ///< a liveness check waits for its answer
        bool silent = false;                                 ///< UNAVAILABLE because a check went unanswered, not by its state
        /// A sign of the adapter now (under the follower's mutex); true when
        /// it had been found silent.
        bool heard_now() {
            last_heard = std::chrono::steady_clock::now();
            return std::exchange(silent, false);
        }
    };

    void follow(const std::string& dev);
    void consider(const std::string& tid);  // discovery candidate
    void on_state(const NotifyState& state);
    void on_sample(const SampleDtu& dtu);
    void on_method_run(const MethodRun& run);
    void on_event(const WatchedEvent& event);
    void refresh(const std::string& dev);
    void after_probe(const std::string& dev, std::uint64_t epoch, Result<Json> model);
    void register_events(const std::string& dev, std::uint64_t epoch);
    void query_items(const std::string& dev, const std::vector<std::string>& ids);
    void store_answers(const std::string& dev, const std::vector<QueryResult>& results);
    void heard(const std::string& dev);
    void follow_again(const std::string& dev);
    void check_silent(std::chrono::steady_clock::time_point now);
    void checked(const std::string& dev, bool answered);
    void housekeeping();

    Client& client_;
    BridgeStore& store_;
    FollowerOptions options_;
    RequestOptions request_options_;

    std::mutex mutex_;
    std::map<std::string, Followed> followed_;
    std::set<std::string> probing_;  ///< discovery candidates being probed
    std::vector<SubscriptionId> subscriptions_;

    std::atomic<bool> running_{false};
    std::mutex wake_mutex_;
    std::condition_variable wake_;
    std::thread housekeeper_;
};

}  // namespace nclink::bridge
