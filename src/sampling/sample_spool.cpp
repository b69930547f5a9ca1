#include "sampling/sample_spool.hpp"

#include <algorithm>
#include <filesystem>

namespace nclink::sampling_detail {
namespace {

std::size_t cost(const Message& m) { return m.topic.size() + m.payload.size(); }

constexpr std::string_view kMarker = R"("privateInfo":{"replayed":true})";

// How long the spool worker waits for the transport's backlog to shrink.
constexpr auto kBacklogPoll = std::chrono::milliseconds(2);
constexpr std::size_t kStepsPerTurn = 64;
constexpr auto kDiskRetry = std::chrono::seconds(10);

}  // namespace

Json to_json(const SpoolStats& s) {
    return Json{{"spooled", s.spooled},       {"replayed", s.replayed},
                {"dropped", s.dropped},       {"dropped_bytes", s.dropped_bytes},
                {"spilled", s.spilled},       {"disk_errors", s.disk_errors},
                {"pending", s.pending},       {"memory_bytes", s.memory_bytes},
                {"disk_bytes", s.disk_bytes}, {"disk_segments", s.disk_segments}};
}

std::string mark_replayed(std::string payload) {
    // Fast path (the encoder's DTUs carry no privateInfo): splice the marker
    // in before the closing brace, no parse. A string value cannot contain
    // the unescaped text "privateInfo" with quotes, so this finds keys only.
    if (payload.find("\"privateInfo\"") == std::string::npos) {
        const auto open = payload.find_first_not_of(" \t\r\n");
        const auto close = payload.find_last_not_of(" \t\r\n");
        if (open == std::string::npos || payload[open] != '{' || payload[close] != '}' || close == open) return payload;
        const auto last = payload.find_last_not_of(" \t\r\n", close - 1);
        const bool empty_object = last == open;
        payload.insert(close, std::string(empty_object ? "" : ",") + std::string(kMarker));
        return payload;
    }
    Json dtu = Json::parse(payload, nullptr, false);
    if (dtu.is_discarded() || !dtu.is_object()) return payload;
    Json& info = dtu["privateInfo"];
    if (info.is_null()) info = Json::object();
    else if (!info.is_object()) info = Json{{"value", info}};
    info["replayed"] = true;
    return dtu.dump(-1, ' ', false, Json::error_handler_t::replace);
}

bool is_replayed(const Json& dtu) {
    if (!dtu.is_object()) return false;
    auto info = dtu.find("privateInfo");
    if (info == dtu.end() || !info->is_object()) return false;
    auto flag = info->find("replayed");
    return flag != info->end() && flag->is_boolean() && flag->get<bool>();
}

SampleSpool::SampleSpool(SpoolOptions options, Transport& transport, Logger logger, core_detail::PollHost* work)
    : options_(std::move(options)),
      transport_(transport),
      logger_(std::move(logger)),
      segment_bytes_(std::clamp<std::size_t>(options_.memory_bytes / 4, 16u << 10, 1u << 20)),
      work_(work) {}

SampleSpool::~SampleSpool() { stop(); }

Result<void> SampleSpool::start() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (started_) return ok_result();
    started_ = true;
    if (disk_enabled()) {
        lock.unlock();
        auto listed = list_segments(options_.disk_dir);
        lock.lock();
        if (!listed) {
            logger_.error("sample spool: {}; spooling to RAM only", listed.error().message);
            counters_.disk_errors++;
            disk_retry_at_ = std::chrono::steady_clock::time_point::max();
        } else {
            std::size_t dtus = 0;
            for (auto& segment : listed.value()) {
                disk_used_ += segment.bytes;
                dtus += segment.records;
                next_seq_ = std::max(next_seq_, segment.seq + 1);
                segments_.push_back(std::move(segment));
            }
            if (dtus > 0)
                logger_.info("sample spool: {} DTU(s) spooled by a previous run in {} are replayed after connecting", dtus,
                             options_.disk_dir);
            enforce_disk_budget_locked();
        }
    }
    link_up_ = transport_.state() == LinkState::connected;
    worker_.start(work_, "nclink-spool", [this](core_detail::PollHost::Time) { return turn(); });
    return ok_result();
}

void SampleSpool::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!started_ || stopped_) return;
        stopping_ = true;
    }
    worker_.stop();  // returns once no turn of the worker runs or will
    {
        // From here publish() drops (counted): the engine stops before us.
        std::lock_guard<std::mutex> lock(mutex_);
        stopped_ = true;
    }
    persist_on_stop();
}

void SampleSpool::publish(Message message) {
    std::lock_guard<std::mutex> order(order_mutex_);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopped_ || !link_up_ || pending_locked() > 0) {
            enqueue_locked(std::move(message));
            worker_.wake();
            return;
        }
    }
    if (auto sent = transport_.publish(std::move(message)); !sent) {
        std::lock_guard<std::mutex> lock(mutex_);
        ++counters_.dropped;
        logger_.debug("sample spool: transport refused a Sample DTU: {}", sent.error().message);
    }
}

void SampleSpool::on_link(LinkState link) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        link_up_ = link == LinkState::connected;
        if (link_up_ && drop_burst_ > 0) {
            logger_.warn("sample spool: {} DTU(s) dropped while offline (budget full)", drop_burst_);
            drop_burst_ = 0;
        }
        worker_.wake();
    }
}

SpoolStats SampleSpool::stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    SpoolStats s = counters_;
    s.pending = pending_locked();
    s.memory_bytes = memory_used_;
    s.disk_bytes = disk_used_;
    s.disk_segments = segments_.size() + (has_loaded_ ? 1 : 0);
    return s;
}

bool SampleSpool::empty() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return pending_locked() == 0;
}

std::size_t SampleSpool::pending_locked() const {
    std::size_t n = memory_.size() + loaded_.size() + spilling_;
    for (const auto& segment : segments_) n += segment.records;
    return n;
}

void SampleSpool::enqueue_locked(Message message) {
    const std::size_t size = cost(message);
    if (stopped_ || options_.memory_bytes == 0 || size > options_.memory_bytes) {
        ++counters_.dropped;
        counters_.dropped_bytes += size;
        if (drop_burst_++ == 0)
            logger_.warn("sample spool: {}: dropping Sample DTUs, first on {}",
                         stopped_                     ? "stopped"
                         : options_.memory_bytes == 0 ? "offline and no spool configured"
                                                      : "a DTU larger than the whole spool",
                         message.topic);
        return;
    }
    memory_used_ += size;
    memory_.push_back(std::move(message));
    ++counters_.spooled;
    // The spool worker moves RAM to disk from half the budget on; RAM is a
    // hard limit even when the disk cannot keep up.
    while (memory_used_ > options_.memory_bytes) drop_memory_front_locked();
}

void SampleSpool::drop_memory_front_locked() {
    const std::size_t size = cost(memory_.front());
    if (drop_burst_++ == 0)
        logger_.warn("sample spool full ({} bytes RAM{}): dropping the oldest Sample DTUs, first on {}", options_.memory_bytes,
                     disk_enabled() ? fmt::format(", {} bytes disk", options_.disk_bytes) : "", memory_.front().topic);
    memory_used_ -= size;
    ++counters_.dropped;
    counters_.dropped_bytes += size;
    memory_.pop_front();
}

core_detail::PollHost::Time SampleSpool::turn() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (std::size_t step = 0; !stopping_; ++step) {
        // A long replay goes in turns, so the other machines on the shared
        // threads are not held up behind it.
        if (step == kStepsPerTurn) return std::chrono::steady_clock::now();
        const bool can_spill = disk_enabled() && std::chrono::steady_clock::now() >= disk_retry_at_;
        if (can_spill && memory_used_ > options_.memory_bytes / 2 && !memory_.empty()) {
            spill_one_segment(lock);
            continue;
        }
        if (link_up_ && pending_locked() > 0) {
            // Pace by the transport's backlog: stats() is cheap (one lock).
            lock.unlock();
            const auto transport = transport_.stats();
            const bool room = transport.buffered < options_.replay_backlog;
            const bool replayed = room && replay_one();
            lock.lock();
            if (!replayed) return std::chrono::steady_clock::now() + kBacklogPoll;
            continue;
        }
        return core_detail::PollHost::Time::max();  // publish() or on_link() wakes it
    }
    return core_detail::PollHost::Time::max();
}

void SampleSpool::spill_one_segment(std::unique_lock<std::mutex>& lock) {
    std::vector<Message> batch;
    std::size_t bytes = 0;
    while (!memory_.empty() && (batch.empty() || bytes + cost(memory_.front()) <= segment_bytes_)) {
        bytes += cost(memory_.front());
        memory_used_ -= cost(memory_.front());
        batch.push_back(std::move(memory_.front()));
        memory_.pop_front();
    }
    const std::uint64_t seq = next_seq_++;
    // The batch is older than anything left in RAM and newer than every
    // segment; replay (this thread too) does not run until it is placed.
    spilling_ = batch.size();
    lock.unlock();
    auto written = write_segment(options_.disk_dir, seq, batch);
    lock.lock();
    spilling_ = 0;
    if (!written) {
        ++counters_.disk_errors;
        disk_retry_at_ = std::chrono::steady_clock::now() + kDiskRetry;
        logger_.error("sample spool: cannot write a segment ({}); keeping DTUs in RAM, retrying in {} s", written.error().message,
                      kDiskRetry.count());
        for (auto it = batch.rbegin(); it != batch.rend(); ++it) {
            memory_used_ += cost(*it);
            memory_.push_front(std::move(*it));
        }
        while (memory_used_ > options_.memory_bytes) drop_memory_front_locked();
        return;
    }
    counters_.spilled += batch.size();
    disk_used_ += written.value().bytes;
    segments_.push_back(std::move(written).value());
    enforce_disk_budget_locked();
}

void SampleSpool::enforce_disk_budget_locked() {
    while (disk_used_ > options_.disk_bytes && !segments_.empty()) {
        const SegmentInfo oldest = segments_.front();
        segments_.pop_front();
        std::error_code ec;
        std::filesystem::remove(oldest.path, ec);
        disk_used_ -= std::min(disk_used_, oldest.bytes);
        counters_.dropped += oldest.records;
        counters_.dropped_bytes += oldest.bytes;
        if (drop_burst_++ == 0)
            logger_.warn("sample spool disk budget full ({} bytes): dropping the oldest segment ({} DTUs)", options_.disk_bytes,
                         oldest.records);
    }
}

bool SampleSpool::load_next_segment(std::unique_lock<std::mutex>& lock) {
    if (segments_.empty()) return false;
    SegmentInfo next = segments_.front();
    segments_.pop_front();
    lock.unlock();
    SegmentContents contents = read_segment(next);
    lock.lock();
    if (contents.damaged > 0) {
        counters_.dropped += contents.damaged;
        logger_.error("sample spool: {} damaged: {} of {} DTU(s) unreadable, dropped", next.path, contents.damaged, next.records);
    }
    next.records = contents.messages.size();  // pending counts what can be replayed
    loaded_info_ = std::move(next);
    loaded_.assign(std::make_move_iterator(contents.messages.begin()), std::make_move_iterator(contents.messages.end()));
    has_loaded_ = true;
    return true;
}

void SampleSpool::finish_loaded_locked() {
    std::error_code ec;
    std::filesystem::remove(loaded_info_.path, ec);
    disk_used_ -= std::min(disk_used_, loaded_info_.bytes);
    has_loaded_ = false;
    loaded_info_ = {};
}

bool SampleSpool::replay_one() {
    // Disk segments hold the oldest DTUs: load the next one outside the
    // order lock (file I/O must not hold up live publishes).
    {
        std::unique_lock<std::mutex> lock(mutex_);
        if (has_loaded_ && loaded_.empty()) finish_loaded_locked();
        if (!has_loaded_ && !segments_.empty()) load_next_segment(lock);
    }
    Message next;
    {
        std::lock_guard<std::mutex> order(order_mutex_);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!link_up_ || stopping_) return false;
            if (!loaded_.empty()) {
                next = std::move(loaded_.front());
                loaded_.pop_front();
            } else if (has_loaded_ || !segments_.empty()) {
                return true;  // the segment just finished: come back for the next one
            } else if (!memory_.empty()) {
                next = std::move(memory_.front());
                memory_used_ -= cost(next);
                memory_.pop_front();
            } else {
                return false;
            }
        }
        next.payload = mark_replayed(std::move(next.payload));
        const auto sent = transport_.publish(std::move(next));
        std::lock_guard<std::mutex> lock(mutex_);
        if (sent) ++counters_.replayed;
        else ++counters_.dropped;
    }
    return true;
}

void SampleSpool::persist_on_stop() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (pending_locked() == 0) return;
    if (disk_enabled()) {
        // The rest of a half-replayed segment replaces it; RAM follows as new
        // segments. Oldest first, so sequence numbers keep the order.
        if (has_loaded_) {
            std::vector<Message> rest(std::make_move_iterator(loaded_.begin()), std::make_move_iterator(loaded_.end()));
            loaded_.clear();
            const SegmentInfo old = loaded_info_;
            finish_loaded_locked();
            if (!rest.empty()) {
                auto written = write_segment(options_.disk_dir, old.seq, rest);
                if (written) {
                    disk_used_ += written.value().bytes;
                    segments_.push_front(std::move(written).value());
                } else {
                    counters_.dropped += rest.size();
                    ++counters_.disk_errors;
                }
            }
        }
        while (!memory_.empty()) {
            spill_one_segment(lock);
            if (std::chrono::steady_clock::now() < disk_retry_at_) break;  // the disk failed
        }
        enforce_disk_budget_locked();
        if (!memory_.empty()) {
            logger_.warn("sample spool: {} Sample DTU(s) could not be written to disk at stop and are lost", memory_.size());
            counters_.dropped += memory_.size();
            memory_.clear();
            memory_used_ = 0;
        }
        if (const std::size_t kept = pending_locked(); kept > 0)
            logger_.info("sample spool: {} Sample DTU(s) kept in {} for the next start", kept, options_.disk_dir);
        return;
    }
    if (link_up_) {
        // No disk: hand the rest to the transport, which flushes at stop.
        std::deque<Message> rest;
        rest.swap(memory_);
        memory_used_ = 0;
        lock.unlock();
        std::lock_guard<std::mutex> order(order_mutex_);
        for (auto& m : rest) {
            m.payload = mark_replayed(std::move(m.payload));
            const bool sent = transport_.publish(std::move(m)).ok();
            std::lock_guard<std::mutex> relock(mutex_);
            ++(sent ? counters_.replayed : counters_.dropped);
        }
        return;
    }
    logger_.warn("sample spool: stopping offline without a disk budget: {} Sample DTU(s) lost", memory_.size());
    counters_.dropped += memory_.size();
    memory_.clear();
    memory_used_ = 0;
}

}  // namespace nclink::sampling_detail
