#include "gcode_program.hpp"

#include <cctype>
#include <cstdlib>
#include <string>

namespace nclink::sim {

namespace {

constexpr std::string_view program_text = R"(%
O1000 (NCLINK SIM - POCKET AND CIRCLE)
N10 G21 G90 G17 G54
N20 T1 M6
N30 S8000 M3
N40 G0 X0 Y0 Z50
N50 G0 X-60 Y-40 Z5
N60 G1 Z-2 F300
N70 G1 X60 F1200
N80 Y40
N90 X-60
N100 Y-40
N110 G0 Z5
N120 G0 X-40 Y-25
N130 G1 Z-4 F300
N140 G1 X40 F1000
N150 Y25
N160 X-40
N170 Y-25
N180 G0 Z50
N190 T2 M6
N200 S6000 M3
N210 G0 X50 Y0 Z5
N220 G1 Z-3 F250
N230 G2 X50 Y0 I-50 J0 F900
N240 G3 X50 Y0 I-50 J0
N250 G0 Z50
N260 M5
N270 G0 X0 Y0
N280 M30
%
)";

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

}  // namespace

std::string_view builtin_program() { return program_text; }

Result<Program> parse_program(std::string_view text) {
    Program program;
    Motion modal = Motion::none;
    std::size_t line_no = 0;
    while (!text.empty()) {
        ++line_no;
        const auto eol = text.find('\n');
        std::string_view line = text.substr(0, eol);
        text = eol == std::string_view::npos ? std::string_view() : text.substr(eol + 1);
        // Drop (comments) and ; comments.
        std::string clean;
        int depth = 0;
        for (char c : line) {
            if (c == ';' && depth == 0) break;
            if (c == '(') ++depth;
            else if (c == ')') depth = depth > 0 ? depth - 1 : 0;
            else if (depth == 0) clean.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
        }
        std::string_view body = trim(clean);
        if (body.empty() || body == "%") continue;
        if (body.front() == 'O') {
            program.name = std::string(trim(body));
            continue;
        }
        Block block;
        std::optional<Motion> motion_word;
        std::size_t pos = 0;
        while (pos < body.size()) {
            const char letter = body[pos];
            if (std::isspace(static_cast<unsigned char>(letter))) {
                ++pos;
                continue;
            }
            if (!std::isalpha(static_cast<unsigned char>(letter)))
                return make_error(ErrorCode::syntax_error, "line " + std::to_string(line_no) + ": unexpected '" + letter + "'");
            std::size_t end = pos + 1;
            while (end < body.size() && (std::isdigit(static_cast<unsigned char>(body[end])) || body[end] == '.' ||
                                         body[end] == '-' || body[end] == '+'))
                ++end;
            const std::string number(body.substr(pos + 1, end - pos - 1));
            char* stop = nullptr;
            const double v = std::strtod(number.c_str(), &stop);
            if (number.empty() || stop != number.c_str() + number.size())
                return make_error(ErrorCode::syntax_error,
                                  "line " + std::to_string(line_no) + ": bad number after '" + letter + "'");
            switch (letter) {
                case 'N': block.number = static_cast<int>(v); break;
                case 'G': {
                    const int g = static_cast<int>(v);
                    if (g == 0) motion_word = Motion::rapid;
                    else if (g == 1) motion_word = Motion::linear;
                    else if (g == 2) motion_word = Motion::arc_cw;
                    else if (g == 3) motion_word = Motion::arc_ccw;
                    else if (g == 4) block.dwell_s = -1;  // P gives the time
                    break;
                }
                case 'X': block.x = v; break;
                case 'Y': block.y = v; break;
                case 'Z': block.z = v; break;
                case 'I': block.i = v; break;
                case 'J': block.j = v; break;
                case 'F': block.feed = v; break;
                case 'S': block.spindle = v; break;
                case 'T': block.tool = static_cast<int>(v); break;
                case 'P':
                    if (block.dwell_s < 0) block.dwell_s = v;
                    break;
                case 'M': {
                    const int m = static_cast<int>(v);
                    if (m == 3) block.spindle_dir = 1;
                    else if (m == 4) block.spindle_dir = -1;
                    else if (m == 5) block.spindle_dir = 0;
                    else if (m == 6) block.tool_change = true;
                    else if (m == 2 || m == 30) block.end = true;
                    break;
                }
                default: break;  // other words do not affect the simulation
            }
            pos = end;
        }
        if (block.dwell_s < 0) block.dwell_s = 0;
        if (motion_word) modal = *motion_word;
        if (block.x || block.y || block.z) block.motion = modal;
        program.blocks.push_back(block);
    }
    if (program.blocks.empty()) return make_error(ErrorCode::syntax_error, "program has no blocks");
    return program;
}

}  // namespace nclink::sim
