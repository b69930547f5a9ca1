// Many machines in one process (docs/gateway.md). Each machine is a whole
// adapter with its own connection (so its own last will) and terminal id;
// the gateway keeps the list, starts them a few at a time (connecting is
// what takes time) and adds or removes one without touching the others.
#include <nclink/gateway.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <set>
#include <thread>

namespace nclink {

namespace {
// Descriptors a machine may hold: its broker connection (3 with
// libmosquitto: the socket and a wake-up pair), spool and persistence files.
constexpr rlim_t kFilesPerMachine = 8;

// The soft limit is 1024 on a stock Debian while the hard one is far higher:
// a gateway of a few hundred machines would fail to connect the rest with
// EMFILE. Raised (never lowered) to what the machines need, within the hard limit.
void raise_open_file_limit(std::size_t machines, const Logger& logger) {
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return;
    const rlim_t wanted = 256 + kFilesPerMachine * static_cast<rlim_t>(machines);
    if (limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur >= wanted) return;
    const rlim_t before = limit.rlim_cur;
    limit.rlim_cur = limit.rlim_max == RLIM_INFINITY ? wanted : std::min(wanted, limit.rlim_max);
    if (limit.rlim_cur > before && ::setrlimit(RLIMIT_NOFILE, &limit) == 0)
        logger.info("gateway: open file limit raised from {} to {} for {} machine(s)", before, limit.rlim_cur, machines);
    if (limit.rlim_cur < wanted)
        logger.warn("gateway: {} machine(s) may need {} open files, the limit is {} (raise LimitNOFILE / ulimit -n)", machines,
                    wanted, limit.rlim_cur);
}

SharedThreadsOptions shared_options(const GatewayConfig& config) {
    SharedThreadsOptions o;
    o.timer_threads = config.timer_threads;
    o.request_threads = config.request_threads;
    o.driver_threads = config.driver_threads;
    o.work_threads = config.work_threads;
    o.shared_mqtt_io = config.mqtt_client != "paho";
    o.mqtt_connect_max = config.mqtt_connect_max;
    return o;
}
}  // namespace

struct NCLINK_LOCAL Gateway::Impl {
    GatewayConfig config;
    MachineDriverFactory drivers;
    Logger logger;
    // Every machine takes its timers, request workers and deadline watchdog
    // from these (shared_threads.hpp): a fixed set for the process.
    std::shared_ptr<SharedThreads> threads;
    // Machines of one model file share one parsed model and its value rules
    // (model_cache.hpp): a 300-point model is about 0.7 MB per machine.
    std::shared_ptr<ModelCache> models = std::make_shared<ModelCache>();

    mutable std::mutex mutex;
    std::map<std::string, std::shared_ptr<Adapter>> running;  // by machine id
    std::map<std::string, std::string> guid_owner;            // dev_uuid -> machine id
    std::set<std::string> reserved;                           // ids being started or stopped
    bool started = false;
    bool stopped = false;

    Impl(GatewayConfig c, MachineDriverFactory d, Logger l)
        : config(std::move(c)),
          drivers(std::move(d)),
          logger(std::move(l)),
          threads(std::make_shared<SharedThreads>(shared_options(config))) {}

    Result<void> add(MachineConfig machine) {
        const std::string id = machine.id;
        const std::string guid = machine.adapter.dev_uuid;
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (stopped) return make_error(ErrorCode::unavailable, "gateway stopped");
            if (running.count(id) || reserved.count(id))
                return make_error(ErrorCode::keys_of_arguments, fmt::format("machine '{}' is already served", id));
            // Two adapters with one GUID would share a client id and push
            // each other off the broker: refuse before connecting.
            if (!guid.empty() && guid_owner.count(guid))
                return make_error(ErrorCode::keys_of_arguments,
                                  fmt::format("GUID '{}' is already served by machine '{}'", guid, guid_owner.at(guid)));
            reserved.insert(id);
            if (!guid.empty()) guid_owner[guid] = id;
        }
        auto release = [&](const std::string& dev) {
            std::lock_guard<std::mutex> lock(mutex);
            reserved.erase(id);
            if (auto it = guid_owner.find(dev); it != guid_owner.end() && it->second == id) guid_owner.erase(it);
        };
        std::shared_ptr<Driver> driver;
        if (machine.adapter.driver_plugin.empty()) {
            if (!drivers) {
                release(guid);
                return make_error(ErrorCode::parameter_missing,
                                  fmt::format("machine '{}': no driver plugin configured and no driver factory", id));
            }
            auto made = drivers(machine);
            if (!made || !made.value()) {
                release(guid);
                return make_error(made ? ErrorCode::parameter_missing : made.error().code,
                                  fmt::format("machine '{}': {}", id, made ? "no driver" : made.error().message));
            }
            driver = std::move(made).value();
        }
        auto adapter = std::make_shared<Adapter>(machine.adapter, std::move(driver), logger);
        adapter->use_shared_threads(threads);
        adapter->use_model_cache(models);
        if (auto r = adapter->start(); !r) {
            adapter->stop(std::chrono::milliseconds(0));
            release(guid);
            return make_error(r.error().code, fmt::format("machine '{}': {}", id, r.error().message));
        }
        const std::string dev = adapter->dev_uuid();
        std::unique_lock<std::mutex> lock(mutex);
        reserved.erase(id);
        if (guid.empty()) {
            // The GUID came from the model: checked only now.
            if (guid_owner.count(dev)) {
                const std::string owner = guid_owner.at(dev);
                lock.unlock();
                adapter->stop(std::chrono::milliseconds(0));
                return make_error(ErrorCode::keys_of_arguments,
                                  fmt::format("machine '{}': GUID '{}' is already served by machine '{}'", id, dev, owner));
            }
            guid_owner[dev] = id;
        }
        running[id] = std::move(adapter);
        logger.info("gateway: machine {} serving as {}", id, dev);
        return ok_result();
    }

    Result<void> remove(const std::string& id, std::chrono::milliseconds flush) {
        std::shared_ptr<Adapter> adapter;
        {
            std::lock_guard<std::mutex> lock(mutex);
            const auto it = running.find(id);
            if (it == running.end()) return make_error(ErrorCode::node_not_exists, fmt::format("no machine '{}'", id));
            adapter = it->second;
            running.erase(it);
            reserved.insert(id);  // not added again until its connection is closed
        }
        adapter->stop(flush);  // publishes its offline state, closes its connection
        std::lock_guard<std::mutex> lock(mutex);
        reserved.erase(id);
        for (auto it = guid_owner.begin(); it != guid_owner.end();) it = it->second == id ? guid_owner.erase(it) : std::next(it);
        logger.info("gateway: machine {} removed", id);
        return ok_result();
    }

    // Runs `work` over the items on up to `threads` threads.
    template <class T, class Work>
    static void in_parallel(std::vector<T>& items, std::size_t threads, Work&& work) {
        std::atomic<std::size_t> next{0};
        auto run = [&] {
            for (std::size_t i = next++; i < items.size(); i = next++) work(items[i]);
        };
        std::vector<std::thread> pool;
        for (std::size_t t = 1; t < std::min(threads, items.size()); ++t) pool.emplace_back(run);
        run();
        for (auto& t : pool) t.join();
    }
};

Gateway::Gateway(GatewayConfig config, MachineDriverFactory drivers, Logger logger)
    : impl_(std::make_unique<Impl>(std::move(config), std::move(drivers), std::move(logger))) {}

Gateway::~Gateway() { stop(std::chrono::milliseconds(0)); }

Result<void> Gateway::start() {
    {
        std::lock_guard<std::mutex> lock(impl_->mutex);
        if (impl_->started) return make_error(ErrorCode::unavailable, "gateway already started");
        impl_->started = true;
    }
    std::vector<MachineConfig> machines = impl_->config.machines;
    raise_open_file_limit(machines.size(), impl_->logger);
    std::mutex errors_mutex;
    std::vector<std::string> errors;
    const std::size_t threads = impl_->config.start_threads ? impl_->config.start_threads : 4;
    Impl::in_parallel(machines, threads, [&](MachineConfig& m) {
        if (auto r = impl_->add(std::move(m)); !r) {
            impl_->logger.error("gateway: {}", r.error().message);
            std::lock_guard<std::mutex> lock(errors_mutex);
            errors.push_back(r.error().message);
        }
    });
    impl_->logger.info("gateway: {} of {} machine(s) serving", machines.size() - errors.size(), machines.size());
    if (errors.empty()) return ok_result();
    std::string all;
    for (const auto& e : errors) all += (all.empty() ? "" : "; ") + e;
    return make_error(ErrorCode::unavailable, fmt::format("{} machine(s) not started: {}", errors.size(), all));
}

void Gateway::stop(std::chrono::milliseconds flush_timeout) {
    std::vector<std::shared_ptr<Adapter>> adapters;
    {
        std::lock_guard<std::mutex> lock(impl_->mutex);
        if (impl_->stopped) return;
        impl_->stopped = true;
        for (auto& [id, adapter] : impl_->running) adapters.push_back(adapter);
        impl_->running.clear();
        impl_->guid_owner.clear();
    }
    const std::size_t threads = impl_->config.start_threads ? impl_->config.start_threads : 4;
    Impl::in_parallel(adapters, threads, [&](std::shared_ptr<Adapter>& a) { a->stop(flush_timeout); });
}

Result<void> Gateway::add_machine(MachineConfig machine) {
    std::size_t count = 0;
    {
        std::lock_guard<std::mutex> lock(impl_->mutex);
        count = impl_->running.size() + impl_->reserved.size() + 1;
    }
    raise_open_file_limit(count, impl_->logger);
    return impl_->add(std::move(machine));
}

Result<void> Gateway::remove_machine(const std::string& id, std::chrono::milliseconds flush_timeout) {
    return impl_->remove(id, flush_timeout);
}

GatewayReload Gateway::reload(GatewayConfig next) {  // `next` is taken apart: machines are moved out
    GatewayReload report;
    // Machines leave before others come, so the new list is the most that
    // run at once.
    raise_open_file_limit(next.machines.size(), impl_->logger);
    std::set<std::string> wanted;
    for (const auto& m : next.machines) wanted.insert(m.id);
    for (const auto& m : machines())
        if (!wanted.count(m.id)) {
            if (auto r = impl_->remove(m.id, std::chrono::milliseconds(2000)); r) report.removed.push_back(m.id);
        }
    for (auto& m : next.machines) {
        const std::string id = m.id;
        const std::shared_ptr<Adapter> adapter = machine(id);
        if (!adapter) {
            if (auto r = impl_->add(std::move(m)); r) report.added.push_back(id);
            else report.errors.push_back(r.error().message);
            continue;
        }
        // Adapter::reload compares with the configuration the machine runs
        // on: log_level applies at once, anything else needs a new start,
        // which in a gateway is this machine's alone.
        const ConfigReload changes = adapter->reload(m.adapter);
        if (changes.restart_needed.empty()) {
            if (!changes.applied.empty()) report.applied.push_back(id);
            continue;
        }
        impl_->logger.info("gateway: machine {} changed ({}): restarting it", id, fmt::join(changes.restart_needed, ", "));
        (void)impl_->remove(id, std::chrono::milliseconds(2000));
        if (auto r = impl_->add(std::move(m)); r) report.restarted.push_back(id);
        else report.errors.push_back(r.error().message);
    }
    return report;
}

std::vector<MachineInfo> Gateway::machines() const {
    std::vector<std::pair<std::string, std::shared_ptr<Adapter>>> copy;
    {
        std::lock_guard<std::mutex> lock(impl_->mutex);
        copy.assign(impl_->running.begin(), impl_->running.end());
    }
    std::vector<MachineInfo> out;
    for (const auto& [id, adapter] : copy) {
        MachineInfo info;
        info.id = id;
        info.dev_uuid = adapter->dev_uuid();
        info.state = adapter->state();
        info.registered = adapter->stats().registered;
        out.push_back(std::move(info));
    }
    return out;
}

std::shared_ptr<Adapter> Gateway::machine(const std::string& id) const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    const auto it = impl_->running.find(id);
    return it == impl_->running.end() ? nullptr : it->second;
}

}  // namespace nclink
