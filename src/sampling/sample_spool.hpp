// Offline store-and-forward of Sample DTUs (docs/store-and-forward.md).
//
// Sits between the sampling engine's DtuSink and the transport:
//
//   uploader --publish()--> [link up, nothing spooled] --> transport
//                           [otherwise] --> spool (memory, then disk segments)
//   spool worker: after reconnect, replays the spool in order into the
//   transport, each DTU marked "privateInfo": {"replayed": true}; DTUs
//   produced meanwhile queue behind the replay, so the order on the wire is
//   the order of production.
//
// Why Sample DTUs do not simply wait in the transport's own offline buffer
// (src/transport/outbox.*): that buffer is shared with request answers,
// events and method results, and a sampling backlog would crowd them out;
// samples also want a disk budget and a marker. So while the link is down
// Sample DTUs never reach the transport: nothing is buffered twice. Only DTUs
// handed to the transport before it noticed the link was gone sit in its
// buffer; they go out first after reconnect (it keeps publish order), ahead
// of the replay, so the order still holds. Of those, QoS 1 DTUs not yet
// acknowledged are sent again (at-least-once); a QoS 0 DTU the client had
// already written to the dying socket is lost (at-most-once: choose QoS 1
// per channel if that window matters).
//
// Replay is paced by the transport's backlog (at most replay_backlog
// messages waiting in it), so a large spool never overflows the transport's
// buffer and live answers are not stuck behind megabytes of samples.
//
// Budgets: memory_bytes in RAM (topic + payload bytes); with a disk
// directory and disk_bytes > 0, the oldest spooled DTUs move to segment
// files (spool_segment.hpp: atomic writes, CRC per record) once RAM is half
// full. When a budget is full the oldest DTUs are dropped and counted.
// Segments left by a previous run (a crash, or a stop while offline) are
// replayed after the first connect; a clean stop() writes what is still
// spooled to disk. A segment is deleted only after all of it was handed to
// the transport, so a crash during replay repeats part of it (never loses it).
//
// Threads: publish() from any thread (the uploader); on_link() from the
// transport's callback thread (never blocks: takes only the state lock,
// which is never held while calling the transport); the spool's worker
// spills to disk and replays, one turn at a time: serial work
// (core/serial_work.hpp), a pollable of the gateway's shared work threads or
// of a host of one thread of its own ("nclink-spool"). stats() from any
// thread.
#pragma once

#include "core/serial_work.hpp"
#include "sampling/spool_segment.hpp"

#include <nclink/json.hpp>
#include <nclink/log.hpp>
#include <nclink/result.hpp>
#include <nclink/transport.hpp>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <string_view>

namespace nclink::sampling_detail {

struct SpoolOptions {
    /// RAM for spooled DTUs (topic + payload bytes). 0 = no spool: Sample
    /// DTUs produced while the link is down are dropped (and counted).
    std::size_t memory_bytes = 4u << 20;
    /// Disk budget for segment files; 0 or an empty disk_dir = RAM only.
    std::size_t disk_bytes = 0;
    std::string disk_dir;
    /// While replaying, hand the transport the next DTU only while fewer than
    /// this many messages wait in its buffer.
    std::size_t replay_backlog = 32;
};

/// Counters only grow; pending/bytes are current levels.
struct SpoolStats {
    std::uint64_t spooled = 0;   ///< DTUs that entered the spool
    std::uint64_t replayed = 0;  ///< DTUs handed to the transport from the spool (marked)
    std::uint64_t dropped = 0;   ///< DTUs dropped: budget full (oldest first), no spool, or unreadable on disk
    std::uint64_t dropped_bytes = 0;
    std::uint64_t spilled = 0;      ///< DTUs written to disk segments
    std::uint64_t disk_errors = 0;  ///< failed segment writes (RAM then holds the DTUs)
    std::size_t pending = 0;        ///< DTUs waiting in the spool (RAM + disk)
    std::size_t memory_bytes = 0;
    std::size_t disk_bytes = 0;
    std::size_t disk_segments = 0;
};

Json to_json(const SpoolStats& stats);

/// The marker: returns `payload` (a JSON object's text) with
/// "privateInfo": {"replayed": true} set. Other privateInfo keys are kept;
/// a privateInfo that is not an object is kept under "value". Text that is
/// not a JSON object comes back unchanged.
std::string mark_replayed(std::string payload);
/// True when a Sample DTU carries the replay marker.
bool is_replayed(const Json& dtu);

class SampleSpool {
public:
    /// `work`: the shared work threads the spool's worker runs on (gateway
    /// mode), or null for a thread of its own.
    SampleSpool(SpoolOptions options, Transport& transport, Logger logger, core_detail::PollHost* work = nullptr);
    ~SampleSpool();  ///< stop()s
    SampleSpool(const SampleSpool&) = delete;
    SampleSpool& operator=(const SampleSpool&) = delete;

    /// Picks up segments of a previous run and starts the worker. The
    /// link state is read from the transport once; on_link() follows it.
    Result<void> start();
    /// Stops the worker. What is still spooled goes to disk (when a
    /// disk budget is set), else to the transport if the link is up, else it
    /// is dropped (counted, logged). Idempotent.
    void stop();

    /// The engine's DtuSink. Thread-safe; never blocks on the network or disk
    /// (only on a transport hand-over already under way).
    void publish(Message message);
    /// The link changed (Feature::on_link). Never blocks.
    void on_link(LinkState link);

    SpoolStats stats() const;
    /// True when nothing is spooled (RAM, disk, or being replayed).
    bool empty() const;

private:
    /// One turn of the worker (spill, replay; at most kStepsPerTurn steps,
    /// then it yields the shared thread); returns when it must look again.
    core_detail::PollHost::Time turn();
    std::size_t pending_locked() const;
    void enqueue_locked(Message message);
    void drop_memory_front_locked();
    bool disk_enabled() const { return options_.disk_bytes > 0 && !options_.disk_dir.empty(); }
    /// Worker: moves the oldest RAM DTUs into one segment file.
    void spill_one_segment(std::unique_lock<std::mutex>& lock);
    void enforce_disk_budget_locked();
    /// Worker: hands the next spooled DTU to the transport. False when
    /// there is nothing to replay right now.
    bool replay_one();
    bool load_next_segment(std::unique_lock<std::mutex>& lock);
    void finish_loaded_locked();
    void persist_on_stop();

    const SpoolOptions options_;
    Transport& transport_;
    const Logger logger_;
    const std::size_t segment_bytes_;
    core_detail::PollHost* const work_;

    // Held from taking a DTU (live or spooled) until the transport has it, so
    // hand-overs keep production order. Never taken by on_link().
    std::mutex order_mutex_;

    mutable std::mutex mutex_;  // the worker is started and woken under it
    bool link_up_ = false;
    bool stopping_ = false;
    bool started_ = false;
    bool stopped_ = false;
    std::deque<Message> memory_;  // newest spooled DTUs
    std::size_t memory_used_ = 0;
    std::deque<SegmentInfo> segments_;  // on disk, oldest first, not loaded
    std::deque<Message> loaded_;        // the oldest segment, being replayed
    SegmentInfo loaded_info_;
    bool has_loaded_ = false;
    std::size_t disk_used_ = 0;
    std::size_t spilling_ = 0;  // DTUs being written to a segment right now
    std::uint64_t next_seq_ = 1;
    std::chrono::steady_clock::time_point disk_retry_at_{};
    SpoolStats counters_;
    std::uint64_t drop_burst_ = 0;
    core_detail::SerialWork worker_;  // last: stopped before the rest goes
};

}  // namespace nclink::sampling_detail
