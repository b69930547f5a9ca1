#include "bridge/observation_buffer.hpp"

#include <algorithm>

namespace nclink::bridge {

ObservationBuffer::ObservationBuffer(std::size_t capacity) : slots_(std::max<std::size_t>(capacity, 1)) {}

std::uint64_t ObservationBuffer::append(ItemIndex item, Json value, std::int64_t time_ms) {
    Observation& slot = slots_[next_ % slots_.size()];
    if (size_ == slots_.size()) {
        // The oldest falls out: keep it as that item's value before the buffer.
        if (fallen_.size() <= slot.item) fallen_.resize(slot.item + 1);
        fallen_[slot.item] = std::move(slot);
    } else {
        ++size_;
    }
    slot.sequence = next_++;
    slot.time_ms = time_ms;
    slot.item = item;
    slot.value = std::move(value);
    if (latest_.size() <= item) latest_.resize(item + 1);
    latest_[item] = slot;
    return slot.sequence;
}

const Observation* ObservationBuffer::find(std::uint64_t sequence) const {
    if (sequence < first_sequence() || sequence >= next_) return nullptr;
    return &slots_[sequence % slots_.size()];
}

std::vector<std::optional<Observation>> ObservationBuffer::values_at(std::uint64_t at) const {
    std::vector<std::optional<Observation>> values = fallen_;
    values.resize(latest_.size());
    const std::uint64_t end = std::min(at, last_sequence());
    for (std::uint64_t s = first_sequence(); s <= end && s < next_; ++s) {
        const Observation& o = slots_[s % slots_.size()];
        values[o.item] = o;
    }
    return values;
}

ObservationBuffer::Range ObservationBuffer::range(std::uint64_t from, std::size_t count,
                                                  const std::function<bool(ItemIndex)>& wanted) const {
    Range out;
    out.next_sequence = next_;
    std::uint64_t s = std::max(from, first_sequence());
    for (; s < next_ && out.observations.size() < count; ++s) {
        const Observation& o = slots_[s % slots_.size()];
        if (!wanted || wanted(o.item)) out.observations.push_back(o);
    }
    if (out.observations.size() == count) out.next_sequence = s;
    return out;
}

}  // namespace nclink::bridge
