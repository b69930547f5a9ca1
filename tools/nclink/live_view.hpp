// The full-screen view of `nclink top` (`nclink watch --full-screen`): one row
// per sampled point with its latest value, refreshed in place. This is the
// screen's content only -- pure, so it is unit-tested; terminal.hpp draws it.
#pragma once

#include <nclink/dtu.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace nclink::cli {

/// Terminal columns `text` (UTF-8) takes: 2 for East Asian wide characters
/// (CJK item names and values), 1 for others.
std::size_t display_width(const std::string& text);

class LiveView {
public:
    /// `channels`: channel id -> point ids, from the device's model (points
    /// of channels it does not name are p1, p2, ...).
    LiveView(std::string device, std::string broker, std::map<std::string, std::vector<std::string>> channels);

    /// A Sample DTU arrived at `now_ms` (wall ms): each point's latest non-null value.
    void apply(const SampleDtu& dtu, std::int64_t now_ms);
    /// Moves the first shown row by `rows` (clamped when rendering).
    void scroll(int rows) { first_row_ += rows; }
    void scroll_home() { first_row_ = 0; }

    /// Exactly `height` lines of at most `width` characters: a title, a
    /// column header, the rows from the scroll position, and a key help line.
    std::vector<std::string> render(int width, int height, std::int64_t now_ms);

    std::uint64_t dtus() const { return dtus_; }
    std::size_t rows() const { return rows_.size(); }

private:
    struct Row {
        std::string channel;
        std::string point;
        std::string value = "-";
        std::int64_t updated_ms = 0;  ///< 0 = no value yet
        std::uint64_t updates = 0;
    };
    Row& row(const std::string& channel, std::size_t index);

    std::string device_;
    std::string broker_;
    std::map<std::string, std::vector<std::string>> channels_;
    std::map<std::pair<std::string, std::size_t>, Row> rows_;  ///< (channel, point index): the screen's order
    std::uint64_t dtus_ = 0;
    int first_row_ = 0;
};

}  // namespace nclink::cli
