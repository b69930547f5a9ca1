#include "live_view.hpp"

#include "cli_device.hpp"

#include <algorithm>
#include <cstdio>

namespace nclink::cli {
namespace {

std::string latest_value(const Json& point) {
    if (!point.is_array()) return point.dump(-1, ' ', false, Json::error_handler_t::replace);
    for (auto it = point.rbegin(); it != point.rend(); ++it)
        if (!it->is_null()) return it->dump(-1, ' ', false, Json::error_handler_t::replace);
    return {};
}

// One UTF-8 sequence at text[i]: its length and code point (U+FFFD when broken).
std::pair<std::size_t, char32_t> decode(const std::string& text, std::size_t i) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t len = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    if (len == 0 || i + len > text.size()) return {1, 0xFFFD};
    char32_t code = len == 1 ? c : len == 2 ? (c & 0x1F) : len == 3 ? (c & 0x0F) : (c & 0x07);
    for (std::size_t k = 1; k < len; ++k) {
        const auto next = static_cast<unsigned char>(text[i + k]);
        if ((next & 0xC0) != 0x80) return {1, 0xFFFD};
        code = (code << 6) | (next & 0x3F);
    }
    return {len, code};
}

std::size_t width_of(char32_t c) {
    const bool wide = (c >= 0x1100 && c <= 0x115F) || (c >= 0x2E80 && c <= 0xA4CF) || (c >= 0xAC00 && c <= 0xD7A3) ||
                      (c >= 0xF900 && c <= 0xFAFF) || (c >= 0xFE30 && c <= 0xFE4F) || (c >= 0xFF00 && c <= 0xFF60) ||
                      (c >= 0xFFE0 && c <= 0xFFE6) || (c >= 0x20000 && c <= 0x3FFFD);
    return wide ? 2 : 1;
}

// Cut to `width` columns, whole characters only; control characters become
// spaces so nothing a device sends can move the cursor.
std::string fit(const std::string& text, std::size_t width) {
    std::string out;
    std::size_t columns = 0;
    for (std::size_t i = 0; i < text.size();) {
        const auto [len, code] = decode(text, i);
        const std::size_t w = width_of(code);
        if (columns + w > width) break;
        if (code < 0x20 || code == 0x7f || (code >= 0x80 && code < 0xA0)) out += ' ';
        else if (code == 0xFFFD && len == 1 && static_cast<unsigned char>(text[i]) >= 0x80) out += '?';
        else out.append(text, i, len);
        i += len;
        columns += w;
    }
    return out;
}

std::string pad(const std::string& text, std::size_t width) {
    std::string out = fit(text, width);
    const std::size_t columns = display_width(out);
    out.append(width > columns ? width - columns : 0, ' ');
    return out;
}

}  // namespace

std::size_t display_width(const std::string& text) {
    std::size_t columns = 0;
    for (std::size_t i = 0; i < text.size();) {
        const auto [len, code] = decode(text, i);
        columns += width_of(code);
        i += len;
    }
    return columns;
}

namespace {

std::string age(std::int64_t now_ms, std::int64_t then_ms) {
    if (then_ms == 0) return "-";
    const double seconds = static_cast<double>(std::max<std::int64_t>(now_ms - then_ms, 0)) / 1000.0;
    char text[32];
    if (seconds < 60) std::snprintf(text, sizeof text, "%.1fs", seconds);
    else if (seconds < 3600) std::snprintf(text, sizeof text, "%.0fm", seconds / 60);
    else std::snprintf(text, sizeof text, "%.0fh", seconds / 3600);
    return text;
}

}  // namespace

LiveView::LiveView(std::string device, std::string broker, std::map<std::string, std::vector<std::string>> channels)
    : device_(std::move(device)), broker_(std::move(broker)), channels_(std::move(channels)) {
    for (const auto& [channel, points] : channels_)
        for (std::size_t i = 0; i < points.size(); ++i) row(channel, i);
}

LiveView::Row& LiveView::row(const std::string& channel, std::size_t index) {
    auto [it, added] = rows_.try_emplace({channel, index});
    if (added) {
        it->second.channel = channel;
        const auto names = channels_.find(channel);
        it->second.point =
            names != channels_.end() && index < names->second.size() ? names->second[index] : "p" + std::to_string(index + 1);
    }
    return it->second;
}

void LiveView::apply(const SampleDtu& dtu, std::int64_t now_ms) {
    ++dtus_;
    for (std::size_t i = 0; i < dtu.data.size(); ++i) {
        const std::string value = latest_value(dtu.data[i]);
        Row& r = row(dtu.id, i);
        if (value.empty()) continue;  // nothing new for this point in the DTU
        r.value = value;
        r.updated_ms = now_ms;
        ++r.updates;
    }
}

std::vector<std::string> LiveView::render(int width, int height, std::int64_t now_ms) {
    const std::size_t w = static_cast<std::size_t>(std::max(width, 1));
    const std::size_t h = static_cast<std::size_t>(std::max(height, 1));
    std::vector<std::string> lines;
    lines.push_back(
        pad("nclink top  " + device_ + " on " + broker_ + "  " + format_time_ms(now_ms) + "  DTUs " + std::to_string(dtus_), w));
    // Columns: channel and point shrink on narrow screens; the value takes the rest.
    const std::size_t age_w = 6;
    std::size_t channel_w = 14, point_w = 22;
    if (w < 60) channel_w = 10, point_w = 14;
    const std::size_t fixed = channel_w + 1 + point_w + 1 + age_w + 1;
    const std::size_t value_w = w > fixed ? w - fixed : 1;
    lines.push_back(
        pad(pad("CHANNEL", channel_w) + " " + pad("ITEM", point_w) + " " + pad("VALUE", value_w) + " " + pad("AGE", age_w), w));
    const std::size_t body = h > 3 ? h - 3 : 0;  // title, header, help
    const int max_first = static_cast<int>(rows_.size() > body ? rows_.size() - body : 0);
    first_row_ = std::clamp(first_row_, 0, max_first);
    for (std::size_t i = 0; i < body; ++i) {
        const std::size_t r = static_cast<std::size_t>(first_row_) + i;
        if (r >= rows_.size()) {
            lines.push_back(std::string(w, ' '));
            continue;
        }
        const Row& row = std::next(rows_.begin(), static_cast<std::ptrdiff_t>(r))->second;
        lines.push_back(pad(pad(row.channel, channel_w) + " " + pad(row.point, point_w) + " " + pad(row.value, value_w) + " " +
                                pad(age(now_ms, row.updated_ms), age_w),
                            w));
    }
    std::string help = "q quit";
    if (max_first > 0)
        help += "  up/down scroll  rows " + std::to_string(first_row_ + 1) + "-" +
                std::to_string(std::min<std::size_t>(rows_.size(), static_cast<std::size_t>(first_row_) + body)) + " of " +
                std::to_string(rows_.size());
    if (rows_.empty()) help += "  (waiting for samples)";
    if (h >= 3) lines.push_back(pad(help, w));
    lines.resize(h, std::string(w, ' '));
    return lines;
}

}  // namespace nclink::cli
