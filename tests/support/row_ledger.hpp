// Counts the rows of Sample DTUs an application received, to tell lost and
// repeated ones apart: a channel's rows are `sampleInterval` apart, so every
// row has its own time (beginTime + i * interval); a repeated time is a
// duplicate, a hole between two received rows is a loss. Thread-safe.
#pragma once

#include <nclink/dtu.hpp>

#include <cstdint>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace nclink::test {

class RowLedger {
public:
    /// `intervals`: each channel's sampleInterval in ms (channels not named are ignored).
    explicit RowLedger(std::map<std::string, std::int64_t> intervals) : intervals_(std::move(intervals)) {}

    void add(const SampleDtu& dtu) {
        const auto interval = intervals_.find(dtu.id);
        if (interval == intervals_.end() || dtu.data.empty() || !dtu.data[0].is_array()) return;
        const std::size_t rows = dtu.data[0].size();
        std::lock_guard<std::mutex> lock(mutex_);
        auto& times = rows_[dtu.id];
        for (std::size_t i = 0; i < rows; ++i) {
            const std::int64_t t = dtu.begin_time + static_cast<std::int64_t>(i) * interval->second;
            if (!times.insert(t).second) ++duplicates_;
        }
        ++dtus_;
    }
    /// Forgets every row (and frees the memory).
    void clear() {
        std::lock_guard<std::mutex> lock(mutex_);
        std::map<std::string, std::set<std::int64_t>>().swap(rows_);
    }
    std::uint64_t rows(const std::string& channel) const {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = rows_.find(channel);
        return it == rows_.end() ? 0 : it->second.size();
    }
    std::uint64_t rows() const {
        std::lock_guard<std::mutex> lock(mutex_);
        std::uint64_t n = 0;
        for (const auto& entry : rows_) n += entry.second.size();
        return n;
    }
    std::uint64_t dtus() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return dtus_;
    }
    /// Rows handed on more than once.
    std::uint64_t duplicates() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return duplicates_;
    }
    /// Rows missing between the first and the last received of each channel.
    std::uint64_t holes() const {
        std::lock_guard<std::mutex> lock(mutex_);
        std::uint64_t n = 0;
        for (const auto& [channel, times] : rows_) {
            if (times.empty()) continue;
            const std::int64_t step = intervals_.at(channel);
            const std::int64_t span = (*times.rbegin() - *times.begin()) / step + 1;
            n += static_cast<std::uint64_t>(span) - times.size();
        }
        return n;
    }
    /// The first and last row time received on a channel ({0, 0}: none).
    std::pair<std::int64_t, std::int64_t> span(const std::string& channel) const {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = rows_.find(channel);
        if (it == rows_.end() || it->second.empty()) return {0, 0};
        return {*it->second.begin(), *it->second.rbegin()};
    }
    /// The holes of one channel as [from, to] time ranges (for messages).
    std::vector<std::pair<std::int64_t, std::int64_t>> gaps(const std::string& channel) const {
        std::lock_guard<std::mutex> lock(mutex_);
        std::vector<std::pair<std::int64_t, std::int64_t>> out;
        const auto it = rows_.find(channel);
        if (it == rows_.end()) return out;
        const std::int64_t step = intervals_.at(channel);
        std::int64_t previous = 0;
        bool first = true;
        for (std::int64_t t : it->second) {
            if (!first && t - previous > step) out.emplace_back(previous + step, t - step);
            previous = t;
            first = false;
        }
        return out;
    }

private:
    const std::map<std::string, std::int64_t> intervals_;
    mutable std::mutex mutex_;
    std::map<std::string, std::set<std::int64_t>> rows_;
    std::uint64_t dtus_ = 0;
    std::uint64_t duplicates_ = 0;
};

}  // namespace nclink::test
