// Progress of long work in `nclink` (method calls, model transfers to many
// devices): a bar redrawn in place on a terminal, plain lines when the output
// is a file or pipe (so logs stay readable), nothing with --no-progress.
// The bar's text comes from render_bar(), pure so it is unit-tested.
#pragma once

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>

namespace nclink::cli {

enum class ProgressMode { bar, lines, off };

/// bar on a terminal, lines otherwise; off when `no_progress` (or `json`:
/// machine-readable output carries its own progress records).
ProgressMode progress_mode(bool no_progress, bool json, std::FILE* out);

/// The columns of the terminal on `out` (80 when not a terminal or unknown).
int terminal_columns(std::FILE* out);

/// One line, exactly `width` columns (ASCII): "LABEL [#####.....]  42.0% DETAIL",
/// the bar taking what the label and detail leave. `fraction` outside 0..1 is
/// clamped; nullopt (unknown) draws a moving marker from `tick`.
std::string render_bar(const std::string& label, std::optional<double> fraction, const std::string& detail, int width,
                       unsigned tick = 0);

/// Not thread-safe: one thread draws (or guard it).
class Progress {
public:
    Progress(ProgressMode mode, std::FILE* out, std::string label);
    ~Progress();  ///< finish()
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Bar: redraws (at most every 50 ms unless the detail changed or it is
    /// done). Lines: a line when the detail changes or the percentage passes
    /// a multiple of 10.
    void update(std::optional<double> fraction, const std::string& detail);
    /// Prints a whole line above the bar (a result, a warning) without
    /// breaking it.
    void note(const std::string& line);
    /// Ends the bar's line. Idempotent.
    void finish();

    ProgressMode mode() const { return mode_; }

private:
    void draw();

    ProgressMode mode_;
    std::FILE* out_;
    std::string label_;
    std::optional<double> fraction_;
    std::string detail_;
    bool drawn_ = false;
    unsigned tick_ = 0;
    int last_decile_ = -1;
    std::string last_line_detail_;
    std::chrono::steady_clock::time_point last_draw_{};
};

}  // namespace nclink::cli
