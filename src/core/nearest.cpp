#include "core/nearest.hpp"

#include <algorithm>
#include <cctype>

namespace nclink::core_detail {
namespace {

char fold(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

bool iequal(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return fold(x) == fold(y); });
}

bool iprefix(std::string_view prefix, std::string_view of) {
    return prefix.size() <= of.size() && iequal(prefix, of.substr(0, prefix.size()));
}

}  // namespace

std::size_t edit_distance(std::string_view a, std::string_view b) {
    // Optimal string alignment distance over three rows.
    const std::size_t n = a.size(), m = b.size();
    std::vector<std::size_t> before(m + 1), previous(m + 1), current(m + 1);
    for (std::size_t j = 0; j <= m; ++j) previous[j] = j;
    for (std::size_t i = 1; i <= n; ++i) {
        current[0] = i;
        for (std::size_t j = 1; j <= m; ++j) {
            const std::size_t cost = fold(a[i - 1]) == fold(b[j - 1]) ? 0 : 1;
            current[j] = std::min({previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost});
            if (i > 1 && j > 1 && fold(a[i - 1]) == fold(b[j - 2]) && fold(a[i - 2]) == fold(b[j - 1]))
                current[j] = std::min(current[j], before[j - 2] + 1);
        }
        before.swap(previous);
        previous.swap(current);
    }
    return previous[m];
}

std::optional<std::string> nearest_name(std::string_view name, const std::vector<std::string_view>& candidates) {
    if (name.empty()) return std::nullopt;
    for (const auto c : candidates)
        if (iequal(name, c)) return std::string(c);
    const std::size_t limit = std::clamp<std::size_t>(name.size() / 3, 1, 3);
    std::optional<std::string> best;
    std::size_t best_distance = limit + 1;
    for (const auto c : candidates) {
        const std::size_t d = edit_distance(name, c);
        if (d < best_distance) best_distance = d, best = std::string(c);
    }
    if (best) return best;
    // "SPINDLE" for "SPINDLE_SPEED", "temp" for "temperature": a prefix of
    // at least three characters names its completion when only one fits.
    if (name.size() >= 3) {
        std::vector<std::string_view> completions;
        for (const auto c : candidates)
            if (iprefix(name, c) || (c.size() >= 3 && iprefix(c, name))) completions.push_back(c);
        if (completions.size() == 1) return std::string(completions.front());
    }
    return std::nullopt;
}

}  // namespace nclink::core_detail
