// Soak (docs/delivery.md): the simulated mill behind an adapter, an
// application with a persistent session subscribed to every model channel and
// to one event per sampled item, a real mosquitto with crash-safe persistence
// restarted every period. At the end the adapter stops (flushing), and the
// program prints rows and events produced vs received: lost, duplicated
// (handed to the application twice, and held back by the client), late
// (received more than 1 s after their last row's time), and the process's
// RSS growth. Not a test: run it by hand.
//
//   bench_soak [seconds=600] [restart_period_s=60] [--crash] [--save-every N]
//
// --crash kills the broker (-9) instead of stopping it cleanly. --save-every
// N: the broker saves after every N changes (autosave_interval N; default 1,
// after every change).
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/model.hpp>
#include "sim/sim_driver.hpp"

#include "support/mosquitto_broker.hpp"
#include "support/row_ledger.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <malloc.h>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

using namespace nclink;
using namespace std::chrono_literals;

namespace {

long rss_kb() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::strtol(line.c_str() + 6, nullptr, 10);
    return 0;
}

std::int64_t wall_ms() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

template <class P>
bool wait_for(P&& done, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!done()) {
        if (std::chrono::steady_clock::now() > deadline) return false;
        std::this_thread::sleep_for(10ms);
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    int seconds = 600, period = 60;
    bool crash = false;
    int save_every = 1;
    int positional = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--crash") crash = true;
        else if (arg == "--save-every" && i + 1 < argc) save_every = std::max(1, std::atoi(argv[++i]));
        else if (positional++ == 0) seconds = std::atoi(argv[i]);
        else period = std::atoi(argv[i]);
    }
    const std::string model_path = std::string(NCLINK_SOURCE_DIR) + "/models/sim-mill.json";
    const std::string dev = "nclink-sim-mill-01";
    const std::map<std::string, std::int64_t> intervals = {{"ch_fast", 1}, {"ch_slow", 100}};
    const std::vector<std::string> items = {"x_position",    "y_position",   "z_position", "x_speed",     "y_speed",   "z_speed",
                                            "spindle_speed", "spindle_load", "feed_speed", "x_load",      "y_load",    "z_load",
                                            "x_current",     "y_current",    "z_current",  "line_number", "part_count"};

    test::MosquittoOptions broker_options;
    broker_options.persistent = true;
    broker_options.save_every_change = true;
    broker_options.save_after_changes = save_every;
    test::MosquittoBroker broker(broker_options);

    // The application first: every row the adapter publishes is meant for it.
    test::RowLedger ledger(intervals);
    std::atomic<std::uint64_t> late_dtus{0}, dtus{0};
    std::mutex events_mutex;
    std::set<std::string> event_ids;
    // @id counter -> event time, to place lost events against the restarts.
    std::map<std::uint64_t, std::int64_t> event_times;
    std::vector<std::pair<std::int64_t, std::int64_t>> outages;  // wall ms: broker stopped, started again
    std::uint64_t event_repeats = 0;
    MqttOptions m;
    m.broker_url = broker.url();
    m.client_id = "nclink-soak-app";
    m.clean_session = false;
    m.reconnect_max = 1000ms;
    ClientOptions o;
    o.ex_cid = "soak-app";
    o.default_timeout = 5s;
    o.logger = Logger(stderr_sink(), LogLevel::warn);
    auto client = Client::create(m, o).value();
    (void)client->subscribe_samples(dev, [&](const SampleDtu& d) {
        ++dtus;
        ledger.add(d);
        const auto rows = d.data.empty() || !d.data[0].is_array() ? 0 : d.data[0].size();
        const auto interval = d.id == "ch_fast" ? 1 : 100;
        if (wall_ms() - (d.begin_time + static_cast<std::int64_t>(rows) * interval) > 1000) ++late_dtus;
    });
    if (!client->start().ok() || !client->wait_connected(10s)) {
        std::fprintf(stderr, "bench_soak: the application cannot connect\n");
        return 1;
    }
    std::this_thread::sleep_for(300ms);

    AdapterConfig c;
    c.model_path = model_path;
    c.broker_url = broker.url();
    c.register_timeout = 500ms;
    c.events.poll_interval = 100ms;
    auto loaded = load_model_file(model_path);
    auto driver = SimDriver::create(loaded.model).value();
    auto adapter_owner = std::make_unique<Adapter>(c, std::move(driver), Logger(stderr_sink(), LogLevel::warn));
    Adapter& adapter = *adapter_owner;
    if (!adapter.start().ok()) {
        std::fprintf(stderr, "bench_soak: the adapter does not start\n");
        return 1;
    }
    wait_for([&] { return adapter.state() == AdapterState::normal; }, 10s);
    std::size_t registered = 0;
    for (const auto& item : items) {
        Client::EventRegistration r;
        r.id = item;  // the default change filter
        auto id = client->register_event(dev, r, [&](const EventData& e) {
            std::lock_guard<std::mutex> lock(events_mutex);
            if (!event_ids.insert(e.msg_id ? e.msg_id->dump() : std::to_string(event_ids.size())).second) ++event_repeats;
            if (e.msg_id && e.msg_id->is_string()) {
                const std::string& text = e.msg_id->get_ref<const std::string&>();
                const auto digits = text.find_last_not_of("0123456789");
                if (digits != std::string::npos && digits + 1 < text.size())
                    event_times[std::stoull(text.substr(digits + 1))] = e.time;
            }
        });
        if (id) ++registered;
    }
    std::this_thread::sleep_for(2s);
    const long rss_start = rss_kb();
    std::printf(
        "soak: %d s, broker %s every %d s (saving after every %d change(s)), %zu events registered, RSS at start %ld kB\n",
        seconds, crash ? "killed -9" : "restarted", period, save_every, registered, rss_start);
    std::fflush(stdout);

    const auto begun = std::chrono::steady_clock::now();
    int restarts = 0;
    while (std::chrono::steady_clock::now() - begun < std::chrono::seconds(seconds)) {
        const auto next = begun + std::chrono::seconds(period * (restarts + 1));
        std::this_thread::sleep_until(std::min(next, begun + std::chrono::seconds(seconds)));
        if (std::chrono::steady_clock::now() - begun >= std::chrono::seconds(seconds)) break;
        const auto stopped_at = wall_ms();
        if (crash) broker.crash();
        else broker.stop();
        std::this_thread::sleep_for(1s);
        broker.start();
        {
            std::lock_guard<std::mutex> guard(events_mutex);
            outages.emplace_back(stopped_at, wall_ms());
        }
        ++restarts;
        std::printf("  restart %d at %lld s: rows %llu, RSS %ld kB\n", restarts,
                    static_cast<long long>(
                        std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - begun).count()),
                    static_cast<unsigned long long>(ledger.rows()), rss_kb());
        std::fflush(stdout);
    }
    wait_for([&] { return adapter.stats().features["sampling"]["spool"]["pending"].get<std::uint64_t>() == 0; }, 60s);
    const long rss_end = rss_kb();
    adapter.stop(10s);
    std::uint64_t produced = 0;
    for (const auto& ch : adapter.sampling_stats().channels) produced += ch.rows_published;
    const auto fired = adapter.stats().features["events"]["fired"].get<std::uint64_t>();
    wait_for(
        [&] {
            std::lock_guard<std::mutex> lock(events_mutex);
            return ledger.rows() >= produced && event_ids.size() >= fired;
        },
        60s);
    std::unique_lock<std::mutex> lock(events_mutex);
    const auto stats = client->stats();
    const Json drops = to_json(adapter.stats())["drops"];
    std::printf("rows: produced %llu, received %llu, lost %lld, duplicated %llu (held back by the client: %llu DTUs)\n",
                static_cast<unsigned long long>(produced), static_cast<unsigned long long>(ledger.rows()),
                static_cast<long long>(produced) - static_cast<long long>(ledger.rows()),
                static_cast<unsigned long long>(ledger.duplicates()), static_cast<unsigned long long>(stats.duplicates));
    std::printf("events: fired %llu, received %zu, lost %lld, duplicated %llu\n", static_cast<unsigned long long>(fired),
                event_ids.size(), static_cast<long long>(fired) - static_cast<long long>(event_ids.size()),
                static_cast<unsigned long long>(event_repeats));
    // Where the lost events were: gaps in the adapter's @id counter between
    // two received events (the counter also numbers a few other DTUs, so a
    // gap of one or two may be one of those), placed against the outages.
    {
        std::size_t gaps_shown = 0;
        std::uint64_t previous = 0;
        std::int64_t previous_time = 0;
        for (const auto& [counter, time] : event_times) {
            if (previous != 0 && counter > previous + 2 && gaps_shown < 40) {
                std::int64_t nearest = 0;
                for (const auto& [down, up] : outages)
                    if (nearest == 0 || std::llabs(previous_time - down) < std::llabs(previous_time - nearest)) nearest = down;
                std::printf(
                    "  gap: %llu @ids missing after %llu (event time %+lld ms from the nearest broker stop, next received %+lld "
                    "ms)\n",
                    static_cast<unsigned long long>(counter - previous - 1), static_cast<unsigned long long>(previous),
                    static_cast<long long>(previous_time - nearest), static_cast<long long>(time - nearest));
                ++gaps_shown;
            }
            previous = counter;
            previous_time = time;
        }
    }
    std::printf("late (> 1 s after their last row): %llu of %llu DTUs\n", static_cast<unsigned long long>(late_dtus.load()),
                static_cast<unsigned long long>(dtus.load()));
    std::printf("adapter drops by cause: %s\n", drops.dump().c_str());
    // Messages the application's connection received, against what was
    // handed on: an event lost before the client shows as fewer messages.
    const auto& link = stats.transport;
    std::printf(
        "application connection: %llu messages received = %llu Sample DTUs + %llu events handed on + %llu held back + %llu "
        "other\n",
        static_cast<unsigned long long>(link.received), static_cast<unsigned long long>(dtus.load()),
        static_cast<unsigned long long>(stats.events), static_cast<unsigned long long>(stats.duplicates),
        static_cast<unsigned long long>(link.received -
                                        std::min<std::uint64_t>(link.received, dtus.load() + stats.events + stats.duplicates)));
    // Where an event that fired but never reached the handler could have gone.
    std::printf(
        "client: events handed on %llu, unmatched %llu, malformed %llu, held back %llu; adapter: applications released %llu\n",
        static_cast<unsigned long long>(stats.events), static_cast<unsigned long long>(stats.unmatched_responses),
        static_cast<unsigned long long>(stats.malformed), static_cast<unsigned long long>(stats.duplicates),
        static_cast<unsigned long long>(adapter.stats().applications_released));
    std::printf("RSS: %ld kB at start, %ld kB at end, growth %ld kB over %d broker restarts\n", rss_start, rss_end,
                rss_end - rss_start, restarts);
    // Whose growth it was: the benchmark's own ledgers (every row time and
    // event id) are freed first, then the adapter and the client. What stays
    // after both are gone would be a leak.
    ledger.clear();
    std::set<std::string>().swap(event_ids);
    std::map<std::uint64_t, std::int64_t>().swap(event_times);
    ::malloc_trim(0);
    const long rss_without_ledgers = rss_kb();
    lock.unlock();  // a callback still queued on the client's thread may want it
    client->stop();
    client.reset();
    adapter_owner.reset();
    ::malloc_trim(0);
    const long rss_after = rss_kb();
    std::printf(
        "RSS: %ld kB without the benchmark's ledgers (they held %ld kB), %ld kB with adapter and client gone "
        "(%+ld kB against the start)\n",
        rss_without_ledgers, rss_end - rss_without_ledgers, rss_after, rss_after - rss_start);
    return 0;
}
