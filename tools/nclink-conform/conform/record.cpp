#include "conform/record.hpp"

#include <fmt/format.h>

namespace nclink::conform {

std::string_view to_string(Outcome outcome) noexcept {
    switch (outcome) {
        case Outcome::pass: return "pass";
        case Outcome::fail: return "fail";
        case Outcome::not_supported: return "not supported";
        case Outcome::skipped: return "skipped";
    }
    return "fail";
}

void ItemResult::fail(std::string note, std::string topic, std::string dtu) {
    outcome = Outcome::fail;
    evidence.push_back(Evidence{std::move(note), std::move(topic), clip(std::move(dtu))});
}

void ItemResult::not_supported(std::string why, std::string topic, std::string dtu) {
    if (outcome == Outcome::fail) return;
    outcome = Outcome::not_supported;
    if (summary.empty()) summary = why;
    if (!topic.empty() || !dtu.empty()) evidence.push_back(Evidence{std::move(why), std::move(topic), clip(std::move(dtu))});
}

void ItemResult::skip(std::string why) {
    if (outcome != Outcome::pass) return;
    outcome = Outcome::skipped;
    summary = std::move(why);
}

std::size_t ItemResult::failures() const noexcept { return outcome == Outcome::fail ? evidence.size() : 0; }

Verdict TestRecord::verdict() const {
    for (const auto& item : items) {
        if (item.outcome == Outcome::fail) return Verdict::fail;
        if (item.required && item.outcome == Outcome::not_supported) return Verdict::fail;
    }
    return Verdict::pass;
}

std::size_t TestRecord::count(Outcome outcome) const {
    std::size_t n = 0;
    for (const auto& item : items) n += item.outcome == outcome ? 1 : 0;
    return n;
}

const ItemResult* TestRecord::find(std::string_view key) const {
    for (const auto& item : items)
        if (item.key == key) return &item;
    return nullptr;
}

std::string clip(std::string text, std::size_t max) {
    if (text.size() <= max) return text;
    const std::size_t cut = text.size() - max;
    text.resize(max);
    // Do not leave half a UTF-8 sequence at the end.
    while (!text.empty() && (static_cast<unsigned char>(text.back()) & 0xC0) == 0x80) text.pop_back();
    if (!text.empty() && (static_cast<unsigned char>(text.back()) & 0x80)) text.pop_back();
    return text + fmt::format(" ... ({} more bytes)", cut);
}

}  // namespace nclink::conform
