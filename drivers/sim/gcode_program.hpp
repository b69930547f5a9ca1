// The simulated mill's part program: a tiny G-code reader (G0/G1/G2/G3/G4,
// X Y Z I J F S T, M3/M4/M5/M6/M30, N numbers, (comments)) and the built-in
// program it runs. Absolute coordinates (G90) in the XY plane (G17) only:
// enough for a plausible path, not a CNC interpreter.
#pragma once

#include <nclink/result.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::sim {

enum class Motion { none, rapid, linear, arc_cw, arc_ccw };

/// One block, with modal motion already resolved.
struct Block {
    int number = 0;  ///< N word (0 when absent)
    Motion motion = Motion::none;
    std::optional<double> x, y, z, i, j;
    std::optional<double> feed;      ///< F, mm/min
    std::optional<double> spindle;   ///< S, r/min
    std::optional<int> spindle_dir;  ///< M3 1, M4 -1, M5 0
    std::optional<int> tool;         ///< T
    bool tool_change = false;        ///< M6
    double dwell_s = 0;              ///< G4 P<seconds>
    bool end = false;                ///< M30 / M2

    bool moves() const noexcept { return motion != Motion::none && (x || y || z); }
};

struct Program {
    std::string name;  ///< from the O line, e.g. "O1000"
    std::vector<Block> blocks;
};

/// Parses program text. Unknown words are ignored; a malformed number is a
/// syntax error (412) naming the line.
Result<Program> parse_program(std::string_view text);

/// The mill's built-in program O1000: a rectangular pocket (two passes of
/// linear moves) with one tool, then a full circle with a second tool.
std::string_view builtin_program();

}  // namespace nclink::sim
