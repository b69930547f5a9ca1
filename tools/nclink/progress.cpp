#include "progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace nclink::cli {

ProgressMode progress_mode(bool no_progress, bool json, std::FILE* out) {
    if (no_progress || json) return ProgressMode::off;
    return ::isatty(::fileno(out)) != 0 ? ProgressMode::bar : ProgressMode::lines;
}

int terminal_columns(std::FILE* out) {
    winsize size{};
    if (::ioctl(::fileno(out), TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
    return 80;
}

namespace {

std::string clip(const std::string& text, std::size_t width) {
    if (text.size() <= width) return text;
    if (width == 0) return {};
    return text.substr(0, width - 1) + "~";
}

}  // namespace

std::string render_bar(const std::string& label, std::optional<double> fraction, const std::string& detail, int width,
                       unsigned tick) {
    const std::size_t total = static_cast<std::size_t>(std::max(width, 20));
    char percent[16];
    if (fraction) {
        const double f = std::clamp(*fraction, 0.0, 1.0);
        std::snprintf(percent, sizeof percent, "%5.1f%%", f * 100.0);
    } else {
        std::snprintf(percent, sizeof percent, "%6s", "");
    }
    // The bar takes 40 cells, shrinking to 10 on narrow terminals; then the
    // detail and the label give way (clipped).
    std::size_t bar = 40;
    std::string head = label, tail = detail;
    const auto need = [&] { return (head.empty() ? 0 : head.size() + 1) + 2 + bar + 1 + 6 + (tail.empty() ? 0 : 1 + tail.size()); };
    while (need() > total && bar > 10) --bar;
    if (need() > total) {
        const std::size_t over = need() - total;
        tail = over >= tail.size() ? std::string() : clip(tail, tail.size() - over);
    }
    if (need() > total) {
        const std::size_t over = need() - total;
        head = over >= head.size() ? std::string() : clip(head, head.size() - over);
    }

    std::string cells(bar, '.');
    if (fraction) {
        const auto filled = static_cast<std::size_t>(std::lround(std::clamp(*fraction, 0.0, 1.0) * static_cast<double>(bar)));
        std::fill(cells.begin(), cells.begin() + static_cast<std::ptrdiff_t>(std::min(filled, bar)), '#');
    } else {
        const std::size_t at = tick % (2 * bar - 2 > 0 ? 2 * bar - 2 : 1);  // bounces to and fro
        const std::size_t pos = at < bar ? at : 2 * bar - 2 - at;
        cells[std::min(pos, bar - 1)] = '#';
    }
    std::string line = head + (head.empty() ? "" : " ") + "[" + cells + "] " + percent;
    if (!tail.empty()) line += " " + tail;
    if (line.size() < total) line.append(total - line.size(), ' ');
    if (line.size() > total) line.resize(total);
    return line;
}

Progress::Progress(ProgressMode mode, std::FILE* out, std::string label) : mode_(mode), out_(out), label_(std::move(label)) {}

Progress::~Progress() { finish(); }

void Progress::update(std::optional<double> fraction, const std::string& detail) {
    const bool changed = detail != detail_;
    fraction_ = fraction;
    detail_ = detail;
    if (mode_ == ProgressMode::off) return;
    if (mode_ == ProgressMode::lines) {
        const int decile = fraction ? static_cast<int>(std::floor(std::clamp(*fraction, 0.0, 1.0) * 10.0)) : -1;
        if (detail == last_line_detail_ && decile == last_decile_) return;
        last_line_detail_ = detail;
        last_decile_ = decile;
        if (fraction)
            std::fprintf(out_, "%s %.0f%% %s\n", label_.c_str(), std::clamp(*fraction, 0.0, 1.0) * 100.0, detail.c_str());
        else std::fprintf(out_, "%s %s\n", label_.c_str(), detail.c_str());
        std::fflush(out_);
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    const bool done = fraction && *fraction >= 1.0;
    if (!changed && !done && drawn_ && now - last_draw_ < std::chrono::milliseconds(50)) return;
    last_draw_ = now;
    ++tick_;
    draw();
}

void Progress::draw() {
    // \r and a full-width line: the previous drawing is overwritten, and the
    // width follows the terminal when it is resized.
    const int width = terminal_columns(out_) - 1;  // the last column would wrap on some terminals
    std::fprintf(out_, "\r%s", render_bar(label_, fraction_, detail_, width, tick_).c_str());
    std::fflush(out_);
    drawn_ = true;
}

void Progress::note(const std::string& line) {
    if (mode_ == ProgressMode::bar && drawn_) {
        std::fprintf(out_, "\r\x1b[K%s\n", line.c_str());
        draw();
    } else {
        std::fprintf(out_, "%s\n", line.c_str());
        std::fflush(out_);
    }
}

void Progress::finish() {
    if (mode_ == ProgressMode::bar && drawn_) {
        std::fprintf(out_, "\n");
        std::fflush(out_);
    }
    drawn_ = false;
}

}  // namespace nclink::cli
